#include "detector/epipolar_significance.h"

#include <gtest/gtest.h>

#include <cmath>

namespace memloop {
namespace {

// 10 of 20 correspondences within 3 pixels in 240x192 images: alpha = 2 * 3 * 307.35 / 46080 =
// 0.040019; log10(3 * 13) + log10 C(20, 10) + log10 C(10, 7) + 3 log10(alpha)
// = 1.59106 + 5.26658 + 2.07918 - 4.19316 = 4.74366: such fits are common among random matches.
TEST(EpipolarSignificanceTest, FalseAlarmsOfAFitByHand) {
  EXPECT_NEAR(Log10FalseAlarms(20, 10, 3.0, {240, 192}), 4.74366, 1e-4);
}

// The same counts in 960x540 images: alpha = 6 * 1101.41 / 518400 = 0.012748, 3 log10(alpha) =
// -5.68362: 4.74366 + 4.19316 - 5.68362 = 3.25320. The image's size changes the verdict's odds.
TEST(EpipolarSignificanceTest, ALargerImageMakesTheSameFitRarer) {
  EXPECT_NEAR(Log10FalseAlarms(20, 10, 3.0, {960, 540}), 3.25320, 1e-4);
}

TEST(EpipolarSignificanceTest, SevenOrFewerInliersAreNoEvidence) {
  EXPECT_TRUE(std::isinf(Log10FalseAlarms(20, 7, 0.1, {640, 480})));
  EXPECT_TRUE(std::isinf(LowestLog10FalseAlarms({0.1, 0.1, 0.1, 0.1, 0.1, 0.1, 0.1}, {640, 480})));
  EXPECT_TRUE(std::isinf(Log10FalseAlarms(20, 10, 1.0, {0, 0})));  // no image size
}

// Horizontal translation: F = [[0,0,0],[0,0,-1],[0,1,0]], epipolar lines are the rows. (10, 20)
// and (50, 23): the line in b is y = 20, in a y = 23: 3 pixels each way.
TEST(EpipolarSignificanceTest, ResidualIsTheDistanceToTheEpipolarLine) {
  const cv::Mat fundamental = (cv::Mat_<double>(3, 3) << 0, 0, 0, 0, 0, -1, 0, 1, 0);
  const std::vector<double> residuals =
      EpipolarResiduals(fundamental, {{10, 20}, {7, 9}}, {{50, 23}, {90, 9}});
  ASSERT_EQ(residuals.size(), 2u);
  EXPECT_NEAR(residuals[0], 3.0, 1e-9);
  EXPECT_NEAR(residuals[1], 0.0, 1e-9);
}

// 30 correspondences within half a pixel in 640x480 are no chance; 30 spread evenly up to 200
// pixels from their lines, as random points are, are: even their best k expects many such fits.
TEST(EpipolarSignificanceTest, TheLowestOverKTellsPreciseGeometryFromChance) {
  std::vector<double> precise(30, 0.5), spread;
  for (int k = 0; k < 30; ++k) spread.push_back(200.0 * (k + 1) / 30);
  EXPECT_LT(LowestLog10FalseAlarms(precise, {640, 480}), -10);
  EXPECT_GT(LowestLog10FalseAlarms(spread, {640, 480}), 0);
}

}  // namespace
}  // namespace memloop
