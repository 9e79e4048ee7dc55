#include "util/background_threads.h"

#include <gtest/gtest.h>

#include <chrono>
#include <future>
#include <memory>
#include <stdexcept>
#include <string>

namespace memloop {
namespace {

// Holds its thread's exit until the test opens the gate: a thread's thread_local objects are
// destroyed after its work has returned, as a low-priority thread's exit waits for the CPU.
std::shared_future<void>* exit_gate = nullptr;
struct HeldExit {
  ~HeldExit() { exit_gate->wait(); }
};
thread_local HeldExit held_exit;

TEST(BackgroundThreadsTest, GivesTheResultOrTheException) {
  BackgroundThreads threads;
  std::future<int> sum = threads.Start([] { return 2 + 3; });
  std::future<std::string> text = threads.Start([] { return std::string("built"); });
  std::future<void> failed = threads.Start([] { throw std::runtime_error("no memory"); });
  EXPECT_EQ(sum.get(), 5);
  EXPECT_EQ(text.get(), "built");
  EXPECT_THROW(failed.get(), std::runtime_error);
  threads.JoinAll();
  EXPECT_EQ(threads.unjoined(), 0u);
}

// The result is ready once set, while the thread has not ended: std::async's future would wait
// here until the gate opens, that is forever (the wait is bounded so that a failure is a failed
// test, not a hung one).
TEST(BackgroundThreadsTest, ResultReadyBeforeTheThreadEnds) {
  std::promise<void> gate;
  std::shared_future<void> opened = gate.get_future().share();
  exit_gate = &opened;
  BackgroundThreads threads;
  std::future<int> result = threads.Start([] {
    (void)&held_exit;  // this thread's exit now waits for the gate
    return 7;
  });
  ASSERT_EQ(result.wait_for(std::chrono::seconds(30)), std::future_status::ready);
  EXPECT_EQ(result.get(), 7);
  EXPECT_EQ(threads.unjoined(), 1u);  // not joined: it cannot end yet
  gate.set_value();
  threads.JoinAll();
  EXPECT_EQ(threads.unjoined(), 0u);
  exit_gate = nullptr;
}

// JoinAll waits for work still running, so that what the work reads can go after it; what the
// work captured goes with the future's state.
TEST(BackgroundThreadsTest, JoinAllWaitsForRunningWork) {
  auto captured = std::make_shared<int>(1);
  std::promise<void> go;
  std::shared_future<void> started = go.get_future().share();
  bool done = false;
  BackgroundThreads threads;
  std::future<void> work = threads.Start([captured, started, &done] {
    started.wait();
    done = true;
  });
  EXPECT_EQ(captured.use_count(), 2);
  go.set_value();
  threads.JoinAll();
  EXPECT_TRUE(done);  // joined: the write is visible
  work = {};
  EXPECT_EQ(captured.use_count(), 1);
}

}  // namespace
}  // namespace memloop
