#include "input/capture_sequence.h"

#include <chrono>
#include <cmath>
#include <opencv2/videoio.hpp>
#include <thread>

#include "memloop/errors.h"

namespace memloop {
namespace {

using Clock = std::chrono::steady_clock;

class VideoSequence : public ImageSequence {
 public:
  // FFmpeg only: it reads every common file format, and a file it cannot read gets one clear
  // line here instead of GStreamer's warnings and critical messages.
  VideoSequence(const std::string& path, double rate_hz)
      : capture_(path, cv::CAP_FFMPEG), period_ms_(rate_hz > 0 ? 1000.0 / rate_hz : 0) {
    if (!capture_.isOpened()) {
      throw InputError(path,
                       "cannot be opened as a video (not an image folder, nor a video "
                       "file FFmpeg can decode)");
    }
    fps_ = capture_.get(cv::CAP_PROP_FPS);
    const int frames = static_cast<int>(capture_.get(cv::CAP_PROP_FRAME_COUNT));
    if (frames > 0) {
      frame_count_ = period_ms_ > 0 && fps_ > 0
                         ? static_cast<int>(std::ceil(frames * 1000.0 / fps_ / period_ms_))
                         : frames;
    }
  }

  bool Next(Frame* frame) override {
    cv::Mat image;
    double time_ms = 0;
    while (true) {
      if (!capture_.read(image) || image.empty()) return false;
      ++read_;
      // The frame's time: its timestamp, or its number over the frame rate when there is none.
      time_ms = fps_ > 0 ? (read_ - 1) * 1000.0 / fps_ : capture_.get(cv::CAP_PROP_POS_MSEC);
      if (period_ms_ <= 0 || time_ms + 1e-6 >= due_ms_) break;
    }
    if (period_ms_ > 0) due_ms_ += period_ms_;
    frame->index = next_++;
    frame->name = "frame " + std::to_string(read_);
    frame->timestamp = time_ms / 1000;
    frame->image = image;
    frame->error.clear();
    frame->dropped = 0;
    return true;
  }
  int size() const override { return frame_count_; }

 private:
  cv::VideoCapture capture_;
  double period_ms_;
  double fps_ = 0;
  double due_ms_ = 0;
  int frame_count_ = -1;
  int read_ = 0;  // frames decoded
  ImageIndex next_ = 0;
};

// A live camera. With a rate, one frame per period (the newest: older buffered ones are
// discarded); without, each frame as the caller asks, and frames the camera delivered meanwhile
// are counted as dropped.
class CameraSequence : public ImageSequence {
 public:
  CameraSequence(int device, double rate_hz)
      : capture_(device),
        period_(rate_hz > 0 ? std::chrono::duration<double>(1.0 / rate_hz)
                            : std::chrono::duration<double>(0)) {
    if (!capture_.isOpened()) {
      throw InputError("camera " + std::to_string(device), "cannot be opened");
    }
    const double fps = capture_.get(cv::CAP_PROP_FPS);
    frame_period_ms_ = fps > 0 ? 1000.0 / fps : 0;
  }

  bool Next(Frame* frame) override {
    if (period_.count() > 0) {
      if (next_ > 0) std::this_thread::sleep_until(due_);
      due_ = std::max(due_ + std::chrono::duration_cast<Clock::duration>(period_), Clock::now());
    }
    const Clock::time_point asked = Clock::now();
    cv::Mat image;
    if (!capture_.read(image) || image.empty()) return false;
    frame->dropped = 0;
    if (next_ > 0 && period_.count() == 0 && frame_period_ms_ > 0) {
      // Frames the camera made since the previous read, beyond the one read now.
      const double gap_ms =
          std::chrono::duration<double, std::milli>(asked - previous_read_).count();
      frame->dropped = std::max(0, static_cast<int>(gap_ms / frame_period_ms_) - 1);
    }
    previous_read_ = Clock::now();
    frame->index = next_;
    frame->name = "frame " + std::to_string(++next_);
    // The computer's clock (seconds since 1970), as other sensors on the robot are stamped.
    frame->timestamp =
        std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
    frame->image = image;
    frame->error.clear();
    return true;
  }
  int size() const override { return -1; }

 private:
  cv::VideoCapture capture_;
  std::chrono::duration<double> period_;
  double frame_period_ms_ = 0;
  Clock::time_point due_ = Clock::now();
  Clock::time_point previous_read_;
  ImageIndex next_ = 0;
};

}  // namespace

std::unique_ptr<ImageSequence> OpenVideo(const std::string& path, double rate_hz) {
  return std::make_unique<VideoSequence>(path, rate_hz);
}

std::unique_ptr<ImageSequence> ImageSequence::OpenCamera(int device,
                                                         const SequenceOptions& options) {
  CheckSequenceOptions(options);
  return std::make_unique<CameraSequence>(device, options.rate_hz);
}

}  // namespace memloop
