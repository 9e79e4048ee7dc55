#include "storage/ltm_read_ahead.h"

#include <gtest/gtest.h>

#include <limits>

#include "small_memory.h"
#include "storage/long_term_memory.h"
#include "temp_dir.h"

namespace memloop {
namespace {

constexpr double kForever = std::numeric_limits<double>::infinity();

// A map whose LTM holds locations 1-3, each with a word of its own (in the file).
std::string MapWithThreeLocations(testing::TempDir& dir) {
  const std::string path = dir.File("map.db");
  LongTermMemory ltm(path);
  for (LocationId id = 1; id <= 3; ++id) {
    Location location;
    location.id = id;
    location.signature = testing::MakeSignature({static_cast<WordId>(10 + id)});
    location.images = {static_cast<ImageIndex>(id)};
    ltm.Store(location);
    ltm.StoreWord(10 + id, (cv::Mat_<float>(1, 2) << 1.0f * id, 0.0f));
  }
  ltm.Flush();
  return path;
}

TEST(LtmReadAheadTest, ReadsWhatIsRequestedAndForgetsItOnceWaitedFor) {
  testing::TempDir dir;
  LtmReadAhead read_ahead(MapWithThreeLocations(dir));
  read_ahead.Request({1, 2});
  EXPECT_TRUE(read_ahead.WaitRead(2, kForever));
  EXPECT_TRUE(read_ahead.WaitRead(1, kForever));
  EXPECT_EQ(read_ahead.rows_read(), 2);
  // Waited for: forgotten, so asking again reads the rows again (they may have been rewritten).
  EXPECT_TRUE(read_ahead.WaitRead(1, kForever));
  EXPECT_EQ(read_ahead.rows_read(), 3);
}

// A held reader stands for a disk that does not answer within the iteration: the wait gives up at
// once, and the request stays queued until the reader goes on.
TEST(LtmReadAheadTest, AnUnreadLocationIsNotWaitedForBeyondTheTimeout) {
  testing::TempDir dir;
  LtmReadAhead read_ahead(MapWithThreeLocations(dir));
  read_ahead.SetHeld(true);
  EXPECT_FALSE(read_ahead.WaitRead(3, kForever));
  EXPECT_EQ(read_ahead.queued(), 1u);
  EXPECT_EQ(read_ahead.rows_read(), 0);
  read_ahead.SetHeld(false);
  EXPECT_TRUE(read_ahead.WaitRead(3, kForever));
  EXPECT_EQ(read_ahead.rows_read(), 1);
  EXPECT_EQ(read_ahead.queued(), 0u);
}

TEST(LtmReadAheadTest, RequestsBeyondTheQueueBoundDropTheOldest) {
  testing::TempDir dir;
  LtmReadAhead read_ahead(MapWithThreeLocations(dir));
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

// Nothing to read (no such location, no map file) counts as read: the detector's own read is the
// one that finds and reports a problem.
TEST(LtmReadAheadTest, WhatCannotBeReadCountsAsRead) {
  testing::TempDir dir;
  LtmReadAhead read_ahead(MapWithThreeLocations(dir));
  EXPECT_TRUE(read_ahead.WaitRead(99, kForever));
  LtmReadAhead no_map(dir.File("absent.db"));
  EXPECT_TRUE(no_map.WaitRead(1, kForever));
  EXPECT_EQ(no_map.rows_read(), 1);
}

}  // namespace
}  // namespace memloop
