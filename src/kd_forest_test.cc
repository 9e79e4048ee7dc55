#include "kd_forest.h"

#include <gtest/gtest.h>

namespace memloop {
namespace {

cv::Mat RandomPoints(int rows, int dim, uint64_t seed) {
  cv::Mat points(rows, dim, CV_32F);
  cv::RNG(seed).fill(points, cv::RNG::UNIFORM, 0.0, 1.0);
  return points;
}

std::vector<WordId> Ids(int first, int count) {
  std::vector<WordId> ids;
  for (int i = 0; i < count; ++i) ids.push_back(first + i);
  return ids;
}

// Brute force: (nearest id, true distance) among the live points.
std::pair<WordId, float> Nearest(const cv::Mat& query, const cv::Mat& points,
                                 const std::vector<WordId>& ids, const std::set<WordId>& removed) {
  std::pair<WordId, float> best = {kNoWord, 1e30f};
  for (int row = 0; row < points.rows; ++row) {
    if (removed.count(ids[row])) continue;
    const float distance = static_cast<float>(cv::norm(query, points.row(row), cv::NORM_L2));
    if (distance < best.second) best = {ids[row], distance};
  }
  return best;
}

TEST(KdForestTest, AgreesWithBruteForceThroughAddsRemovesAndRebuilds) {
  DictionaryOptions options;
  options.kd_checks = 4000;  // near exact
  KdForest forest(16, options);
  const cv::Mat points = RandomPoints(3000, 16, 1);
  const std::vector<WordId> ids = Ids(1, 3000);
  // Added in batches, as images are: the forest is extended and rebuilt along the way.
  for (int start = 0; start < 3000; start += 300) {
    forest.Add(std::vector<WordId>(ids.begin() + start, ids.begin() + start + 300),
               points.rowRange(start, start + 300));
  }
  std::set<WordId> removed;
  for (WordId id = 1; id <= 3000; id += 3) {
    forest.Remove(id);
    removed.insert(id);
  }
  EXPECT_EQ(forest.size(), 3000u - removed.size());
  EXPECT_GT(forest.build_count(), 1);

  const cv::Mat queries = RandomPoints(200, 16, 2);
  const auto found = forest.Search(queries);
  int agree = 0;
  for (int row = 0; row < queries.rows; ++row) {
    const auto expected = Nearest(queries.row(row), points, ids, removed);
    EXPECT_EQ(removed.count(found[row][0].word), 0u);
    EXPECT_LE(found[row][0].distance, found[row][1].distance);
    agree += found[row][0].word == expected.first;
    if (found[row][0].word == expected.first) {
      EXPECT_NEAR(found[row][0].distance, expected.second, 1e-4);  // true, not squared
    }
  }
  EXPECT_GE(agree, 196);  // approximate search: allow 2% misses
}

TEST(KdForestTest, FindsItsOwnPointsAfterRebuildAndKeepsDescriptors) {
  KdForest forest(8, DictionaryOptions());
  const cv::Mat points = RandomPoints(500, 8, 3);
  forest.Add(Ids(100, 250), points.rowRange(0, 250));
  forest.Add(Ids(350, 250), points.rowRange(250, 500));  // doubles the size: rebuilt
  const auto found = forest.Search(points);
  for (int row = 0; row < points.rows; ++row) {
    EXPECT_EQ(found[row][0].word, 100 + row);
    EXPECT_FLOAT_EQ(found[row][0].distance, 0.0f);
  }
  EXPECT_EQ(forest.Descriptor(360)[3], points.at<float>(260, 3));
  EXPECT_EQ(forest.Descriptor(99), nullptr);
}

TEST(KdForestTest, SameInputSameForest) {
  const cv::Mat points = RandomPoints(2000, 32, 4);
  const cv::Mat queries = RandomPoints(300, 32, 5);
  KdForest a(32, DictionaryOptions());
  KdForest b(32, DictionaryOptions());
  a.Add(Ids(1, 2000), points);
  b.Add(Ids(1, 2000), points);
  const auto found_a = a.Search(queries);
  const auto found_b = b.Search(queries);
  for (int row = 0; row < queries.rows; ++row) {
    EXPECT_EQ(found_a[row][0].word, found_b[row][0].word);
    EXPECT_EQ(found_a[row][1].word, found_b[row][1].word);
  }
}

TEST(KdForestTest, EmptyAndSingleWord) {
  KdForest forest(2, DictionaryOptions());
  const cv::Mat query = (cv::Mat_<float>(1, 2) << 1, 1);
  EXPECT_EQ(forest.Search(query)[0][0].word, kNoWord);
  forest.Add({7}, (cv::Mat_<float>(1, 2) << 4, 5));
  const auto found = forest.Search(query);
  EXPECT_EQ(found[0][0].word, 7);
  EXPECT_FLOAT_EQ(found[0][0].distance, 5.0f);  // 3-4-5
  EXPECT_EQ(found[0][1].word, kNoWord);
  forest.Remove(7);
  EXPECT_EQ(forest.Search(query)[0][0].word, kNoWord);
}

}  // namespace
}  // namespace memloop
