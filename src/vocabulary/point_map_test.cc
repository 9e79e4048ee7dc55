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
