#include "detector/retrieval.h"

#include <gtest/gtest.h>

#include "detector/transfer.h"
#include "small_map.h"

namespace memloop {
namespace {

class RetrievalTest : public ::testing::Test {
 protected:
  RetrievalTest() {
    // A chain L1 .. L5; L3 and L4 share word 7; L3 also has word 18.
    ids_ = testing::AddChain(memory_, {{1}, {2}, {3, 7, 18}, {4, 7}, {5}});
    memory_.MoveStmOverflowToWm(0);
    // L2, L3, L4 go to LTM (L1 heaviest, L5 immune).
    memory_.at(ids_[0]).weight = 5;
    TransferTrigger trigger;
    trigger.max_wm_locations = 2;
    trigger.dictionary_size_at_start = memory_.dictionary().size();
    Transfer(trigger, {ids_[4]}, {}, memory_, map_.editor);
  }

  testing::SmallMap map_;
  Memory& memory_ = map_.memory;
  LongTermMemory* ltm_ = &map_.ltm;
  std::vector<LocationId> ids_;
};

TEST_F(RetrievalTest, AtMostTwoNearestNeighboursComeBack) {
  ASSERT_EQ(ltm_->size(), 3u);
  const RetrievalOutcome outcome = Retrieve(ids_[0], 2, 4, memory_, *ltm_);
  EXPECT_EQ(outcome.retrieved, (std::vector<LocationId>{ids_[1], ids_[2]}));  // L4 is farther
  EXPECT_TRUE(memory_.InWorkingMemory(ids_[1]));
  EXPECT_TRUE(memory_.InWorkingMemory(ids_[2]));
  EXPECT_TRUE(ltm_->Contains(ids_[3]));
  EXPECT_EQ(memory_.at(ids_[0]).neighbours, (std::set<LocationId>{ids_[1]}));
}

TEST_F(RetrievalTest, NothingToRetrieveWithoutHypothesis) {
  EXPECT_TRUE(Retrieve(kNoLocation, 2, 4, memory_, *ltm_).retrieved.empty());
}

TEST_F(RetrievalTest, WordsThatLeftTheDictionaryAreRematchedOrAddedBack) {
  // A newer word 20 at word 7's point: word 7 is the same feature and must be replaced by it.
  memory_.dictionary().Add({20}, (cv::Mat_<float>(1, 2) << 700, 0));
  const RetrievalOutcome outcome = Retrieve(ids_[2], 1, 4, memory_, *ltm_);  // L3 itself first
  ASSERT_EQ(outcome.retrieved, (std::vector<LocationId>{ids_[2]}));
  EXPECT_EQ(outcome.words_replaced, 1);
  EXPECT_EQ(outcome.words_added, 2);  // words 3 and 18 had no newer twin
  EXPECT_EQ(memory_.at(ids_[2]).signature.words, (std::vector<WordId>{3, 20, 18}));
  EXPECT_TRUE(memory_.dictionary().Contains(18));
  EXPECT_EQ(memory_.dictionary().References(20).count(ids_[2]), 1u);
  ltm_->Flush();
  // Every reference in LTM changed (L4 held word 7 too) and the old word is gone.
  EXPECT_FALSE(ltm_->LoadWord(7).has_value());
  const auto l4 = ltm_->Retrieve(ids_[3]);
  EXPECT_EQ(l4->signature.words, (std::vector<WordId>{4, 20}));
}

TEST_F(RetrievalTest, RenamesAreSeenBeforeTheyAreWritten) {
  memory_.dictionary().Add({20}, (cv::Mat_<float>(1, 2) << 700, 0));
  Retrieve(ids_[2], 1, 4, memory_, *ltm_);
  // No Flush: the rename may still be queued; L4 must come back with the new word anyway.
  EXPECT_EQ(ltm_->Retrieve(ids_[3])->signature.words, (std::vector<WordId>{4, 20}));
}

TEST(RetrievalClockTest, ExpectedCostIsTheMeanPlusTwiceTheDeviation) {
  RetrievalClock::Cost cost;
  EXPECT_FALSE(cost.measured);
  EXPECT_DOUBLE_EQ(cost.expected_ms(), 0);
  cost.Record(10);  // mean 10, deviation 10 / 2
  EXPECT_DOUBLE_EQ(cost.expected_ms(), 20);
  cost.Record(20);  // deviation 5 + (10 - 5) / 4 = 6.25, mean 10 + 10 / 8 = 11.25
  EXPECT_DOUBLE_EQ(cost.deviation_ms, 6.25);
  EXPECT_DOUBLE_EQ(cost.mean_ms, 11.25);
  EXPECT_DOUBLE_EQ(cost.expected_ms(), 23.75);
  cost.Record(2);  // deviation 6.25 + (9.25 - 6.25) / 4 = 7, mean 11.25 - 9.25 / 8 = 10.09375
  EXPECT_DOUBLE_EQ(cost.expected_ms(), 24.09375);
}

TEST(RetrievalClockTest, ARetrievalFitsWhenItsExpectedTimeEndsBeforeTheDeadline) {
  RetrievalClock::Cost cost;
  cost.Record(8);  // expected 8 + 2 x 4 = 16
  const auto at = [](double ms) { return [ms] { return ms; }; };
  EXPECT_TRUE(RetrievalClock(at(20), 40, &cost).Fits());   // 20 + 16 <= 40
  EXPECT_TRUE(RetrievalClock(at(24), 40, &cost).Fits());   // 40, just
  EXPECT_FALSE(RetrievalClock(at(25), 40, &cost).Fits());  // 41
  EXPECT_TRUE(RetrievalClock(at(1000), 0, &cost).Fits());  // no deadline (T_time off)
  EXPECT_TRUE(RetrievalClock().Fits());
  RetrievalClock::Cost unmeasured;
  EXPECT_TRUE(RetrievalClock(at(39), 40, &unmeasured).Fits());
  EXPECT_FALSE(RetrievalClock(at(41), 40, &unmeasured).Fits());  // already past it
}

TEST(RetrievalClockTest, DeferralsShrinkTheBoundAndEndInAProbe) {
  RetrievalClock::Cost cost;
  cost.Record(8);
  cost.Record(48);  // one slow retrieval: deviation 4 + (40 - 4) / 4 = 13, mean 13
  EXPECT_DOUBLE_EQ(cost.expected_ms(), 39);
  const auto at = [](double ms) { return [ms] { return ms; }; };
  EXPECT_FALSE(RetrievalClock(at(15), 47, &cost).Fits());  // 15 + 39 > 47
  cost.Deferred();  // deviation 13 x 3/4 = 9.75: 13 + 19.5 = 32.5
  EXPECT_DOUBLE_EQ(cost.expected_ms(), 32.5);
  EXPECT_FALSE(RetrievalClock(at(15), 47, &cost).Fits());
  cost.Deferred();  // deviation 7.3125: 27.625
  EXPECT_TRUE(RetrievalClock(at(15), 47, &cost).Fits());
  // A mean that stays high (slow retrievals in a row) is probed after kProbeAfter deferrals.
  RetrievalClock::Cost slow;
  slow.Record(40);
  for (int k = 1; k < RetrievalClock::Cost::kProbeAfter; ++k) slow.Deferred();
  EXPECT_FALSE(RetrievalClock(at(15), 47, &slow).Fits());
  slow.Deferred();
  EXPECT_TRUE(slow.ProbeDue());
  EXPECT_TRUE(RetrievalClock(at(15), 47, &slow).Fits());   // the probe
  EXPECT_FALSE(RetrievalClock(at(48), 47, &slow).Fits());  // not past the deadline
  slow.Record(10);
  EXPECT_FALSE(slow.ProbeDue());
}

TEST_F(RetrievalTest, RetrievalsThatDoNotFitAreDeferred) {
  RetrievalClock::Cost cost;
  const RetrievalOutcome late =
      Retrieve(ids_[0], 2, 4, memory_, *ltm_, RetrievalClock([] { return 45.0; }, 40, &cost));
  EXPECT_TRUE(late.retrieved.empty());
  EXPECT_EQ(late.deferred, 2);  // the two it would have retrieved
  EXPECT_EQ(ltm_->size(), 3u);
  EXPECT_FALSE(cost.measured);
  // With time left, the same two come back, and their time is measured.
  const RetrievalOutcome in_time =
      Retrieve(ids_[0], 2, 4, memory_, *ltm_, RetrievalClock([] { return 0.0; }, 1e9, &cost));
  EXPECT_EQ(in_time.retrieved, (std::vector<LocationId>{ids_[1], ids_[2]}));
  EXPECT_EQ(in_time.deferred, 0);
  EXPECT_TRUE(cost.measured);
}

}  // namespace
}  // namespace memloop
