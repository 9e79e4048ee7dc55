#pragma once

#include <chrono>

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
