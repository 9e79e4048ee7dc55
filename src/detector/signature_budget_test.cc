#include "detector/signature_budget.h"

#include <gtest/gtest.h>

namespace memloop {
namespace {

TEST(SignatureBudgetTest, AChunkIsTakenWhenItEndsByTheDeadlineOrBelowTheMinimum) {
  EXPECT_TRUE(TakeNextChunk(32, 50, 8.0, 1.5, 10.0));    // 9.5 <= 10
  EXPECT_TRUE(TakeNextChunk(32, 50, 8.5, 1.5, 10.0));    // 10, just
  EXPECT_FALSE(TakeNextChunk(64, 50, 8.6, 1.5, 10.0));   // 10.1
  EXPECT_TRUE(TakeNextChunk(32, 50, 20.0, 1.5, 10.0));   // late, but 32 < the 50 always taken
  EXPECT_FALSE(TakeNextChunk(50, 50, 20.0, 1.5, 10.0));  // the minimum reached
}

MemoryOptions TimeLimit(double ms) {
  MemoryOptions memory;
  memory.time_limit_ms = ms;
  memory.time_target = 0.75;
  memory.signature_min_share = 0.5;
  return memory;
}

TEST(SignatureBudgetTest, OffWithoutTimeLimitOrWhenTheParameterSaysSo) {
  EXPECT_FALSE(SignatureBudget(TimeLimit(0), 2).enabled());
  EXPECT_FALSE(SignatureBudget(TimeLimit(0), 2).Gate(100, [] { return 1e9; }));
  MemoryOptions off = TimeLimit(20);
  off.signature_within_time = 0;
  EXPECT_FALSE(SignatureBudget(off, 2).enabled());
  EXPECT_TRUE(SignatureBudget(TimeLimit(20), 2).enabled());
}

// Target 0.75 x 20 = 15 ms. The steps after the search took 2 ms (expected 2 + 2 x 1 = 4: the
// deadline is 11 ms); a search of 200 rows on two threads took 4 ms: 4 x 2 / 200 = 0.04 ms a row on
// one thread, expected 0.04 + 2 x 0.02 = 0.08, a chunk of 16 rows 1.28 ms.
TEST(SignatureBudgetTest, TheDeadlineLeavesRoomForTheStepsAfterTheSearch) {
  SignatureBudget budget(TimeLimit(20), 2);
  EXPECT_DOUBLE_EQ(budget.DeadlineMs(), 15);  // nothing measured yet
  budget.RecordAfterQuantization(2);
  budget.RecordQuantization(4, 200);
  EXPECT_DOUBLE_EQ(budget.DeadlineMs(), 11);
  EXPECT_NEAR(budget.ChunkMs(), 1.28, 1e-12);
  double now = 9.0;
  const SearchGate gate = budget.Gate(200, [&now] { return now; });  // the search starts at 9 ms
  now = 9.5;              // 48 rows taken in 0.5 ms: faster than expected
  EXPECT_TRUE(gate(48));  // 9.5 + 1.28 <= 11
  now = 9.8;
  EXPECT_FALSE(gate(112));  // 9.8 + 1.28 > 11, and 112 >= the 100 always taken
  EXPECT_TRUE(gate(96));    // under the minimum, 50% of 200
}

// A deferred retrieval asks the next image for room (memory.signature_room_for_retrieval): the
// deadline is then T_time less the room when that is before the target. T_time 20, target 15;
// steps after the search expected 4 ms (as above).
TEST(SignatureBudgetTest, RoomForADeferredRetrievalBringsTheDeadlineForward) {
  SignatureBudget budget(TimeLimit(20), 2);
  budget.RecordAfterQuantization(2);
  budget.RecordQuantization(4, 200);
  budget.LeaveRoom(3);                        // 20 - 3 = 17, after the target: no change
  EXPECT_DOUBLE_EQ(budget.DeadlineMs(), 11);  // 15 - 4
  budget.LeaveRoom(9);                        // 20 - 9 = 11, before the target
  EXPECT_DOUBLE_EQ(budget.DeadlineMs(), 7);   // 11 - 4
  budget.LeaveRoom(0);
  EXPECT_DOUBLE_EQ(budget.DeadlineMs(), 11);
  MemoryOptions off = TimeLimit(20);
  off.signature_room_for_retrieval = 0;
  SignatureBudget without(off, 2);
  without.LeaveRoom(9);
  EXPECT_DOUBLE_EQ(without.DeadlineMs(), 15);
}

// A search slower than the last ones judges by its own chunks: 48 rows in 3.5 ms on two threads is
// 3.5 x 2 x 16 / 48 = 2.33 ms a chunk, more than the 1.28 expected from the last searches.
TEST(SignatureBudgetTest, ASlowSearchJudgesByItsOwnChunks) {
  SignatureBudget budget(TimeLimit(20), 2);
  budget.RecordAfterQuantization(2);
  budget.RecordQuantization(4, 200);
  double now = 6.0;
  const SearchGate gate = budget.Gate(80, [&now] { return now; });  // at least 40 rows
  now = 8.0;
  EXPECT_TRUE(gate(40));  // 2 x 2 x 16 / 40 = 1.6 a chunk: 9.6 <= 11
  now = 9.5;
  EXPECT_FALSE(gate(48));  // 9.5 + 2.33 > 11 (with the expected 1.28 alone: 10.78, taken)
}

// As above: deadline 11 ms, 0.08 ms a row on one thread, 200 rows on two threads 8 ms. With
// 9 ms left every row is searched with the dictionary's 32 leaves (0); with 4 ms left, half the
// cost fits: 16 leaves; with 1 ms, 32 / 8 = 4, raised to the 8 of memory.signature_min_checks.
TEST(SignatureBudgetTest, FewerLeavesInProportionToTheTimeLeft) {
  MemoryOptions memory = TimeLimit(20);
  memory.signature_min_checks = 8;
  SignatureBudget budget(memory, 2, {}, 32);
  EXPECT_EQ(budget.Checks(200, 2.0), 0);  // nothing measured yet
  budget.RecordAfterQuantization(2);
  budget.RecordQuantization(4, 200);
  EXPECT_EQ(budget.Checks(200, 2.0), 0);
  EXPECT_EQ(budget.Checks(200, 3.0), 0);  // 8 ms left: just
  EXPECT_EQ(budget.Checks(200, 7.0), 16);
  EXPECT_EQ(budget.Checks(200, 10.0), 8);
  EXPECT_EQ(budget.Checks(200, 30.0), 8);  // already late
  memory.signature_min_checks = 0;         // features dropped first, as before
  SignatureBudget drop_first(memory, 2, {}, 32);
  drop_first.RecordAfterQuantization(2);
  drop_first.RecordQuantization(4, 200);
  EXPECT_EQ(drop_first.Checks(200, 10.0), 0);
  EXPECT_EQ(SignatureBudget(TimeLimit(0), 2, {}, 32).Checks(200, 10.0), 0);  // T_time off
}

// A search of 8 leaves of 32 that took 1 ms counts as 4 ms at 32 (0.08 ms a row expected, a
// chunk 1.28 ms), and a gate for 16 leaves expects half a chunk: at 9.8 ms with 112 rows taken,
// 9.8 + 0.64 <= 11 (with 32 leaves, 9.8 + 1.28 > 11:
// TheDeadlineLeavesRoomForTheStepsAfterTheSearch).
TEST(SignatureBudgetTest, SearchesOfFewerLeavesAreCountedAtTheDictionarysLeaves) {
  SignatureBudget budget(TimeLimit(20), 2, {}, 32);
  budget.RecordAfterQuantization(2);
  budget.RecordQuantization(1, 200, 8);
  EXPECT_NEAR(budget.ChunkMs(), 1.28, 1e-12);
  double now = 9.0;
  const SearchGate gate = budget.Gate(
      200, [&now] { return now; }, 16);
  now = 9.8;
  EXPECT_TRUE(gate(112));
  now = 10.5;
  EXPECT_FALSE(gate(112));  // 10.5 + 0.64 > 11
}

// Goal 1%, target 0.75 x 20 = 15 ms. An iteration over 20 ms brings the target 0.1 x 0.99 of it
// earlier (scale 0.901: 13.515 ms), each one within moves it 0.1 x 0.01 = 0.001 back (99 of them:
// 0.901 + 0.099 = 1); never past 1, never under 0.5 (seven over: 1 - 6.93 x 0.1 < 0.5).
TEST(SignatureBudgetTest, TheTargetMovesToTheShareOfIterationsOverTimeAllowed) {
  MemoryOptions memory = TimeLimit(20);
  memory.over_time_goal = 0.01;
  SignatureBudget budget(memory, 2);
  EXPECT_DOUBLE_EQ(budget.TargetMs(), 15);
  budget.RecordIteration(19.9);  // within: already at the target
  EXPECT_DOUBLE_EQ(budget.target_scale(), 1);
  budget.RecordIteration(20.5);
  EXPECT_NEAR(budget.target_scale(), 0.901, 1e-12);
  EXPECT_NEAR(budget.TargetMs(), 13.515, 1e-12);
  EXPECT_NEAR(budget.DeadlineMs(), 13.515, 1e-12);  // nothing measured after the search
  for (int i = 0; i < 98; ++i) budget.RecordIteration(12);
  EXPECT_NEAR(budget.target_scale(), 0.999, 1e-9);
  budget.RecordIteration(12);
  budget.RecordIteration(12);
  EXPECT_DOUBLE_EQ(budget.target_scale(), 1);
  for (int i = 0; i < 7; ++i) budget.RecordIteration(25);
  EXPECT_DOUBLE_EQ(budget.target_scale(), 0.5);
  EXPECT_DOUBLE_EQ(budget.TargetMs(), 7.5);
}

// Goal 0 is the time target alone; without T_time nothing moves.
TEST(SignatureBudgetTest, TheTargetStaysWithoutAGoalOrATimeLimit) {
  MemoryOptions fixed = TimeLimit(20);
  fixed.over_time_goal = 0;
  SignatureBudget budget(fixed, 2);
  budget.RecordIteration(40);
  EXPECT_DOUBLE_EQ(budget.TargetMs(), 15);
  SignatureBudget off(TimeLimit(0), 2);
  off.RecordIteration(40);
  EXPECT_DOUBLE_EQ(off.target_scale(), 1);
}

}  // namespace
}  // namespace memloop
