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

// Chunks of 4,096 ids: id 4,096 + 64 + 3 is chunk 1, block 1, bit 3.
TEST(WordBitsetTest, ChunksRoundTripTheirIds) {
  WordBitset set;
  EXPECT_EQ(set.chunk_count(), 0u);
  for (WordId id : {5, 64, 4096 + 67, 3 * 4096}) set.Insert(id);
  ASSERT_EQ(set.chunk_count(), 4u);
  EXPECT_EQ(set.ChunkBlocks(0), (std::vector<uint64_t>{uint64_t{1} << 5, 1}));
  EXPECT_EQ(set.ChunkBlocks(1), (std::vector<uint64_t>{0, uint64_t{1} << 3}));
  EXPECT_TRUE(set.ChunkBlocks(2).empty());  // no id in it: no block
  EXPECT_EQ(set.ChunkBlocks(3), (std::vector<uint64_t>{1}));
  EXPECT_TRUE(set.ChunkBlocks(9).empty());  // past the end
  set.Erase(3 * 4096);
  EXPECT_TRUE(set.ChunkBlocks(3).empty());  // trailing empty blocks are left out
  std::vector<WordId> ids;
  for (size_t chunk = 0; chunk < set.chunk_count(); ++chunk) {
    WordBitset::AppendChunkIds(chunk, set.ChunkBlocks(chunk), ids);
  }
  EXPECT_EQ(ids, set.Ids());
  EXPECT_EQ(ids, (std::vector<WordId>{5, 64, 4096 + 67}));
  EXPECT_EQ(WordBitset::ChunkOf(4095), 0u);
  EXPECT_EQ(WordBitset::ChunkOf(4096), 1u);
}

// Chunks of another size (maps of format 4-5: 65,536 ids): id 65,536 + 128 + 1 is that size's
// chunk 1, block 2, bit 1.
TEST(WordBitsetTest, ChunksOfAnotherSizeRoundTripTheirIds) {
  WordBitset set;
  for (WordId id : {4100, 65536 + 129}) set.Insert(id);
  const std::vector<uint64_t> first = set.ChunkBlocks(0, 65536);
  ASSERT_EQ(first.size(), 65u);  // up to block 64 (ids 4,096-4,159)
  EXPECT_EQ(first[64], uint64_t{1} << 4);
  EXPECT_EQ(set.ChunkBlocks(1, 65536), (std::vector<uint64_t>{0, 0, uint64_t{1} << 1}));
  std::vector<WordId> ids;
  WordBitset::AppendChunkIds(0, first, ids, 65536);
  WordBitset::AppendChunkIds(1, set.ChunkBlocks(1, 65536), ids, 65536);
  EXPECT_EQ(ids, (std::vector<WordId>{4100, 65536 + 129}));
}

}  // namespace
}  // namespace memloop
