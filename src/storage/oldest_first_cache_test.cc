#include "storage/oldest_first_cache.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace memloop {
namespace {

TEST(OldestFirstCacheTest, DropsTheOldestBeyondTheBound) {
  OldestFirstCache<int, std::string> cache(10);
  std::vector<int> dropped;
  const auto note = [&dropped](int key, const std::string&) { dropped.push_back(key); };
  cache.Add(1, "a", 4, note);
  cache.Add(2, "b", 4, note);
  EXPECT_EQ(cache.bytes(), 8u);
  cache.Add(3, "c", 4, note);  // 12 > 10: 1 goes
  EXPECT_EQ(dropped, (std::vector<int>{1}));
  EXPECT_EQ(cache.bytes(), 8u);
  EXPECT_EQ(cache.Find(1), nullptr);
  ASSERT_NE(cache.Find(2), nullptr);
  EXPECT_EQ(*cache.Find(2), "b");
  cache.Add(4, "big", 20, note);  // over the bound alone: the others go, it stays
  EXPECT_EQ(dropped, (std::vector<int>{1, 2, 3}));
  EXPECT_EQ(cache.size(), 1u);
  EXPECT_EQ(cache.bytes(), 20u);
}

TEST(OldestFirstCacheTest, AKeyAddedAgainBecomesTheNewest) {
  OldestFirstCache<int, std::string> cache(8);
  cache.Add(1, "a", 4);
  cache.Add(2, "b", 4);
  cache.Add(1, "a2", 4);  // replaces 1, now newer than 2
  EXPECT_EQ(cache.bytes(), 8u);
  cache.Add(3, "c", 4);  // 2 is the oldest
  EXPECT_FALSE(cache.Contains(2));
  EXPECT_EQ(*cache.Find(1), "a2");
}

TEST(OldestFirstCacheTest, TakeAndEraseRemove) {
  OldestFirstCache<int, std::string> cache(100);
  cache.Add(1, "a", 4);
  cache.Add(2, "b", 5);
  EXPECT_EQ(cache.Take(1), std::optional<std::string>("a"));
  EXPECT_EQ(cache.Take(1), std::nullopt);
  cache.Erase(2);
  cache.Erase(7);  // absent: nothing
  EXPECT_EQ(cache.size(), 0u);
  EXPECT_EQ(cache.bytes(), 0u);
}

}  // namespace
}  // namespace memloop
