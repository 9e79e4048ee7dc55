#include "detector/stopwatch.h"

#include <gtest/gtest.h>

#include <thread>

namespace memloop {
namespace {

// Sleeping costs no CPU however loaded the machine; a spin that has run 30 ms of CPU took at
// least as long on the wall clock (a thread runs on one core at a time).
TEST(ThreadCpuMsTest, CountsTheTimeTheThreadRanNotTheTimeItWaited) {
  const double before_sleep = ThreadCpuMs();
  std::this_thread::sleep_for(std::chrono::milliseconds(60));
  EXPECT_LT(ThreadCpuMs() - before_sleep, 20.0);

  const Stopwatch wall;
  const double start = ThreadCpuMs();
  volatile double sink = 0;
  while (ThreadCpuMs() - start < 30.0) sink = sink + 1.0;
  const double ran = ThreadCpuMs() - start;
  EXPECT_GE(ran, 30.0);
  EXPECT_GE(wall.ElapsedMs() + 1.0, ran);
}

}  // namespace
}  // namespace memloop
