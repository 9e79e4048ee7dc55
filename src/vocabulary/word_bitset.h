// A set of word ids as one bit per id: the checkpoint keeps which words' descriptors the file
// holds, the dictionary which words LTM holds too. Ids are dense (the dictionary gives them in
// order), so a rebuilt forest's hundreds of thousands of words are compared with a few bitwise
// operations per 64 ids instead of a hash look-up each (issue 9: 110 ms at 220,000 words, inside
// the iteration), and listing them costs a scan of the bits, not a walk through a tree (15 ms at
// 70,000 marked words, at every checkpoint).
#pragma once

#include <algorithm>
#include <cstdint>
#include <vector>

#include "memloop/types.h"

namespace memloop {

class WordBitset {
 public:
  // True when `id` was not in the set.
  bool Insert(WordId id) {
    const auto [block, bit] = Locate(id);
    if (block >= blocks_.size()) blocks_.resize(block + 1, 0);
    if (blocks_[block] & bit) return false;
    blocks_[block] |= bit;
    lowest_block_ = std::min(lowest_block_, block);
    return true;
  }
  // True when `id` was in the set.
  bool Erase(WordId id) {
    const auto [block, bit] = Locate(id);
    if (block >= blocks_.size() || !(blocks_[block] & bit)) return false;
    blocks_[block] &= ~bit;
    return true;
  }
  bool Contains(WordId id) const {
    const auto [block, bit] = Locate(id);
    return block < blocks_.size() && (blocks_[block] & bit);
  }
  void Clear() {
    blocks_.clear();
    lowest_block_ = 0;
  }
  // Moves the ids of this set that `other` lacks into `moved` (removed from this set).
  void MoveAbsentFrom(const WordBitset& other, WordBitset& moved) {
    for (size_t block = 0; block < blocks_.size(); ++block) {
      const uint64_t absent =
          blocks_[block] & ~(block < other.blocks_.size() ? other.blocks_[block] : 0);
      if (absent == 0) continue;
      blocks_[block] &= ~absent;
      if (block >= moved.blocks_.size()) moved.blocks_.resize(block + 1, 0);
      moved.blocks_[block] |= absent;
      moved.lowest_block_ = std::min(moved.lowest_block_, block);
    }
  }
  // Every id in the set, ascending.
  std::vector<WordId> Ids() const {
    std::vector<WordId> ids;
    if (lowest_block_ < blocks_.size()) {
      AppendIds(lowest_block_, blocks_.data() + lowest_block_, blocks_.data() + blocks_.size(),
                ids);
    }
    return ids;
  }
  // The set in chunks of kChunkIds ids, to be stored in pieces: the checkpoint writes only the
  // chunks whose ids changed. 4,096 ids (512 bytes): after 50,000 images the ids span 10 million,
  // and a location transferred back to LTM marks words all over them (issue 39: chunks of 65,536
  // ids, 8 KB each, made 92 KB of marks a checkpoint). `chunk_ids` (a multiple of 64) reads chunks
  // of another size: maps of format 4-5 hold chunks of 65,536 ids.
  static constexpr size_t kChunkIds = 4096;
  static size_t ChunkOf(WordId id) { return static_cast<size_t>(id) / kChunkIds; }
  size_t chunk_count() const { return (blocks_.size() + kChunkBlocks - 1) / kChunkBlocks; }
  // Chunk `chunk` as 64-bit blocks (block k: ids chunk * chunk_ids + 64 k + bit), without its
  // trailing empty blocks: an empty chunk has none.
  std::vector<uint64_t> ChunkBlocks(size_t chunk, size_t chunk_ids = kChunkIds) const {
    const size_t chunk_blocks = chunk_ids / 64;
    const size_t begin = std::min(chunk * chunk_blocks, blocks_.size());
    size_t end = std::min(begin + chunk_blocks, blocks_.size());
    while (end > begin && blocks_[end - 1] == 0) --end;
    return std::vector<uint64_t>(blocks_.begin() + begin, blocks_.begin() + end);
  }
  // The ids of chunk `chunk` given as ChunkBlocks gives it, appended to `ids` in ascending order.
  static void AppendChunkIds(size_t chunk, const std::vector<uint64_t>& blocks,
                             std::vector<WordId>& ids, size_t chunk_ids = kChunkIds) {
    AppendIds(chunk * (chunk_ids / 64), blocks.data(), blocks.data() + blocks.size(), ids);
  }
  // Removes and returns up to `count` ids, smallest first.
  std::vector<WordId> TakeSmallest(size_t count) {
    std::vector<WordId> taken;
    for (size_t block = lowest_block_; block < blocks_.size() && taken.size() < count; ++block) {
      while (blocks_[block] != 0 && taken.size() < count) {
        const int bit = __builtin_ctzll(blocks_[block]);
        taken.push_back(static_cast<WordId>(block * 64 + bit));
        blocks_[block] &= blocks_[block] - 1;
      }
      lowest_block_ = block;
    }
    return taken;
  }

 private:
  static std::pair<size_t, uint64_t> Locate(WordId id) {
    const auto index = static_cast<size_t>(id);
    return {index / 64, uint64_t{1} << (index % 64)};
  }

  static constexpr size_t kChunkBlocks = kChunkIds / 64;

  // The ids of blocks [begin, end), the first of which is block number `first_block`.
  static void AppendIds(size_t first_block, const uint64_t* begin, const uint64_t* end,
                        std::vector<WordId>& ids) {
    for (const uint64_t* block = begin; block != end; ++block) {
      const size_t first_id = (first_block + static_cast<size_t>(block - begin)) * 64;
      for (uint64_t bits = *block; bits != 0; bits &= bits - 1) {
        ids.push_back(static_cast<WordId>(first_id + __builtin_ctzll(bits)));
      }
    }
  }

  std::vector<uint64_t> blocks_;
  size_t lowest_block_ = 0;  // no id below this block is in the set
};

}  // namespace memloop
