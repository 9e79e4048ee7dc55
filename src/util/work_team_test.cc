#include "util/work_team.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <numeric>
#include <set>
#include <stdexcept>
#include <thread>
#include <vector>

namespace memloop {
namespace {

// Every item is done exactly once, whatever the number of threads and the chunk size, and a team
// runs loop after loop. Alone, the caller does the whole loop in one call.
TEST(WorkTeamTest, DoesEveryItemOnce) {
  for (int threads : {1, 2, 4}) {
    WorkTeam team(threads);
    EXPECT_EQ(team.threads(), threads);
    for (size_t chunk : {1, 3, 64}) {
      for (size_t count : {0, 1, 7, 200}) {
        std::vector<int> done(count, 0);
        team.Run(count, chunk, [&](size_t begin, size_t end) {
          EXPECT_LE(end - begin, threads == 1 ? count : chunk);
          for (size_t i = begin; i < end; ++i) ++done[i];
        });
        EXPECT_EQ(std::accumulate(done.begin(), done.end(), 0), static_cast<int>(count))
            << threads << " threads, chunk " << chunk << ", " << count << " items";
        EXPECT_TRUE(std::all_of(done.begin(), done.end(), [](int n) { return n == 1; }));
      }
    }
  }
}

// The helper works too: with two threads and chunks that wait for each other, the loop can only
// end if two threads run chunks at once. (One thread would block forever in the first chunk; the
// wait is bounded so that a failure is a failed test, not a hung one.)
TEST(WorkTeamTest, HelperRunsChunksBesideTheCaller) {
  WorkTeam team(2);
  std::atomic<int> arrived{0};
  std::set<std::thread::id> ids;
  std::mutex ids_mutex;
  std::atomic<bool> met{true};  // written by either thread
  team.Run(2, 1, [&](size_t, size_t) {
    {
      std::lock_guard<std::mutex> lock(ids_mutex);
      ids.insert(std::this_thread::get_id());
    }
    ++arrived;
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
    while (arrived < 2) {
      if (std::chrono::steady_clock::now() > deadline) {
        met = false;
        return;
      }
      std::this_thread::yield();
    }
  });
  EXPECT_TRUE(met);
  EXPECT_EQ(ids.size(), 2u);
}

// With a gate, chunks are taken while it says so: the items done are exactly the prefix the call
// returns, whatever the number of threads (taken 0, 16, 32, 48 < 50: 64 items), and the first
// chunk is taken whatever the gate says. A team whose loop was gated runs the next one whole.
TEST(WorkTeamTest, GateEndsTheLoopAtAPrefix) {
  for (int threads : {1, 2, 4}) {
    WorkTeam team(threads);
    for (size_t count : {40, 64, 200}) {
      std::vector<int> done(count, 0);
      std::vector<size_t> asked;  // the gate is called under the team's lock: one at a time
      const size_t returned = team.Run(
          count, 16,
          [&](size_t begin, size_t end) {
            for (size_t i = begin; i < end; ++i) ++done[i];
          },
          [&](size_t taken) {
            asked.push_back(taken);
            return taken < 50;
          });
      const size_t expected = std::min<size_t>(count, 64);
      EXPECT_EQ(returned, expected) << threads << " threads, " << count << " items";
      for (size_t i = 0; i < count; ++i) EXPECT_EQ(done[i], i < expected ? 1 : 0) << i;
      for (size_t taken : asked) EXPECT_GT(taken, 0u);  // never asked about the first chunk
    }
    std::vector<int> done(100, 0);
    EXPECT_EQ(team.Run(100, 16,
                       [&](size_t begin, size_t end) {
                         for (size_t i = begin; i < end; ++i) ++done[i];
                       }),
              100u);
    EXPECT_TRUE(std::all_of(done.begin(), done.end(), [](int n) { return n == 1; }));
    EXPECT_EQ(team.Run(
                  100, 16, [](size_t, size_t) {}, [](size_t) { return false; }),
              16u);
  }
}

// A chunk's exception reaches the caller; the team still runs the next loop.
TEST(WorkTeamTest, RethrowsAChunksFailure) {
  WorkTeam team(2);
  EXPECT_THROW(team.Run(10, 1,
                        [](size_t begin, size_t) {
                          if (begin == 7) throw std::runtime_error("item 7");
                        }),
               std::runtime_error);
  std::atomic<int> done{0};
  team.Run(10, 1, [&](size_t begin, size_t end) { done += static_cast<int>(end - begin); });
  EXPECT_EQ(done, 10);
}

}  // namespace
}  // namespace memloop
