// A detector fed by a stream that does not wait for it (a camera driver, a ROS topic): images are
// handed over from any thread and processed on a thread of its own, either every one in order
// (bag replay, tests) or, when they come faster than it goes, the newest only, the others dropped
// and counted (a robot wants its latest view matched, not a growing backlog). The ROS node is a
// thin layer over this class; so would be a ROS 2 node.
#pragma once

#include <chrono>
#include <condition_variable>
#include <deque>
#include <functional>
#include <future>
#include <memory>
#include <mutex>
#include <opencv2/core.hpp>
#include <string>
#include <thread>
#include <vector>

#include "memloop/detector.h"

namespace memloop {

enum class StreamPolicy {
  kLatest,  // when an image waits and a newer one comes, the waiting one is dropped
  kQueue,   // every image, in order: the stream waits in memory
};

// One processed image, as the result callback gets it.
struct LiveResult {
  Result result;
  ImageInfo image;  // as handed over (index and name filled in)
  // The matched image (result.loop_closure_images.front()): its time stamp and session, as the
  // map recorded them (kNoTimestamp, -1 when unknown).
  double match_timestamp = kNoTimestamp;
  int match_session = -1;
  std::chrono::steady_clock::time_point arrival;  // when Push() took the image
};

// What the stream has done so far (diagnostics).
struct LiveStatus {
  long long received = 0;   // images handed over
  long long processed = 0;  // images the detector processed
  long long dropped = 0;    // images a newer one replaced before they were processed (kLatest)
  long long refused = 0;    // images the detector refused (empty, unsupported depth)
  long long loop_closures = 0;
  long long waiting = 0;  // images handed over, not yet processed
  bool paused = false;
  std::string failure;  // why processing stopped ("" while it goes on)
  // Of the last processed images (up to 100): the median and the longest iteration, and the
  // median and longest time from an image's arrival to its result.
  double median_iteration_ms = 0, max_iteration_ms = 0;
  double median_latency_ms = 0, max_latency_ms = 0;
  Result last;  // the last processed image's result (memory sizes)
};

class LiveDetector {
 public:
  // Called on the processing thread after each image, in order; it may publish the result. An
  // exception it throws stops processing as a detector failure would.
  using ResultCallback = std::function<void(const LiveResult&)>;
  // Called on the processing thread when an image is refused (InputError) or processing stops
  // on a failure (`fatal`): the message names the image or the map.
  using ErrorCallback = std::function<void(const std::string& message, bool fatal)>;

  // Opens the map as Detector does (same errors, thrown here) and starts the processing thread.
  // Images are numbered after the map's last image (0 for a new map), in the order they are
  // handed over, dropped ones included: an index names an image of the stream.
  LiveDetector(const Options& options, const std::string& map_path, MapMode mode,
               StreamPolicy policy, ResultCallback on_result, ErrorCallback on_error = {});
  // Stop().
  ~LiveDetector();
  LiveDetector(const LiveDetector&) = delete;
  LiveDetector& operator=(const LiveDetector&) = delete;

  // Hands an 8-bit gray or BGR image over (copied by reference: the caller must not write to
  // it afterwards); never blocks on the detector. `info.index` is ignored (see the constructor).
  void Push(const cv::Mat& image, ImageInfo info);
  // The same with the image's depth map, registered to it (Detector::Process's depth: 16-bit
  // millimetres or 32-bit float metres); one of another size or type refuses the image.
  void Push(const cv::Mat& image, const cv::Mat& depth, ImageInfo info);
  // An image of the stream that could not be read (an unsupported encoding): it keeps its index,
  // as a frame the CLI skips does, and is counted as refused.
  void Skip();
  // Writes a checkpoint of everything processed so far and waits until it is committed: the map
  // then resumes from here (Detector::Flush). Images handed over before the call are processed
  // first (kQueue) or the waiting one (kLatest). Throws Error when processing has stopped.
  void Save();
  // While paused, images handed over are dropped (counted): a robot carried, or charging.
  void SetPaused(bool paused);
  LiveStatus Status() const;
  // Finishes the image being processed, drops those still waiting (counted), and closes the map
  // (complete: it resumes from its last image) and releases it. Idempotent; the destructor
  // calls it.
  void Stop();
  // The image index the next image handed over gets.
  ImageIndex next_index() const;

 private:
  struct Pending {
    cv::Mat image;
    cv::Mat depth;  // empty: none
    ImageInfo info;
    std::chrono::steady_clock::time_point arrival;
  };
  struct ImageRecord {
    double timestamp = kNoTimestamp;
    int session = -1;
  };
  void Run();
  void ProcessOne(Pending& pending);
  void RecordTimes(double iteration_ms, double latency_ms);

  std::unique_ptr<Detector> detector_;
  const StreamPolicy policy_;
  ResultCallback on_result_;
  ErrorCallback on_error_;
  std::vector<ImageRecord> images_;  // by image index; the processing thread's only

  mutable std::mutex mutex_;
  std::condition_variable wake_;
  std::deque<Pending> waiting_;
  struct SaveRequest {
    ImageIndex after;  // once the images before this index are processed or dropped
    std::shared_ptr<std::promise<void>> done;
  };
  void RunSave(SaveRequest& request);
  std::deque<SaveRequest> saves_;
  LiveStatus status_;
  std::deque<double> iteration_ms_, latency_ms_;
  ImageIndex next_index_ = 0;
  bool stopping_ = false;
  bool stopped_ = false;
  bool closed_ = false;  // the map closed (the processing thread's, then Save()'s once stopped)
  std::thread thread_;
};

}  // namespace memloop
