#include "detector/rehearsal.h"

#include <gtest/gtest.h>

#include "small_map.h"

namespace memloop {
namespace {

TEST(RehearsalTest, MergesTheMostRecentSimilarLocationAsThePaperSays) {
  testing::SmallMap map;
  Memory& memory = map.memory;
  // L1 {1,2,3}; L2 {4,5,6}; L_t {1,2,4,5,7}: s(L_t, L2) = 2/5 = 0.4 > 0.2, checked first.
  const auto ids = testing::AddChain(memory, {{1, 2, 3}, {4, 5, 6}, {1, 2, 4, 5, 7}});
  memory.at(ids[1]).weight = 3;
  const RehearsalOutcome outcome = Rehearse(ids[2], 0.2, memory, map.editor);

  EXPECT_EQ(outcome.merged_id, ids[1]);
  EXPECT_DOUBLE_EQ(outcome.similarity, 0.4);
  const Location& merged = memory.at(ids[2]);
  EXPECT_EQ(merged.signature.words, (std::vector<WordId>{4, 5, 6}));  // z_c copied into z_t
  EXPECT_EQ(merged.weight, 0 + 3 + 1);                                // weight_c + 1
  EXPECT_EQ(merged.neighbours, (std::set<LocationId>{ids[0]}));       // L_c's links
  EXPECT_EQ(memory.at(ids[0]).neighbours, (std::set<LocationId>{ids[2]}));
  EXPECT_EQ(merged.images, (std::vector<ImageIndex>{2, 1}));
  EXPECT_FALSE(memory.Contains(ids[1]));  // L_c deleted from STM
  EXPECT_EQ(memory.stm(), (std::deque<LocationId>{ids[0], ids[2]}));
  // Word 7 was only in z_t: it left the dictionary. Words 1, 2 are still L1's.
  EXPECT_FALSE(memory.dictionary().Contains(7));
  EXPECT_TRUE(memory.dictionary().Contains(1));
  EXPECT_TRUE(map.CheckConsistencyEmpty());
  EXPECT_EQ(memory.dictionary().References(4).at(ids[2]), 1);
}

TEST(RehearsalTest, NothingMergedAtOrBelowTheThreshold) {
  testing::SmallMap map;
  Memory& memory = map.memory;
  // s(L_t, L1) = 1/5 = 0.2, not above T_rehearsal = 0.2.
  const auto ids = testing::AddChain(memory, {{1, 2, 3, 4, 5}, {1, 6, 7, 8, 9}});
  const RehearsalOutcome outcome = Rehearse(ids[1], 0.2, memory, map.editor);
  EXPECT_EQ(outcome.merged_id, kNoLocation);
  EXPECT_EQ(memory.size(), 2u);
  EXPECT_EQ(memory.at(ids[1]).weight, 0);
}

TEST(RehearsalTest, WorkingMemoryIsNotRehearsed) {
  testing::SmallMap map;
  const auto ids = testing::AddChain(map.memory, {{1, 2, 3}, {1, 2, 3}});
  map.memory.MoveStmOverflowToWm(1);  // L1 to WM: identical, but not in STM
  EXPECT_EQ(Rehearse(ids[1], 0.2, map.memory, map.editor).merged_id, kNoLocation);
}

}  // namespace
}  // namespace memloop
