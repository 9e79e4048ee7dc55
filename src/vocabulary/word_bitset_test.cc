#include "vocabulary/word_bitset.h"

#include <gtest/gtest.h>

namespace memloop {
namespace {

TEST(WordBitsetTest, InsertEraseContainAcrossBlocks) {
  WordBitset set;
  EXPECT_TRUE(set.Insert(3));
  EXPECT_FALSE(set.Insert(3));   // already there
  EXPECT_TRUE(set.Insert(200));  // block 3
  EXPECT_TRUE(set.Contains(200));
  EXPECT_FALSE(set.Contains(199));
  EXPECT_FALSE(set.Contains(100000));  // beyond the blocks: absent, not an error
  EXPECT_TRUE(set.Erase(3));
  EXPECT_FALSE(set.Erase(3));
  EXPECT_FALSE(set.Contains(3));
}

// {1, 64, 65, 130} against {64, 130}: 1 and 65 move (ids on both sides of a block boundary).
TEST(WordBitsetTest, MovesTheIdsTheOtherLacks) {
  WordBitset written;
  for (WordId id : {1, 64, 65, 130}) written.Insert(id);
  WordBitset named;
  named.Insert(64);
  named.Insert(130);
  WordBitset forgotten;
  forgotten.Insert(500);
  written.MoveAbsentFrom(named, forgotten);
  EXPECT_FALSE(written.Contains(1));
  EXPECT_TRUE(written.Contains(64));
  EXPECT_FALSE(written.Contains(65));
  EXPECT_TRUE(written.Contains(130));
  EXPECT_EQ(forgotten.TakeSmallest(10), (std::vector<WordId>{1, 65, 500}));
  EXPECT_TRUE(forgotten.TakeSmallest(10).empty());
}

TEST(WordBitsetTest, TakesTheSmallestFirstAFewAtATime) {
  WordBitset set;
  for (WordId id : {700, 5, 64, 63}) set.Insert(id);
  EXPECT_EQ(set.TakeSmallest(2), (std::vector<WordId>{5, 63}));
  set.Insert(6);  // below where the last take stopped: found again
  EXPECT_EQ(set.TakeSmallest(2), (std::vector<WordId>{6, 64}));
  EXPECT_EQ(set.TakeSmallest(5), (std::vector<WordId>{700}));
}

TEST(WordBitsetTest, ListsItsIdsInOrder) {
  WordBitset set;
  EXPECT_TRUE(set.Ids().empty());
  for (WordId id : {700, 5, 64, 63, 0}) set.Insert(id);
  set.Erase(64);
  EXPECT_EQ(set.Ids(), (std::vector<WordId>{0, 5, 63, 700}));
  EXPECT_EQ(set.Ids().size(), 4u);  // listing takes nothing out
}

}  // namespace
}  // namespace memloop
