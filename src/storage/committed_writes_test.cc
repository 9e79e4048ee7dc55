#include "storage/committed_writes.h"

#include <gtest/gtest.h>

namespace memloop {
namespace {

using Kind = CommittedWrites::Kind;

// Location 5 as read: words 1, 2, 1; a neighbour link to 4 and a loop-closure link to 9.
Location ReadCopy() {
  Location location;
  location.id = 5;
  location.signature.words = {1, 2, 1};
  location.neighbours = {4};
  location.loop_closures = {9};
  return location;
}

TEST(CommittedWritesTest, WritesAfterTheReadAreReplayedInOrder) {
  CommittedWrites writes(100);
  writes.Add(3, Kind::kRenameWord, 2, 7);  // seen by the read (since = 3)
  writes.Add(4, Kind::kRenameWord, 1, 8);  // 1 -> 8, then 8 -> 12: 1 -> 12
  writes.Add(5, Kind::kRenameWord, 8, 12);
  writes.Add(6, Kind::kRedirect, 4, 6);  // neighbour 4 absorbed by 6
  writes.Add(7, Kind::kRedirect, 9, 5);  // loop closure 9 absorbed by 5 itself: no self-link
  writes.Add(8, Kind::kLoopClosureLink, 5, 11);
  writes.Add(9, Kind::kNeighbourLink, 3, 5);  // another location's link: not 5's row
  writes.Add(10, Kind::kStore, 6, 0);         // another location stored
  Location location = ReadCopy();
  location.signature.words = {1, 7, 1};  // the rename at 3 is in the read already
  ASSERT_TRUE(writes.ReplaySince(3, location));
  EXPECT_EQ(location.signature.words, (std::vector<WordId>{12, 7, 12}));
  EXPECT_EQ(location.neighbours, (std::set<LocationId>{6}));
  EXPECT_EQ(location.loop_closures, (std::set<LocationId>{11}));
}

// The read may already hold writes committed after `since` (it began later): replaying them again
// changes nothing.
TEST(CommittedWritesTest, ReplayingWhatTheReadSawChangesNothing) {
  CommittedWrites writes(100);
  writes.Add(2, Kind::kRenameWord, 1, 8);
  writes.Add(3, Kind::kRedirect, 4, 6);
  writes.Add(4, Kind::kNeighbourLink, 5, 10);
  Location location = ReadCopy();
  location.signature.words = {8, 2, 8};
  location.neighbours = {6, 10};
  const Location expected = location;
  ASSERT_TRUE(writes.ReplaySince(1, location));
  EXPECT_EQ(location.signature.words, expected.signature.words);
  EXPECT_EQ(location.neighbours, expected.neighbours);
  EXPECT_EQ(location.loop_closures, expected.loop_closures);
}

TEST(CommittedWritesTest, AStoreOfTheLocationAfterTheReadMakesTheReadUseless) {
  CommittedWrites writes(100);
  writes.Add(2, Kind::kStore, 5, 0);
  Location location = ReadCopy();
  EXPECT_TRUE(writes.ReplaySince(2, location));  // the read holds that store already
  EXPECT_FALSE(writes.ReplaySince(1, location));
}

TEST(CommittedWritesTest, ReadsOlderThanTheWritesKeptCannotBeReplayed) {
  CommittedWrites writes(2);
  writes.Add(2, Kind::kNeighbourLink, 1, 2);
  writes.Add(4, Kind::kNeighbourLink, 1, 3);
  writes.Add(6, Kind::kNeighbourLink, 1, 4);  // the write at 2 goes
  EXPECT_EQ(writes.size(), 2u);
  Location location = ReadCopy();
  EXPECT_FALSE(writes.ReplaySince(1, location));  // the write at 2 is needed
  EXPECT_TRUE(writes.ReplaySince(2, location));   // writes 4 and 6 are kept
  EXPECT_TRUE(writes.ReplaySince(3, location));
}

}  // namespace
}  // namespace memloop
