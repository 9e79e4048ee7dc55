#include "util/thread_priority.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <thread>

#include "memloop/errors.h"

namespace memloop {
namespace {

// The lowered priority is the calling thread's own: the thread that called it runs nicer, the
// others keep theirs.
TEST(ThreadPriorityTest, LowersOnlyTheCallingThread) {
  const int before = ThisThreadsNiceness();
  int inside_before = 0, inside_after = 0;
  bool lowered = false;
  std::thread background([&] {
    inside_before = ThisThreadsNiceness();
    lowered = LowerThisThreadsPriority();
    inside_after = ThisThreadsNiceness();
  });
  background.join();
#ifdef __linux__
  ASSERT_TRUE(lowered);
  EXPECT_EQ(inside_after, std::min(inside_before + kBackgroundNiceness, 19));
#else
  EXPECT_FALSE(lowered);
#endif
  EXPECT_EQ(ThisThreadsNiceness(), before);
}

// Runs `body` on a new thread put under SCHED_FIFO at `priority` first; false when the system
// refuses (no root, CAP_SYS_NICE or `ulimit -r`), body then not run.
template <typename Body>
bool OnRealTimeThread(int priority, Body body) {
  bool allowed = false;
  std::thread thread([&] {
    try {
      SetThisThreadsRealTimePriority(priority);
    } catch (const Error&) {
      return;
    }
    allowed = true;
    body();
  });
  thread.join();
  return allowed;
}

TEST(ThreadPriorityTest, RealTimePriorityOutOfRangeIsRefusedNamingIt) {
  for (const int priority : {0, -3, 100}) {
    try {
      SetThisThreadsRealTimePriority(priority);
      FAIL() << "priority " << priority << " was accepted";
    } catch (const Error& error) {
      EXPECT_NE(std::string(error.what()).find("real-time priority " + std::to_string(priority)),
                std::string::npos)
          << error.what();
    }
  }
  EXPECT_EQ(ThisThreadsRealTimePriority(), 0);
}

// The detector's helpers are started after the caller's priority is set and inherit it; its
// background threads step below it, where the helpers preempt them and other programs do not.
TEST(ThreadPriorityTest, HelpersInheritTheRealTimePriorityBackgroundThreadsStepBelow) {
  int caller = -1, helper = -1, writer = -1, build = -1;
  const bool allowed = OnRealTimeThread(7, [&] {
    caller = ThisThreadsRealTimePriority();
    std::thread([&] { helper = ThisThreadsRealTimePriority(); }).join();
    std::thread([&] {
      EXPECT_TRUE(StepBelowRealTimePriority());
      writer = ThisThreadsRealTimePriority();
    }).join();
    std::thread([&] {
      EXPECT_TRUE(LowerThisThreadsPriority());
      build = ThisThreadsRealTimePriority();
    }).join();
  });
  if (!allowed) GTEST_SKIP() << "this process may not use SCHED_FIFO (not root, no CAP_SYS_NICE)";
  EXPECT_EQ(caller, 7);
  EXPECT_EQ(helper, 7);
  EXPECT_EQ(writer, 6);
  EXPECT_EQ(build, 6);
  EXPECT_EQ(ThisThreadsRealTimePriority(), 0);  // this thread was never changed
}

// Below real-time priority 1 is the usual scheduling: there a background build also runs nicer,
// and a thread that only steps below keeps its nice level.
TEST(ThreadPriorityTest, BelowRealTimePriorityOneIsTheUsualScheduling) {
  int caller_nice = 0, writer = -1, writer_nice = 99, build = -1, build_nice = -99;
  const bool allowed = OnRealTimeThread(1, [&] {
    caller_nice = ThisThreadsNiceness();
    std::thread([&] {
      EXPECT_TRUE(StepBelowRealTimePriority());
      writer = ThisThreadsRealTimePriority();
      writer_nice = ThisThreadsNiceness();
    }).join();
    std::thread([&] {
      EXPECT_TRUE(LowerThisThreadsPriority());
      build = ThisThreadsRealTimePriority();
      build_nice = ThisThreadsNiceness();
    }).join();
  });
  if (!allowed) GTEST_SKIP() << "this process may not use SCHED_FIFO (not root, no CAP_SYS_NICE)";
  EXPECT_EQ(writer, 0);
  EXPECT_EQ(writer_nice, caller_nice);
  EXPECT_EQ(build, 0);
  EXPECT_EQ(build_nice, std::min(caller_nice + kBackgroundNiceness, 19));
}

}  // namespace
}  // namespace memloop
