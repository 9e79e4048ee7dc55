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
  EXPECT_EQ(merged.signature.words, (std::vector<WordId>{4, 5, 6}));        // z_c copied into z_t
  EXPECT_EQ(outcome.replaced_words, (std::vector<WordId>{1, 2, 4, 5, 7}));  // the image's own
  EXPECT_EQ(merged.weight, 0 + 3 + 1);                                      // weight_c + 1
  EXPECT_EQ(merged.neighbours, (std::set<LocationId>{ids[0]}));             // L_c's links
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

// memory.rehearsal_most_similar (the paper's 2011 code): every STM location is compared.
TEST(RehearsalTest, MostSimilarMergesTheBestNotTheNewestAboveTheThreshold) {
  testing::SmallMap map;
  Memory& memory = map.memory;
  // L1 {1,2,3,4}; L2 {5,6,8,9}; L_t {1,2,3,5,7}: s(L_t, L1) = 3/5 = 0.6, s(L_t, L2) = 1/5 = 0.2.
  // L3 {1,5,10,11}: s(L_t, L3) = 2/5 = 0.4, the newest above 0.2, is what the text merges.
  const auto ids =
      testing::AddChain(memory, {{1, 2, 3, 4}, {5, 6, 8, 9}, {1, 5, 10, 11}, {1, 2, 3, 5, 7}});
  testing::SmallMap text_map;
  const auto text_ids = testing::AddChain(
      text_map.memory, {{1, 2, 3, 4}, {5, 6, 8, 9}, {1, 5, 10, 11}, {1, 2, 3, 5, 7}});
  EXPECT_EQ(Rehearse(text_ids[3], 0.2, text_map.memory, text_map.editor).merged_id, text_ids[2]);

  const RehearsalOutcome outcome = Rehearse(ids[3], 0.2, memory, map.editor, true);
  EXPECT_EQ(outcome.merged_id, ids[0]);
  EXPECT_DOUBLE_EQ(outcome.similarity, 0.6);
  EXPECT_EQ(memory.at(ids[3]).signature.words, (std::vector<WordId>{1, 2, 3, 4}));
  EXPECT_FALSE(memory.Contains(ids[0]));
  EXPECT_TRUE(map.CheckConsistencyEmpty());
}

TEST(RehearsalTest, NothingMergedAtOrBelowTheThreshold) {
  testing::SmallMap map;
  Memory& memory = map.memory;
  // s(L_t, L1) = 1/5 = 0.2, not above T_rehearsal = 0.2.
  const auto ids = testing::AddChain(memory, {{1, 2, 3, 4, 5}, {1, 6, 7, 8, 9}});
  const RehearsalOutcome outcome = Rehearse(ids[1], 0.2, memory, map.editor);
  EXPECT_EQ(outcome.merged_id, kNoLocation);
  EXPECT_TRUE(outcome.replaced_words.empty());
  EXPECT_EQ(Rehearse(ids[1], 0.2, memory, map.editor, true).merged_id, kNoLocation);
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
