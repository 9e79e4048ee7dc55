// Splits one loop of independent items between the calling thread and helper threads, for the
// per-image work that is most of an iteration: the kd-forest's searches (issue 9: ~40 us per
// descriptor at 400,000 words, 60% of an iteration and nearly all of a retrieval).
//
// The caller works too, taking chunks from the same counter as the helpers: when a helper gets no
// CPU (two cores shared with the LTM writer and a background build), the caller does its chunks,
// so a loop never takes much longer than on one thread. Items are independent and each writes
// only its own output, so results do not depend on the number of threads or on who ran what.
#pragma once

#include <condition_variable>
#include <cstddef>
#include <exception>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace memloop {

class WorkTeam {
 public:
  // `threads` counts the caller: 1 runs every loop on the caller's thread, with no helper.
  explicit WorkTeam(int threads);
  ~WorkTeam();
  WorkTeam(const WorkTeam&) = delete;
  WorkTeam& operator=(const WorkTeam&) = delete;

  int threads() const { return static_cast<int>(helpers_.size()) + 1; }

  // Before each chunk after the first: whether to take it, given the items taken so far.
  using Gate = std::function<bool(size_t taken)>;

  // Calls work(begin, end) over [0, count) in chunks of at most `chunk` items (in one call when
  // the caller works alone and there is no gate), and returns when every chunk taken is done. With
  // a `gate`, a chunk is taken only while it says so: the items done are then [0, returned), since
  // chunks are taken in order and each one taken is finished (a loop with a deadline: the items
  // done are a prefix whatever the threads did). Returns `count` without a gate. The first
  // exception a chunk throws is rethrown here (the other chunks still run). One loop at a time:
  // Run is not reentrant and is called from one thread.
  size_t Run(size_t count, size_t chunk, const std::function<void(size_t, size_t)>& work,
             const Gate& gate = {});

 private:
  void HelperLoop();
  // Takes and runs chunks of the current loop until none is left or the gate closes (the count
  // then ends at the items taken). Called with mutex_ held.
  void RunChunksLocked(std::unique_lock<std::mutex>& lock);

  std::mutex mutex_;
  std::condition_variable work_ready_;
  std::condition_variable work_done_;
  // The current loop.
  const std::function<void(size_t, size_t)>* work_ = nullptr;
  size_t count_ = 0;
  size_t chunk_ = 1;
  size_t next_ = 0;             // first item not yet taken
  const Gate* gate_ = nullptr;  // the current loop's, or null
  int running_ = 0;             // chunks taken and not finished
  std::exception_ptr failure_;
  bool stopping_ = false;
  std::vector<std::thread> helpers_;
};

}  // namespace memloop
