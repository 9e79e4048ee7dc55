#include "vocabulary/point_map.h"

#include <gtest/gtest.h>

#include <utility>
#include <vector>

namespace memloop {
namespace {

std::vector<std::pair<WordId, size_t>> Live(const PointMap& map) {
  std::vector<std::pair<WordId, size_t>> live;
  map.ForEachLive([&](WordId word, size_t point) { live.emplace_back(word, point); });
  return live;
}

TEST(PointMapTest, MapsBothWaysAndForgetsErasedWords) {
  PointMap map;
  map.Set(7, 0);
  map.Set(2, 1);
  map.Set(40, 2);
  EXPECT_EQ(map.size(), 3u);
  EXPECT_EQ(map.PointOf(2), 1u);
  EXPECT_EQ(map.WordOf(2), 40);
  map.Erase(7);
  map.Erase(7);  // not live: nothing
  EXPECT_EQ(map.size(), 2u);
  EXPECT_FALSE(map.Contains(7));
  EXPECT_EQ(map.PointOf(7), PointMap::kNoPoint);
  EXPECT_EQ(map.WordOf(0), kNoWord);
  // Unknown words and points (beyond the arrays, kNoWord, a negative id) are absent, not errors.
  EXPECT_EQ(map.PointOf(1000), PointMap::kNoPoint);
  EXPECT_EQ(map.PointOf(kNoWord), PointMap::kNoPoint);
  EXPECT_EQ(map.PointOf(-3), PointMap::kNoPoint);
  EXPECT_EQ(map.WordOf(PointMap::kNoPoint), kNoWord);  // FLANN's "fewer than k found"
}

// Memory follows the live words, not the ids issued: a page of 256 ids exists while one of its
// ids is live (ids 255 and 256 are in pages 0 and 1, id 1,000,000 in page 3,906).
TEST(PointMapTest, KeepsAPageOnlyWhileItHoldsALiveWord) {
  PointMap map;
  map.Set(255, 0);
  map.Set(256, 1);
  map.Set(1000000, 2);
  map.Set(1000001, 3);
  EXPECT_EQ(map.pages(), 3u);
  EXPECT_EQ(map.PointOf(256), 1u);
  EXPECT_EQ(map.PointOf(1000001), 3u);
  EXPECT_EQ(map.PointOf(999999), PointMap::kNoPoint);  // in a held page, not live
  EXPECT_EQ(map.PointOf(1000), PointMap::kNoPoint);    // in no page
  map.Erase(1000000);
  EXPECT_EQ(map.pages(), 3u);  // 1,000,001 still holds page 3,906
  map.Erase(1000001);
  map.Erase(255);
  EXPECT_EQ(map.pages(), 1u);
  EXPECT_EQ(map.PointOf(1000001), PointMap::kNoPoint);
  EXPECT_EQ(map.size(), 1u);
  map.Set(1000001, 4);  // a page comes back empty but for the word set
  EXPECT_EQ(map.pages(), 2u);
  EXPECT_EQ(map.PointOf(1000000), PointMap::kNoPoint);
  EXPECT_EQ(map.PointOf(1000001), 4u);
  EXPECT_EQ(Live(map), (std::vector<std::pair<WordId, size_t>>{{256, 1}, {1000001, 4}}));
}

// A word added again after its point left moves to the new point: its old point holds nothing.
TEST(PointMapTest, AWordSetAgainLeavesItsOldPoint) {
  PointMap map;
  map.Set(5, 0);
  map.Set(5, 3);
  EXPECT_EQ(map.size(), 1u);
  EXPECT_EQ(map.PointOf(5), 3u);
  EXPECT_EQ(map.WordOf(0), kNoWord);
  EXPECT_EQ(map.WordOf(3), 5);
}

// What a full build starts from: the live words in id order, whatever order they came in.
TEST(PointMapTest, ListsLiveWordsInIdOrder) {
  PointMap map;
  map.Set(30, 0);
  map.Set(4, 1);
  map.Set(17, 2);
  map.Set(9, 3);
  map.Erase(17);
  EXPECT_EQ(Live(map), (std::vector<std::pair<WordId, size_t>>{{4, 1}, {9, 3}, {30, 0}}));
  map.Clear();
  EXPECT_EQ(map.size(), 0u);
  EXPECT_TRUE(Live(map).empty());
}

}  // namespace
}  // namespace memloop
