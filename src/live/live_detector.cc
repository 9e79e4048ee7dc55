#include "memloop/live_detector.h"

#include <algorithm>
#include <future>

#include "memloop/errors.h"
#include "memloop/map_info.h"
#include "util/thread_name.h"

namespace memloop {
namespace {

constexpr size_t kTimesKept = 100;  // the window of the status' medians

double Median(std::deque<double> values) {
  if (values.empty()) return 0;
  auto middle = values.begin() + static_cast<long>(values.size() / 2);
  std::nth_element(values.begin(), middle, values.end());
  return *middle;
}

double Milliseconds(std::chrono::steady_clock::duration duration) {
  return std::chrono::duration<double, std::milli>(duration).count();
}

}  // namespace

LiveDetector::LiveDetector(const Options& options, const std::string& map_path, MapMode mode,
                           StreamPolicy policy, ResultCallback on_result, ErrorCallback on_error)
    : policy_(policy), on_result_(std::move(on_result)), on_error_(std::move(on_error)) {
  // What the map records of its images, for the matched image's time stamp and session; read
  // before the detector holds the map open to write.
  if (mode != MapMode::kNew || options.memory.localization) {
    for (const MapImage& image : ReadMapImages(map_path)) {
      if (image.index < 0) continue;
      if (images_.size() <= static_cast<size_t>(image.index)) images_.resize(image.index + 1);
      images_[image.index] = {image.timestamp, image.session};
    }
  }
  detector_ = std::make_unique<Detector>(options, map_path, mode);
  next_index_ = detector_->last_image() == kNoImage ? detector_->session_first_image()
                                                    : detector_->last_image() + 1;
  thread_ = std::thread([this] { Run(); });
}

LiveDetector::~LiveDetector() { Stop(); }

ImageIndex LiveDetector::next_index() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return next_index_;
}

void LiveDetector::Push(const cv::Mat& image, ImageInfo info) {
  Push(image, cv::Mat(), std::move(info));
}

void LiveDetector::Push(const cv::Mat& image, const cv::Mat& depth, ImageInfo info) {
  const auto arrival = std::chrono::steady_clock::now();
  {
    std::lock_guard<std::mutex> lock(mutex_);
    ++status_.received;
    info.index = next_index_++;
    if (stopping_ || stopped_ || status_.paused) {  // not processed: counted as dropped
      ++status_.dropped;
      return;
    }
    if (policy_ == StreamPolicy::kLatest && !waiting_.empty()) {
      status_.dropped += static_cast<long long>(waiting_.size());
      waiting_.clear();
    }
    waiting_.push_back({image, depth, std::move(info), arrival});
  }
  wake_.notify_one();
}

void LiveDetector::Skip() {
  std::lock_guard<std::mutex> lock(mutex_);
  ++status_.received;
  ++status_.refused;
  ++next_index_;
}

void LiveDetector::Save() {
  SaveRequest request{0, std::make_shared<std::promise<void>>()};
  std::future<void> saved = request.done->get_future();
  bool queued = false;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    request.after = next_index_;
    queued = !stopped_;
    if (queued) saves_.push_back(request);
  }
  if (queued) {
    wake_.notify_one();
  } else {
    RunSave(request);  // stopped: the map is closed, or processing failed
  }
  saved.get();
}

void LiveDetector::RunSave(SaveRequest& request) {
  std::string failure;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    failure = status_.failure;
  }
  try {
    if (!failure.empty()) {
      throw Error("cannot save the map: processing has stopped (" + failure + ")");
    }
    if (!closed_) detector_->Flush();  // closed: the map is complete already
    request.done->set_value();
  } catch (...) {
    request.done->set_exception(std::current_exception());
  }
}

void LiveDetector::SetPaused(bool paused) {
  std::lock_guard<std::mutex> lock(mutex_);
  status_.paused = paused;
}

LiveStatus LiveDetector::Status() const {
  std::lock_guard<std::mutex> lock(mutex_);
  LiveStatus status = status_;
  status.waiting = static_cast<long long>(waiting_.size());
  status.median_iteration_ms = Median(iteration_ms_);
  status.median_latency_ms = Median(latency_ms_);
  return status;
}

void LiveDetector::Stop() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stopping_ = true;
  }
  wake_.notify_one();
  if (thread_.joinable()) thread_.join();
}

void LiveDetector::Run() {
  NameThisThread("live");
  std::unique_lock<std::mutex> lock(mutex_);
  while (true) {
    wake_.wait(lock, [this] { return stopping_ || !waiting_.empty() || !saves_.empty(); });
    if (!saves_.empty() &&
        (waiting_.empty() || waiting_.front().info.index >= saves_.front().after)) {
      SaveRequest request = std::move(saves_.front());
      saves_.pop_front();
      lock.unlock();
      RunSave(request);
      lock.lock();
      continue;
    }
    if (stopping_) break;
    Pending pending = std::move(waiting_.front());
    waiting_.pop_front();
    lock.unlock();
    try {
      ProcessOne(pending);
    } catch (const std::exception& error) {
      lock.lock();
      status_.failure = error.what();
      break;
    }
    lock.lock();
  }
  // The image in progress is done; those still waiting are dropped.
  status_.dropped += static_cast<long long>(waiting_.size());
  waiting_.clear();
  const std::string failure = status_.failure;
  lock.unlock();
  if (failure.empty()) {
    try {
      detector_->Close();
      closed_ = true;
    } catch (const std::exception& error) {
      lock.lock();
      status_.failure = error.what();
      lock.unlock();
    }
  } else if (on_error_) {
    on_error_(failure, /*fatal=*/true);
  }
  detector_.reset();  // the map is free for another writer
  lock.lock();
  stopped_ = true;
  std::deque<SaveRequest> saves = std::move(saves_);
  lock.unlock();
  for (SaveRequest& request : saves) RunSave(request);
}

void LiveDetector::ProcessOne(Pending& pending) {
  LiveResult live;
  live.image = pending.info;
  live.arrival = pending.arrival;
  try {
    live.result = detector_->Process(pending.image, pending.depth, pending.info);
  } catch (const InputError& error) {  // this image only: the detector goes on
    {
      std::lock_guard<std::mutex> lock(mutex_);
      ++status_.refused;
    }
    if (on_error_) on_error_(error.what(), /*fatal=*/false);
    return;
  }
  const ImageIndex index = live.result.image_index;
  if (index >= 0) {
    if (images_.size() <= static_cast<size_t>(index)) {
      images_.resize(index + 1);
    }
    images_[index] = {pending.info.timestamp, live.result.session};
  }
  if (live.result.HasLoopClosure()) {
    const ImageIndex match = live.result.loop_closure_images.front();
    if (match >= 0 && static_cast<size_t>(match) < images_.size()) {
      live.match_timestamp = images_[match].timestamp;
      live.match_session = images_[match].session;
    }
  }
  if (on_result_) on_result_(live);
  const auto end = std::chrono::steady_clock::now();
  std::lock_guard<std::mutex> lock(mutex_);
  ++status_.processed;
  status_.loop_closures += live.result.HasLoopClosure();
  status_.last = live.result;
  RecordTimes(live.result.times.total_ms, Milliseconds(end - pending.arrival));
}

void LiveDetector::RecordTimes(double iteration_ms, double latency_ms) {
  iteration_ms_.push_back(iteration_ms);
  latency_ms_.push_back(latency_ms);
  if (iteration_ms_.size() > kTimesKept) iteration_ms_.pop_front();
  if (latency_ms_.size() > kTimesKept) latency_ms_.pop_front();
  status_.max_iteration_ms = std::max(status_.max_iteration_ms, iteration_ms);
  status_.max_latency_ms = std::max(status_.max_latency_ms, latency_ms);
}

}  // namespace memloop
