#include "detector/transfer.h"

#include <gtest/gtest.h>

#include "small_map.h"

namespace memloop {
namespace {

class TransferTest : public ::testing::Test {
 protected:
  TransferTest() {
    // L1 {1, 2}, L2 {3, 4}, L3 {5, 6}, L4 {7, 1}: word 1 shared by L1 and L4.
    ids_ = testing::AddChain(memory_, {{1, 2}, {3, 4}, {5, 6}, {7, 1}});
    memory_.MoveStmOverflowToWm(0);
    const int weights[] = {2, 0, 0, 1};
    for (int i = 0; i < 4; ++i) memory_.at(ids_[i]).weight = weights[i];
  }

  testing::SmallMap map_;
  Memory& memory_ = map_.memory;
  LongTermMemory& ltm_ = map_.ltm;
  MapEditor& editor_ = map_.editor;
  std::vector<LocationId> ids_;
};

TEST_F(TransferTest, LowestWeightFirstThenOldestAndRetrievedAreImmune) {
  EXPECT_EQ(TransferOrder(memory_, {}),
            (std::vector<LocationId>{ids_[1], ids_[2], ids_[3], ids_[0]}));
  EXPECT_EQ(TransferOrder(memory_, {ids_[2]}),
            (std::vector<LocationId>{ids_[1], ids_[3], ids_[0]}));
}

// The highest hypothesis' neighbourhood goes after all others, in weight-then-age order itself.
TEST_F(TransferTest, KeptLastLocationsGoAfterAllOthers) {
  EXPECT_EQ(TransferOrder(memory_, {}, {ids_[1], ids_[3]}),
            (std::vector<LocationId>{ids_[2], ids_[0], ids_[1], ids_[3]}));
  TransferTrigger trigger;
  trigger.max_wm_locations = 2;
  trigger.dictionary_size_at_start = memory_.dictionary().size();
  EXPECT_EQ(Transfer(trigger, {}, {ids_[1], ids_[2]}, memory_, editor_),
            (std::vector<LocationId>{ids_[3], ids_[0]}));
}

// A budget below the kept-last set still holds: they leave too, last.
TEST_F(TransferTest, BudgetHoldsEvenOverKeptLastLocations) {
  TransferTrigger trigger;
  trigger.max_wm_locations = 1;
  trigger.dictionary_size_at_start = memory_.dictionary().size();
  EXPECT_EQ(Transfer(trigger, {}, {ids_[1], ids_[2], ids_[3]}, memory_, editor_),
            (std::vector<LocationId>{ids_[0], ids_[1], ids_[2]}));
}

TEST_F(TransferTest, TimeLimitTransfersUntilTheDictionaryIsBackToItsSize) {
  TransferTrigger trigger;
  trigger.time_exceeded = true;
  // 7 words now; "3 were added this iteration": transfer until 4 remain at most.
  trigger.dictionary_size_at_start = memory_.dictionary().size() - 3;
  const auto transferred = Transfer(trigger, {}, {}, memory_, editor_);
  // L2 frees words 3, 4 (5 left: not enough), L3 frees 5, 6 (3 left): stop.
  EXPECT_EQ(transferred, (std::vector<LocationId>{ids_[1], ids_[2]}));
  EXPECT_EQ(memory_.dictionary().size(), 3u);
  EXPECT_TRUE(ltm_.Contains(ids_[1]));
  EXPECT_EQ(ltm_.size(), 2u);
  ASSERT_TRUE(ltm_.LoadWord(3).has_value());  // words go to LTM with their locations
  EXPECT_EQ(*ltm_.LoadWord(3), testing::FloatBytes({300, 0}));
}

TEST_F(TransferTest, AtLeastOneLocationOnceTriggered) {
  TransferTrigger trigger;
  trigger.time_exceeded = true;
  trigger.dictionary_size_at_start = memory_.dictionary().size();  // nothing added
  EXPECT_EQ(Transfer(trigger, {}, {}, memory_, editor_).size(), 1u);
}

// The time controller asks for 3: the dictionary rule alone (nothing added) would stop at one.
TEST_F(TransferTest, TimeControllerTransfersItsCount) {
  TransferTrigger trigger;
  trigger.time_exceeded = true;
  trigger.dictionary_size_at_start = memory_.dictionary().size();
  trigger.min_locations = 3;
  bool cut_short = true;
  EXPECT_EQ(Transfer(trigger, {}, {}, memory_, editor_, StepDeadline(), &cut_short),
            (std::vector<LocationId>{ids_[1], ids_[2], ids_[3]}));
  EXPECT_FALSE(cut_short);  // no deadline: all it asked for
}

// Past T_time's deadline, the controller's extra locations wait; the paper's rule and a budget
// do not (at least one location, and WM down to the budget).
TEST_F(TransferTest, TheControllersExtraLocationsGoOnlyWhileTheyFit) {
  TransferTrigger trigger;
  trigger.time_exceeded = true;
  trigger.dictionary_size_at_start = memory_.dictionary().size();
  trigger.min_locations = 3;
  StepCost cost;
  const StepDeadline past([] { return 60.0; }, 50, &cost);
  bool cut_short = false;
  EXPECT_EQ(Transfer(trigger, {}, {}, memory_, editor_, past, &cut_short),
            (std::vector<LocationId>{ids_[1]}));
  EXPECT_TRUE(cut_short);        // time decided: 1 of the 3 asked for
  EXPECT_TRUE(cost.measured());  // the one it took was timed
  trigger.max_wm_locations = 1;  // 3 left in WM: two more must go
  EXPECT_EQ(Transfer(trigger, {}, {}, memory_, editor_, past),
            (std::vector<LocationId>{ids_[2], ids_[3]}));
}

TEST_F(TransferTest, WorkingMemoryBudgetIsDeterministic) {
  TransferTrigger trigger;
  trigger.max_wm_locations = 2;
  trigger.dictionary_size_at_start = memory_.dictionary().size();
  const auto transferred = Transfer(trigger, {ids_[1]}, {}, memory_, editor_);
  EXPECT_EQ(transferred, (std::vector<LocationId>{ids_[2], ids_[3]}));  // L2 was retrieved
  EXPECT_EQ(memory_.working_memory().size(), 2u);
  // L4 shared word 1 with L1: it stays in the dictionary, marked as held by LTM too.
  EXPECT_TRUE(memory_.dictionary().Contains(1));
  EXPECT_TRUE(memory_.dictionary().IsReferencedByLtm(1));
}

TEST_F(TransferTest, DictionaryBudget) {
  TransferTrigger trigger;
  trigger.max_dictionary_words = 5;
  trigger.dictionary_size_at_start = memory_.dictionary().size();
  EXPECT_EQ(Transfer(trigger, {}, {}, memory_, editor_), (std::vector<LocationId>{ids_[1]}));
  EXPECT_EQ(memory_.dictionary().size(), 5u);
}

TEST_F(TransferTest, NoTriggerNoTransfer) {
  TransferTrigger trigger;
  trigger.dictionary_size_at_start = 0;
  EXPECT_TRUE(Transfer(trigger, {}, {}, memory_, editor_).empty());
}

// T_time 100 ms. The paper (target 1): 90 ms so far is not over, 101 is. memloop's 0.75: 76 > 75
// transfers, 75 does not (at the target is not over). T_time off never triggers.
TEST(TimeExceededTest, AimsBelowTimeLimit) {
  EXPECT_FALSE(TimeExceeded(90, 100, 1.0));
  EXPECT_TRUE(TimeExceeded(101, 100, 1.0));
  EXPECT_TRUE(TimeExceeded(76, 100, 0.75));
  EXPECT_FALSE(TimeExceeded(75, 100, 0.75));
  EXPECT_FALSE(TimeExceeded(1e9, 0, 0.75));
}

// Target 75 ms, WM 1000. 90 ms with 40 in the WM stages: the rest is 50, so the WM stages may
// take 25 of their 40 ms: keep 62.5%, transfer 375 -> capped at 2% = 20. With a cap of 50%: 375.
// 80 ms with 40 in WM: keep 35/40 = 87.5%, 125 over. The rest alone over the target (a slow
// stage that WM does not drive, or a machine busy elsewhere): none, as under the target, with the
// WM stages unmeasured, or with the paper's rule (cap 0).
TEST(LocationsOverTimeTest, ScalesTheWorkingMemoryStagesToTheTarget) {
  EXPECT_EQ(LocationsOverTime(90, 40, 75, 1000, 0.02), 20);
  EXPECT_EQ(LocationsOverTime(90, 40, 75, 1000, 0.5), 375);
  EXPECT_EQ(LocationsOverTime(80, 40, 75, 1000, 0.5), 125);
  EXPECT_EQ(LocationsOverTime(200, 10, 75, 1000, 0.5), 0);
  EXPECT_EQ(LocationsOverTime(90, 40, 50, 1000, 0.5), 0);  // rest 50 = target
  EXPECT_EQ(LocationsOverTime(90, 40, 75, 10, 0.02), 1);   // the cap rounds up: at least one
  EXPECT_EQ(LocationsOverTime(70, 40, 75, 1000, 0.5), 0);
  EXPECT_EQ(LocationsOverTime(90, 0, 75, 1000, 0.5), 0);
  EXPECT_EQ(LocationsOverTime(90, 40, 75, 1000, 0), 0);
}

// memory.wm_min_time_share: WM's stages keep what the rest leaves of the target, at least the
// share. Iteration 90 ms, target 75: with WM's stages at 40 ms the rest is 50, the budget
// max(25, 0.25 x 75 = 18.75) = 25; at 10 ms the rest is 80 > 75, the budget 18.75.
TEST(LocationsOverTimeTest, WmKeepsItsShareOfTheTargetWhenTheRestIsTheCost) {
  EXPECT_DOUBLE_EQ(WmTimeBudget(90, 40, 75, 0.25), 25);
  EXPECT_DOUBLE_EQ(WmTimeBudget(90, 10, 75, 0.25), 18.75);
  EXPECT_DOUBLE_EQ(WmTimeBudget(90, 10, 75, 0), 0);  // the rest alone is over the target
  EXPECT_TRUE(WmIsTheCost(90, 40, 75, 0.25));        // 40 > 25
  EXPECT_FALSE(WmIsTheCost(90, 10, 75, 0.25));       // 10 <= 18.75: features or retrieval are slow
  EXPECT_TRUE(WmIsTheCost(90, 10, 75, 0));           // the paper: any iteration over the target
  EXPECT_TRUE(WmIsTheCost(100, 30, 75, 0.25));       // rest 70: budget max(5, 18.75), 30 > 18.75
  // 1000 locations, WM's stages 30 ms scaled to 18.75: 375 over, capped at 2% = 20 or 50% = 375.
  EXPECT_EQ(LocationsOverTime(100, 30, 75, 1000, 0.02, 0.25), 20);
  EXPECT_EQ(LocationsOverTime(100, 30, 75, 1000, 0.5, 0.25), 375);
  EXPECT_EQ(LocationsOverTime(100, 30, 75, 1000, 1, 0), 834);    // the budget is 5 ms: keep 1/6
  EXPECT_EQ(LocationsOverTime(90, 10, 75, 1000, 0.5, 0.25), 0);  // within its share
}

// memory.retrieved_immune_iterations (and _kept_last_): retrieved at iteration 5 with 3 iterations,
// immune at 5, 6 and 7, not at 8; a location that left WM is not reported.
TEST_F(TransferTest, RetrievedLocationsStayImmuneForTheirIterations) {
  RecentRetrievals immunity(3);
  immunity.StartIteration(5);
  immunity.Retrieved({ids_[1], ids_[2]}, 5);
  EXPECT_EQ(immunity.InWorkingMemory(memory_), (std::set<LocationId>{ids_[1], ids_[2]}));
  immunity.StartIteration(7);
  immunity.Retrieved({ids_[3]}, 7);
  EXPECT_EQ(immunity.InWorkingMemory(memory_), (std::set<LocationId>{ids_[1], ids_[2], ids_[3]}));
  immunity.StartIteration(8);
  EXPECT_EQ(immunity.InWorkingMemory(memory_), (std::set<LocationId>{ids_[3]}));
  EXPECT_EQ(TransferOrder(memory_, immunity.InWorkingMemory(memory_)),
            (std::vector<LocationId>{ids_[1], ids_[2], ids_[0]}));
  RecentRetrievals text(1);  // the paper's text: the retrieving iteration only
  text.StartIteration(5);
  text.Retrieved({ids_[1]}, 5);
  EXPECT_EQ(text.InWorkingMemory(memory_), (std::set<LocationId>{ids_[1]}));
  text.StartIteration(6);
  EXPECT_TRUE(text.InWorkingMemory(memory_).empty());
  immunity.Retrieved({ids_[0]}, 8);
  editor_.TransferToLtm(ids_[0]);
  EXPECT_EQ(immunity.InWorkingMemory(memory_), (std::set<LocationId>{ids_[3]}));
  RecentRetrievals off(0);  // memory.retrieved_kept_last_iterations = 0: none, not even now
  off.StartIteration(5);
  off.Retrieved({ids_[1]}, 5);
  EXPECT_TRUE(off.InWorkingMemory(memory_).empty());
}

}  // namespace
}  // namespace memloop
