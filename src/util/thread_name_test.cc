#include "util/thread_name.h"

#include <gtest/gtest.h>

#include <string>
#include <thread>

#ifdef __linux__
#include <pthread.h>
#endif

namespace memloop {
namespace {

#ifdef __linux__
std::string ThisThreadsName() {
  char name[16] = {};
  pthread_getname_np(pthread_self(), name, sizeof(name));
  return name;
}

// The name is the calling thread's, prefixed, cut to the kernel's 15 characters.
TEST(ThreadNameTest, NamesOnlyTheCallingThreadWithinFifteenCharacters) {
  const std::string before = ThisThreadsName();
  std::string short_name, long_name;
  std::thread background([&] {
    NameThisThread("writer");
    short_name = ThisThreadsName();
    NameThisThread("catchup-thread");
    long_name = ThisThreadsName();
  });
  background.join();
  EXPECT_EQ(short_name, "memloop-writer");
  EXPECT_EQ(long_name, "memloop-catchup");
  EXPECT_EQ(ThisThreadsName(), before);
}
#endif

}  // namespace
}  // namespace memloop
