// A second job on the machine for the length of a scope: two busy threads take both cores, as
// other jobs do on a shared CI machine. Tests whose verdict must not depend on timing run under it.
#pragma once

#include <atomic>
#include <thread>
#include <vector>

namespace memloop::testing {

class BothCoresLoaded {
 public:
  BothCoresLoaded() {
    for (int k = 0; k < 2; ++k) {
      threads_.emplace_back([this] {
        volatile double x = 1;
        while (!stop_) x = x * 1.0000001 + 1e-9;
      });
    }
  }
  ~BothCoresLoaded() {
    stop_ = true;
    for (std::thread& thread : threads_) thread.join();
  }
  BothCoresLoaded(const BothCoresLoaded&) = delete;
  BothCoresLoaded& operator=(const BothCoresLoaded&) = delete;

 private:
  std::atomic<bool> stop_{false};
  std::vector<std::thread> threads_;
};

}  // namespace memloop::testing
