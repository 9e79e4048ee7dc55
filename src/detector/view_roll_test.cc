#include "detector/view_roll.h"

#include <gtest/gtest.h>

#include <cmath>

namespace memloop {
namespace {

// A 6 x 5 grid of points 30 pixels apart in view a; view b is a, rolled about the image centre
// by `degrees` (image axes: x right, y down, so a positive angle turns x toward y), scaled and
// moved, as a camera turning about its axis while it steps forward.
WordCorrespondences Rolled(double degrees, double scale = 1.1, cv::Point2f offset = {0, 0}) {
  WordCorrespondences matched;
  const double c = std::cos(degrees * CV_PI / 180), s = std::sin(degrees * CV_PI / 180);
  for (int row = 0; row < 5; ++row) {
    for (int column = 0; column < 6; ++column) {
      const cv::Point2f a = cv::Point2f(40.0f + 30 * column, 30.0f + 30 * row) + offset;
      const double x = a.x - 120, y = a.y - 96;
      matched.in_a.push_back(a);
      matched.in_b.emplace_back(static_cast<float>(120 + 7 + scale * (c * x - s * y)),
                                static_cast<float>(96 - 4 + scale * (s * x + c * y)));
    }
  }
  return matched;
}

TEST(ViewRollTest, ARolledViewGivesItsRoll) {
  for (const double degrees : {0.0, 9.0, -23.0, 90.0, 179.0}) {
    const ViewRoll roll = EstimateViewRoll(Rolled(degrees));
    ASSERT_TRUE(roll.known) << degrees;
    EXPECT_EQ(roll.correspondences, 30);
    // Every pair votes the same angle: one 1-degree bin, read at its centre.
    EXPECT_NEAR(roll.degrees, degrees, 0.5) << degrees;
    EXPECT_DOUBLE_EQ(roll.agreement, 1.0) << degrees;
  }
}

TEST(ViewRollTest, WrongWordsAreOutvoted) {
  WordCorrespondences matched = Rolled(-15);
  // A third of the correspondences moved to unrelated places: their pairs vote at random.
  for (int k = 0; k < 10; ++k) {
    matched.in_b[3 * k] =
        cv::Point2f(static_cast<float>((k * 53) % 240), static_cast<float>((k * 97) % 192));
  }
  const ViewRoll roll = EstimateViewRoll(matched);
  ASSERT_TRUE(roll.known);
  EXPECT_NEAR(roll.degrees, -15, 1.0);
  // 20 true correspondences make 190 agreeing pairs of the 435 (fewer vote: short segments).
  EXPECT_GT(roll.agreement, 190.0 / 435);
  EXPECT_LT(roll.agreement, 1.0);
}

TEST(ViewRollTest, TooFewOrDisagreeingCorrespondencesAreUnknown) {
  WordCorrespondences few = Rolled(10);
  few.in_a.resize(7);
  few.in_b.resize(7);
  EXPECT_FALSE(EstimateViewRoll(few).known);
  EXPECT_EQ(EstimateViewRoll(few).correspondences, 7);

  // Scattered at random: no window holds a quarter of the votes.
  WordCorrespondences scattered = Rolled(0);
  for (int k = 0; k < scattered.size(); ++k) {
    scattered.in_b[k] =
        cv::Point2f(static_cast<float>((k * 7919) % 241), static_cast<float>((k * 104729) % 193));
  }
  const ViewRoll roll = EstimateViewRoll(scattered);
  EXPECT_FALSE(roll.known);
  EXPECT_LT(roll.agreement, 0.25);
}

TEST(ViewRollTest, OfMoreThanAHundredCorrespondencesTheFirstHundredVote) {
  // 60 correspondences rolled 10 degrees, then 100 rolled 60: the first 100 are 60 at 10 degrees
  // (1,770 agreeing pairs) and 40 at 60 (780); all 160 would give 60 degrees (4,950 pairs).
  WordCorrespondences matched;
  const auto append = [&](const WordCorrespondences& part, int count) {
    for (int k = 0; k < count; ++k) {
      matched.in_a.push_back(part.in_a[k]);
      matched.in_b.push_back(part.in_b[k]);
    }
  };
  append(Rolled(10, 1.1, {0, 0}), 30);
  append(Rolled(10, 1.1, {15, 15}), 30);
  for (int grid = 0; grid < 4; ++grid) append(Rolled(60, 1.1, {7.5f * grid, 3.5f + 5 * grid}), 25);
  const ViewRoll roll = EstimateViewRoll(matched);
  ASSERT_TRUE(roll.known);
  EXPECT_EQ(roll.correspondences, 160);
  EXPECT_NEAR(roll.degrees, 10, 2.0);  // pairs across the two sets in the window pull the mean
}

TEST(ViewRollTest, ScaleChangesOverThreeTimesDoNotVote) {
  EXPECT_TRUE(EstimateViewRoll(Rolled(5, 2.9)).known);
  const ViewRoll roll = EstimateViewRoll(Rolled(5, 3.1));
  EXPECT_FALSE(roll.known);
  EXPECT_EQ(roll.agreement, 0);
}

}  // namespace
}  // namespace memloop
