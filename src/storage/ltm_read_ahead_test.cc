#include "storage/ltm_read_ahead.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <limits>

#include "small_memory.h"
#include "storage/long_term_memory.h"
#include "temp_dir.h"

namespace memloop {
namespace {

constexpr double kForever = std::numeric_limits<double>::infinity();

// A map whose LTM holds locations 1-3, each with a word of its own (in the file).
class LtmReadAheadTest : public ::testing::Test {
 protected:
  LtmReadAheadTest() {
    for (LocationId id = 1; id <= 3; ++id) {
      Location location;
      location.id = id;
      location.signature = testing::MakeSignature({static_cast<WordId>(10 + id)});
      location.images = {static_cast<ImageIndex>(id)};
      ltm_.Store(location);
      ltm_.StoreWord(10 + id, (cv::Mat_<float>(1, 2) << 1.0f * id, 0.0f));
    }
    ltm_.Flush();
  }

  testing::TempDir dir_;
  LongTermMemory ltm_{dir_.File("map.db")};
};

TEST_F(LtmReadAheadTest, ReadsWhatIsRequestedAndForgetsItOnceHandedOver) {
  LtmReadAhead read_ahead(ltm_);
  read_ahead.Request({1, 2});
  EXPECT_TRUE(read_ahead.WaitRead(2, kForever));
  const std::optional<PrefetchedRows> rows = read_ahead.WaitRead(1, kForever);
  ASSERT_TRUE(rows && rows->location);
  EXPECT_EQ(rows->location->signature.words, (std::vector<WordId>{11}));
  EXPECT_EQ(rows->location->images, (std::vector<ImageIndex>{1}));
  ASSERT_EQ(rows->words.count(11), 1u);  // its word's descriptor row: (1, 0) as two floats
  EXPECT_EQ(rows->words.at(11), ltm_.LoadWord(11));
  EXPECT_EQ(rows->committed, ltm_.committed_sequence());  // nothing was written since
  EXPECT_EQ(read_ahead.rows_read(), 2);
  EXPECT_EQ(read_ahead.kept_bytes(), 0u);
  // Handed over: forgotten, so asking again reads the rows again (they may have been rewritten).
  EXPECT_TRUE(read_ahead.WaitRead(1, kForever));
  EXPECT_EQ(read_ahead.rows_read(), 3);
}

// Rows read and never asked for are dropped oldest first beyond the bound, and read again when
// asked for.
TEST_F(LtmReadAheadTest, RowsKeptBeyondTheBoundDropTheOldest) {
  // Requests are read in order: once 2 is read, so is 1.
  LtmReadAhead unbounded(ltm_);
  unbounded.Request({1, 2});
  EXPECT_TRUE(unbounded.WaitRead(2, kForever));
  const size_t one = unbounded.kept_bytes();  // location 1's; 2 and 3 hold as many
  ASSERT_GT(one, 0u);
  LtmReadAhead read_ahead(ltm_, 2 * one + one / 2);  // room for two locations' rows
  read_ahead.Request({1, 2, 3});
  EXPECT_TRUE(read_ahead.WaitRead(3, kForever));  // 1 was dropped when 3 came
  EXPECT_EQ(read_ahead.rows_read(), 3);
  EXPECT_EQ(read_ahead.kept_bytes(), one);
  EXPECT_TRUE(read_ahead.WaitRead(2, kForever));  // kept: not read again
  EXPECT_EQ(read_ahead.rows_read(), 3);
  EXPECT_TRUE(read_ahead.WaitRead(1, kForever));  // dropped: read again
  EXPECT_EQ(read_ahead.rows_read(), 4);
}

// A held reader stands for a disk that does not answer within the iteration: the wait gives up at
// once, and the request stays queued until the reader goes on.
TEST_F(LtmReadAheadTest, AnUnreadLocationIsNotWaitedForBeyondTheTimeout) {
  LtmReadAhead read_ahead(ltm_);
  read_ahead.SetHeld(true);
  EXPECT_FALSE(read_ahead.WaitRead(3, kForever));
  EXPECT_EQ(read_ahead.queued(), 1u);
  EXPECT_EQ(read_ahead.rows_read(), 0);
  read_ahead.SetHeld(false);
  EXPECT_TRUE(read_ahead.WaitRead(3, kForever));
  EXPECT_EQ(read_ahead.rows_read(), 1);
  EXPECT_EQ(read_ahead.queued(), 0u);
}

TEST_F(LtmReadAheadTest, RequestsBeyondTheQueueBoundDropTheOldest) {
  LtmReadAhead read_ahead(ltm_);
  read_ahead.SetHeld(true);
  std::vector<LocationId> ids;
  for (LocationId id = 1; id <= static_cast<LocationId>(LtmReadAhead::kMaxQueued) + 10; ++id) {
    ids.push_back(id);
  }
  read_ahead.Request(ids);
  read_ahead.Request({ids.back(), ids[20]});  // queued already: no second place
  EXPECT_EQ(read_ahead.queued(), LtmReadAhead::kMaxQueued);
  read_ahead.SetHeld(false);
  EXPECT_TRUE(read_ahead.WaitRead(ids.back(), kForever));
}

// Nothing to read (no such location, no map file) counts as read, without a location: the
// detector's own read is the one that finds and reports a problem.
TEST_F(LtmReadAheadTest, WhatCannotBeReadCountsAsRead) {
  LtmReadAhead read_ahead(ltm_);
  const std::optional<PrefetchedRows> absent = read_ahead.WaitRead(99, kForever);
  ASSERT_TRUE(absent);
  EXPECT_FALSE(absent->location);
  const std::string removed = dir_.File("removed.db");
  LongTermMemory other(removed);
  ASSERT_EQ(std::remove(removed.c_str()), 0);
  LtmReadAhead no_map(other);
  const std::optional<PrefetchedRows> unopened = no_map.WaitRead(1, kForever);
  ASSERT_TRUE(unopened);
  EXPECT_FALSE(unopened->location);
  EXPECT_EQ(no_map.rows_read(), 1);
}

}  // namespace
}  // namespace memloop
