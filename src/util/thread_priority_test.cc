#include "util/thread_priority.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <thread>

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

}  // namespace
}  // namespace memloop
