#include "detector/retrieval.h"

#include <gtest/gtest.h>

#include "detector/retrieval_step.h"
#include "small_map.h"

namespace memloop {
namespace {

class RetrievalTest : public ::testing::Test {
 protected:
  RetrievalTest() {
    // A chain L1 .. L5; L3 and L4 share word 7; L3 also has word 18. L2, L3, L4 go to LTM.
    ids_ = map_.ChainWithMiddleInLtm({{1}, {2}, {3, 7, 18}, {4, 7}, {5}});
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

TEST_F(RetrievalTest, RetrievalsThatDoNotFitAreDeferred) {
  StepCost cost;
  RetrievalTime late_time;
  late_time.location = StepDeadline([] { return 45.0; }, 40, &cost);
  const RetrievalOutcome late = Retrieve(ids_[0], 2, 4, memory_, *ltm_, late_time);
  EXPECT_TRUE(late.retrieved.empty());
  EXPECT_EQ(late.deferred, 2);  // the two it would have retrieved
  EXPECT_EQ(ltm_->size(), 3u);
  EXPECT_FALSE(cost.measured());
  // With time left, the same two come back, and their time is measured.
  RetrievalTime time_left;
  time_left.location = StepDeadline([] { return 0.0; }, 1e9, &cost);
  const RetrievalOutcome in_time = Retrieve(ids_[0], 2, 4, memory_, *ltm_, time_left);
  EXPECT_EQ(in_time.retrieved, (std::vector<LocationId>{ids_[1], ids_[2]}));
  EXPECT_EQ(in_time.deferred, 0);
  EXPECT_TRUE(cost.measured());
}

// Read ahead (T_time on): a location whose rows are not read in time is deferred like one that does
// not fit, and stays requested; once read, the same locations come back as without read-ahead.
TEST_F(RetrievalTest, LocationsWhoseRowsAreNotReadYetAreDeferred) {
  ltm_->Flush();  // the reader sees the file only
  LtmReadAhead read_ahead(*ltm_);
  read_ahead.SetHeld(true);  // a disk that does not answer within the iteration
  StepCost cost;
  RetrievalTime time;
  time.location = StepDeadline([] { return 0.0; }, 1e9, &cost);
  time.read_ahead = &read_ahead;
  const RetrievalOutcome unread = Retrieve(ids_[0], 2, 4, memory_, *ltm_, time);
  EXPECT_TRUE(unread.retrieved.empty());
  EXPECT_EQ(unread.deferred, 2);
  EXPECT_EQ(unread.unread, 2);
  EXPECT_EQ(read_ahead.queued(), 3u);  // the whole neighbourhood in LTM, L4 too
  EXPECT_EQ(ltm_->size(), 3u);
  read_ahead.SetHeld(false);
  const RetrievalOutcome read = Retrieve(ids_[0], 2, 4, memory_, *ltm_, time);
  EXPECT_EQ(read.retrieved, (std::vector<LocationId>{ids_[1], ids_[2]}));
  EXPECT_EQ(read.deferred, 0);
}

// Only what this iteration and the next retrieve is read ahead (2 x max_retrieved, nearest
// first), not the whole neighbourhood: one at a time, L2 and L3 are requested, not L4.
TEST_F(RetrievalTest, OnlyTheNextTwoIterationsAreReadAhead) {
  ltm_->Flush();
  LtmReadAhead read_ahead(*ltm_);
  read_ahead.SetHeld(true);
  StepCost cost;
  RetrievalTime time;
  time.location = StepDeadline([] { return 0.0; }, 1e9, &cost);
  time.read_ahead = &read_ahead;
  const RetrievalOutcome unread = Retrieve(ids_[0], 1, 4, memory_, *ltm_, time);
  EXPECT_EQ(unread.deferred, 1);
  EXPECT_EQ(read_ahead.queued(), 2u);
  read_ahead.SetHeld(false);
  EXPECT_EQ(Retrieve(ids_[0], 1, 4, memory_, *ltm_, time).retrieved,
            (std::vector<LocationId>{ids_[1]}));
  EXPECT_EQ(Retrieve(ids_[0], 1, 4, memory_, *ltm_, time).retrieved,
            (std::vector<LocationId>{ids_[2]}));
  EXPECT_EQ(Retrieve(ids_[0], 1, 4, memory_, *ltm_, time).retrieved,
            (std::vector<LocationId>{ids_[3]}));  // L4, read when needed
}

// WorthRetrieving (memory.retrieval_min_value 0.02, memory.retrieval_strong_value 0.05): with
// T_time 20 ms, a hypothesis of 0.03 is retrieved for while 7 + 3 ms <= 10 ms (half of T_time), not
// at 8 + 3 ms; one of 0.05 whatever the time; under 0.02 never; with T_time off, from 0.02 on.
TEST(WorthRetrievingTest, AWeakHypothesisOnlyInTheFirstHalfOfTTime) {
  MemoryOptions memory;
  memory.retrieval_min_value = 0.02;
  memory.retrieval_strong_value = 0.05;
  memory.time_limit_ms = 20;
  EXPECT_TRUE(WorthRetrieving(memory, 0.03, 7, 3));
  EXPECT_FALSE(WorthRetrieving(memory, 0.03, 8, 3));
  EXPECT_TRUE(WorthRetrieving(memory, 0.05, 19, 3));
  EXPECT_FALSE(WorthRetrieving(memory, 0.019, 0, 0));
  memory.time_limit_ms = 0;
  EXPECT_TRUE(WorthRetrieving(memory, 0.02, 1000, 3));
  memory.time_limit_ms = 20;
  memory.retrieval_strong_value = 0;  // off: the paper's rule with memloop's floor alone
  EXPECT_TRUE(WorthRetrieving(memory, 0.03, 19, 3));
}

}  // namespace
}  // namespace memloop
