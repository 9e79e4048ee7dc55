#pragma once

#include <chrono>
#include <ctime>

namespace memloop {

// Wall-clock milliseconds since construction.
class Stopwatch {
 public:
  double ElapsedMs() const {
    return std::chrono::duration<double, std::milli>(Clock::now() - start_).count();
  }

 private:
  using Clock = std::chrono::steady_clock;
  Clock::time_point start_ = Clock::now();
};

// CPU milliseconds the calling thread has run (CLOCK_THREAD_CPUTIME_ID). Over an iteration, wall
// time minus this is time the thread did not run: waiting (for the search's other thread, the
// disk, the map's writer) or descheduled by the OS. On a virtual machine, time the host stopped
// the virtual CPU may count as run: the guest cannot tell (a 0.35 ms step once showed 107 ms).
inline double ThreadCpuMs() {
  timespec now{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &now);
  return static_cast<double>(now.tv_sec) * 1e3 + static_cast<double>(now.tv_nsec) * 1e-6;
}

// Adds the lifetime of the scope to `*total_ms`.
class ScopedTimer {
 public:
  explicit ScopedTimer(double* total_ms) : total_ms_(total_ms) {}
  ~ScopedTimer() { *total_ms_ += stopwatch_.ElapsedMs(); }

 private:
  double* total_ms_;
  Stopwatch stopwatch_;
};

}  // namespace memloop
