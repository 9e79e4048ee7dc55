#include "memloop/evaluation.h"

#include <gtest/gtest.h>

#include <set>

namespace memloop {
namespace {

TEST(EvaluationTest, HandMadeCase) {
  // Ground truth: 5 ~ 1, 6 ~ 1, 6 ~ 2, 8 ~ 3. Images with a loop: 5, 6, 8.
  const std::set<std::pair<int, int>> truth = {{5, 1}, {6, 1}, {6, 2}, {8, 3}};
  const auto is_loop = [&](ImageIndex q, ImageIndex m) { return truth.count({q, m}) > 0; };
  const std::vector<Detection> detections = {
      {5, {1}},     // true
      {6, {4, 2}},  // true: the matched location stands for images 4 and 2
      {7, {3}},     // false: image 7 has no loop
      {8, {2}},     // false: wrong place
  };
  const PrecisionRecall score = Evaluate(detections, is_loop, 10);
  EXPECT_EQ(score.detections, 4);
  EXPECT_EQ(score.true_positives, 2);
  EXPECT_EQ(score.false_positives, 2);
  EXPECT_EQ(score.loop_images, 3);
  EXPECT_DOUBLE_EQ(score.Precision(), 0.5);
  EXPECT_DOUBLE_EQ(score.Recall(), 2.0 / 3);
}

TEST(EvaluationTest, NoDetectionIsFullPrecisionAndNoRecall) {
  const auto is_loop = [](ImageIndex q, ImageIndex m) { return q == 3 && m == 0; };
  const PrecisionRecall score = Evaluate({}, is_loop, 4);
  EXPECT_DOUBLE_EQ(score.Precision(), 1.0);
  EXPECT_DOUBLE_EQ(score.Recall(), 0.0);
  EXPECT_EQ(score.loop_images, 1);
}

}  // namespace
}  // namespace memloop
