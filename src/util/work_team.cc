#include "util/work_team.h"

#include <algorithm>

#include "util/thread_name.h"

namespace memloop {

WorkTeam::WorkTeam(int threads) {
  for (int i = 1; i < threads; ++i) helpers_.emplace_back([this] { HelperLoop(); });
}

WorkTeam::~WorkTeam() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stopping_ = true;
  }
  work_ready_.notify_all();
  for (std::thread& helper : helpers_) helper.join();
}

size_t WorkTeam::Run(size_t count, size_t chunk, const std::function<void(size_t, size_t)>& work,
                     const Gate& gate) {
  chunk = std::max<size_t>(chunk, 1);
  if (count <= chunk || (helpers_.empty() && !gate)) {
    // One chunk (waking a helper costs more than it saves), or the caller alone without a gate.
    if (count > 0) work(0, count);
    return count;
  }
  if (helpers_.empty()) {  // the caller alone, chunk by chunk
    size_t next = 0;
    while (next < count && (next == 0 || gate(next))) {
      const size_t end = std::min(count, next + chunk);
      work(next, end);
      next = end;
    }
    return next;
  }
  std::unique_lock<std::mutex> lock(mutex_);
  work_ = &work;
  gate_ = gate ? &gate : nullptr;
  count_ = count;
  chunk_ = chunk;
  next_ = 0;
  failure_ = nullptr;
  work_ready_.notify_all();
  RunChunksLocked(lock);
  work_done_.wait(lock, [this] { return running_ == 0 && next_ >= count_; });
  const size_t done = count_;
  work_ = nullptr;
  gate_ = nullptr;
  if (failure_) std::rethrow_exception(failure_);
  return done;
}

void WorkTeam::HelperLoop() {
  NameThisThread("team");
  std::unique_lock<std::mutex> lock(mutex_);
  for (;;) {
    work_ready_.wait(lock, [this] { return stopping_ || (work_ != nullptr && next_ < count_); });
    if (stopping_) return;
    RunChunksLocked(lock);
  }
}

void WorkTeam::RunChunksLocked(std::unique_lock<std::mutex>& lock) {
  while (next_ < count_) {
    if (next_ > 0 && gate_ != nullptr && !(*gate_)(next_)) {
      count_ = next_;  // the loop ends at what was taken
      if (running_ == 0) work_done_.notify_all();
      return;
    }
    const size_t begin = next_;
    const size_t end = std::min(count_, begin + chunk_);
    next_ = end;
    ++running_;
    const auto* work = work_;
    lock.unlock();
    std::exception_ptr failure;
    try {
      (*work)(begin, end);
    } catch (...) {
      failure = std::current_exception();
    }
    lock.lock();
    if (failure && !failure_) failure_ = failure;
    if (--running_ == 0 && next_ >= count_) work_done_.notify_all();
  }
}

}  // namespace memloop
