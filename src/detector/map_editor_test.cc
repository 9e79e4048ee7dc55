#include "detector/map_editor.h"

#include <gtest/gtest.h>

#include "small_map.h"

namespace memloop {
namespace {

// L1 - L2 - L3 - L4 in WM, then L1 transferred: L2's neighbour L1 is in LTM.
class MapEditorTest : public ::testing::Test {
 protected:
  MapEditorTest() {
    ids_ = testing::AddChain(map_.memory, {{1}, {2}, {3}, {4}, {5}});
    map_.memory.MoveStmOverflowToWm(0);
    map_.editor.TransferToLtm(ids_[0]);
  }
  testing::SmallMap map_;
  std::vector<LocationId> ids_;
};

TEST_F(MapEditorTest, TransferKeepsLinksBothWaysAndWordsOfLtm) {
  EXPECT_TRUE(map_.ltm.Contains(ids_[0]));
  EXPECT_FALSE(map_.memory.Contains(ids_[0]));
  EXPECT_EQ(map_.ltm.Peek(ids_[0])->neighbours, (std::set<LocationId>{ids_[1]}));
  EXPECT_TRUE(map_.memory.at(ids_[1]).neighbours.count(ids_[0]));
  EXPECT_FALSE(map_.memory.dictionary().Contains(1));
  EXPECT_TRUE(map_.ltm.LoadWord(1).has_value());
  EXPECT_TRUE(map_.CheckConsistencyEmpty());
}

// A loop closure gives L_t the links of L_i; one of them reaches LTM, which must link back.
TEST_F(MapEditorTest, LoopClosureLinksReachingLtmAreWrittenThereToo) {
  map_.editor.LinkLoopClosure(ids_[4], ids_[1]);  // L5 closes a loop with L2
  const Location& t = map_.memory.at(ids_[4]);
  EXPECT_EQ(t.neighbours, (std::set<LocationId>{ids_[0], ids_[2], ids_[3]}));
  EXPECT_EQ(t.loop_closures, (std::set<LocationId>{ids_[1]}));
  EXPECT_EQ(map_.ltm.Peek(ids_[0])->neighbours, (std::set<LocationId>{ids_[1], ids_[4]}));
  EXPECT_TRUE(map_.CheckConsistencyEmpty());
  ASSERT_EQ(map_.editor.past_matches().size(), 1u);
  EXPECT_EQ(map_.editor.past_matches()[0].matched, ids_[1]);
}

// A merged location's LTM links are redirected to the survivor.
TEST_F(MapEditorTest, MergeRedirectsLtmLinksToTheSurvivor) {
  map_.editor.Merge(ids_[3], ids_[1]);  // L2 into L4
  EXPECT_FALSE(map_.memory.Contains(ids_[1]));
  EXPECT_EQ(map_.ltm.Peek(ids_[0])->neighbours, (std::set<LocationId>{ids_[3]}));
  EXPECT_EQ(map_.memory.at(ids_[3]).images, (std::vector<ImageIndex>{3, 1}));
  EXPECT_FALSE(map_.memory.dictionary().Contains(2));  // L2's word had no other reference
  EXPECT_TRUE(map_.CheckConsistencyEmpty());
}

// L3 matched L2, then L5 matched L3. L3 is absorbed into L5 while L2 is still kept (near the
// highest hypothesis): L2's pending match must follow L3 to L5, not be lost.
TEST_F(MapEditorTest, PastMatchFollowsItsMatcherWhenTheMatcherIsAbsorbed) {
  map_.editor.LinkLoopClosure(ids_[2], ids_[1]);
  map_.editor.LinkLoopClosure(ids_[4], ids_[2]);
  map_.editor.AbsorbPastMatches({ids_[1]});
  EXPECT_FALSE(map_.memory.Contains(ids_[2]));
  ASSERT_EQ(map_.editor.past_matches().size(), 1u);
  EXPECT_EQ(map_.editor.past_matches()[0].matched, ids_[1]);
  EXPECT_EQ(map_.editor.past_matches()[0].matcher, ids_[4]);
  map_.editor.AbsorbPastMatches({});
  EXPECT_FALSE(map_.memory.Contains(ids_[1]));
  EXPECT_TRUE(map_.editor.past_matches().empty());
  EXPECT_EQ(map_.memory.at(ids_[4]).images, (std::vector<ImageIndex>{4, 2, 1}));
  EXPECT_TRUE(map_.CheckConsistencyEmpty());
}

TEST_F(MapEditorTest, ConsistencyCheckFindsAOneWayLink) {
  map_.memory.at(ids_[4]).loop_closures.insert(ids_[0]);  // not written to LTM
  const auto problems =
      CheckConsistency(map_.memory, map_.ltm, map_.filter, map_.editor.past_matches());
  ASSERT_FALSE(problems.empty());
  bool found = false;
  for (const auto& line : problems)
    found |= line.find("one-way loop-closure link") != std::string::npos;
  EXPECT_TRUE(found);
}

}  // namespace
}  // namespace memloop
