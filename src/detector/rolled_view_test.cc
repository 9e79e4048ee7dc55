#include "detector/rolled_view.h"

#include <gtest/gtest.h>

#include "detector/likelihood.h"
#include "small_memory.h"

namespace memloop {
namespace {

// Rows at the points of words `ids` (small_memory.h: word w at (100 w, 0)); a negative id is a
// point half-way between words -id and -id + 1, which the ratio test matches to neither.
cv::Mat PointsOf(const std::vector<int>& ids) {
  cv::Mat points(static_cast<int>(ids.size()), 2, CV_32F, cv::Scalar(0));
  for (size_t row = 0; row < ids.size(); ++row) {
    const float x = ids[row] > 0 ? 100.0f * ids[row] : 100.0f * -ids[row] + 50;
    points.at<float>(static_cast<int>(row), 0) = x;
  }
  return points;
}

Features WithRolledView(const std::vector<int>& rolled_words) {
  Features features;
  for (size_t i = 0; i < rolled_words.size(); ++i) {
    features.keypoints.emplace_back(static_cast<float>(i), 1.0f, 3.0f);
  }
  features.descriptors = PointsOf(rolled_words);  // not used by the rolled view
  features.rolled_descriptors = PointsOf(rolled_words);
  return features;
}

// WM: L1 {1, 2, 3}, L2 {4, 5, 6}, L3 {7, 8}; L_t = {1, 9, 10, 11} in STM. Upright, eq. 1:
// s1 = 1 / max(4, 3) = 0.25, s2 = s3 = 0. The rolled view matches words 4, 5, 6 (its fourth
// row, between words 4 and 5, passes no ratio test) and is scored as an image of L_t's 4
// words: s2 = 3 / max(4, 3) = 0.75 is raised, s1 stays 0.25 (the rolled view shares nothing).
TEST(RolledViewTest, EachLocationScoresTheBetterOfTheTwoViews) {
  Memory memory(DescriptorKind::kFloat, 2, testing::SmallDictionaryOptions());
  const auto ids = testing::AddChain(memory, {{1, 2, 3}, {4, 5, 6}, {7, 8}, {1, 9, 10, 11}});
  memory.MoveStmOverflowToWm(1);
  const Signature& z_t = memory.at(ids[3]).signature;
  IdMap<double> scores = ScoreWorkingMemory(z_t, memory);
  ASSERT_DOUBLE_EQ(scores.at(ids[0]), 0.25);

  RolledView view;
  view.Observe(WithRolledView({4, 5, 6, -4}), memory.dictionary());
  ASSERT_TRUE(view.present());
  view.Raise(memory, z_t.size(), scores);
  EXPECT_DOUBLE_EQ(scores.at(ids[0]), 0.25);
  EXPECT_DOUBLE_EQ(scores.at(ids[1]), 0.75);
  EXPECT_DOUBLE_EQ(scores.at(ids[2]), 0.0);
  EXPECT_EQ(view.raised(), 1);
  // The hypothesis on L2 is checked on the view that matched it, the others on z_t.
  EXPECT_EQ(view.ViewOf(ids[1], z_t).words, (std::vector<WordId>{4, 5, 6}));
  EXPECT_EQ(&view.ViewOf(ids[0], z_t), &z_t);
  EXPECT_EQ(&view.ViewOf(kNoLocation, z_t), &z_t);
}

TEST(RolledViewTest, AnImageWithoutARolledViewChangesNothing) {
  Memory memory(DescriptorKind::kFloat, 2, testing::SmallDictionaryOptions());
  const auto ids = testing::AddChain(memory, {{1, 2, 3}, {4, 5, 6}, {1, 4}});
  memory.MoveStmOverflowToWm(1);
  const Signature& z_t = memory.at(ids[2]).signature;
  RolledView view;
  view.Observe(WithRolledView({4, 5, 6}), memory.dictionary());
  IdMap<double> scores = ScoreWorkingMemory(z_t, memory);
  view.Raise(memory, z_t.size(), scores);
  ASSERT_EQ(view.raised(), 1);  // L2: 3 / 3 against 1 / 3

  view.Observe(Features{}, memory.dictionary());  // the next image: not rolled
  EXPECT_FALSE(view.present());
  const IdMap<double> upright = ScoreWorkingMemory(z_t, memory);
  scores = upright;
  view.Raise(memory, z_t.size(), scores);
  EXPECT_EQ(scores, upright);
  EXPECT_EQ(view.raised(), 0);
  EXPECT_EQ(&view.ViewOf(ids[1], z_t), &z_t);
}

}  // namespace
}  // namespace memloop
