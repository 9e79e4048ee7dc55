// Work on threads of its own, whose results can be waited for without waiting for the threads to
// end. std::async would do, but its future joins the thread before it says the result is ready
// (libstdc++: wait_for and get call join): a background thread at a lower priority that has set
// its result must still run again to exit, and on a loaded machine it waits for the CPU while the
// image waits for it (issue 37: beside two busy programs, 19 such waits in 3,150 images, up to
// 188 ms). Here the result is ready once set, and the detector's thread joins a thread only when
// its work ended over kJoinAfter before (it has long exited: a join that returns at once), when
// the next work starts; JoinAll and the destructor join the rest.
#pragma once

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <future>
#include <memory>
#include <thread>
#include <type_traits>
#include <utility>
#include <vector>

namespace memloop {

class BackgroundThreads {
 public:
  BackgroundThreads() = default;
  ~BackgroundThreads() { JoinAll(); }
  BackgroundThreads(const BackgroundThreads&) = delete;
  BackgroundThreads& operator=(const BackgroundThreads&) = delete;

  // A thread whose work ended this long ago is joined by the next Start: its exit is done, even
  // at a low priority on a loaded machine (Linux's scheduler runs every thread within its period).
  static constexpr std::chrono::seconds kJoinAfter{1};

  // Runs work() on a new thread; its result (or exception) in the future, as std::async's. What
  // work captured is destroyed with the future's state, by whoever releases it last.
  template <typename Work>
  std::future<std::invoke_result_t<Work&>> Start(Work work) {
    JoinLongEnded();
    std::packaged_task<std::invoke_result_t<Work&>()> task(std::move(work));
    auto result = task.get_future();
    auto ended_at = std::make_shared<std::atomic<int64_t>>(kRunning);
    std::thread thread([task = std::move(task), ended_at]() mutable {
      task();
      task = {};  // this thread's share of the state, released before it says it has ended
      ended_at->store(Now(), std::memory_order_release);
    });
    threads_.push_back({std::move(thread), std::move(ended_at)});
    return result;
  }

  // Waits for every thread to end: before what their work reads goes. Start, JoinAll and the
  // destructor are called from one thread.
  void JoinAll() {
    for (Running& running : threads_) running.thread.join();
    threads_.clear();
  }

  // Threads not joined yet, ended or not.
  size_t unjoined() const { return threads_.size(); }

 private:
  static constexpr int64_t kRunning = -1;
  static int64_t Now() {
    return std::chrono::duration_cast<std::chrono::nanoseconds>(
               std::chrono::steady_clock::now().time_since_epoch())
        .count();
  }

  struct Running {
    std::thread thread;
    std::shared_ptr<std::atomic<int64_t>> ended_at;  // steady clock, ns; kRunning until then
  };

  void JoinLongEnded() {
    const int64_t before = Now() - std::chrono::nanoseconds(kJoinAfter).count();
    const auto ended =
        std::stable_partition(threads_.begin(), threads_.end(), [&](const Running& r) {
          const int64_t at = r.ended_at->load(std::memory_order_acquire);
          return at == kRunning || at > before;
        });
    for (auto it = ended; it != threads_.end(); ++it) it->thread.join();
    threads_.erase(ended, threads_.end());
  }

  std::vector<Running> threads_;
};

}  // namespace memloop
