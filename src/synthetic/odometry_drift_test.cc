#include "memloop/odometry_drift.h"

#include <gtest/gtest.h>

#include <cmath>

namespace memloop {
namespace {

TEST(OdometryDriftTest, StepsAreOverReadAndTurnedByTheYawSoFar) {
  // Two steps of 1 m along x, facing along x (identity), then a step of 2 m along y.
  const cv::Vec4d identity(0, 0, 0, 1);
  const std::vector<CameraPose> truth = {
      {{0, 0, 0}, identity}, {{1, 0, 0}, identity}, {{2, 0, 0}, identity}, {{2, 2, 0}, identity}};
  OdometryDrift drift;
  drift.scale_error = 0.5;
  drift.yaw_degrees_per_metre = 30;
  drift.yaw_degrees_per_step = 15;
  const std::vector<CameraPose> odometry = DriftedOdometry(truth, drift);
  ASSERT_EQ(odometry.size(), 4u);
  EXPECT_EQ(odometry[0].position, truth[0].position);  // from the first pose
  // Step 1: yaw 30 + 15 = 45 degrees; 1.5 m at 45 degrees.
  const double half = std::sqrt(0.5);
  EXPECT_NEAR(odometry[1].position[0], 1.5 * half, 1e-12);
  EXPECT_NEAR(odometry[1].position[1], 1.5 * half, 1e-12);
  EXPECT_NEAR(odometry[1].quaternion[2], std::sin(CV_PI / 8), 1e-12);  // 45 degrees about z
  EXPECT_NEAR(odometry[1].quaternion[3], std::cos(CV_PI / 8), 1e-12);
  // Step 2: yaw 90 degrees; 1.5 m along y.
  EXPECT_NEAR(odometry[2].position[0], 1.5 * half, 1e-12);
  EXPECT_NEAR(odometry[2].position[1], 1.5 * half + 1.5, 1e-12);
  // Step 3: 2 m along y, yaw 90 + 60 + 15 = 165 degrees: 3 m towards (-sin 165, cos 165).
  const double yaw = 165 * CV_PI / 180;
  EXPECT_NEAR(odometry[3].position[0], 1.5 * half - 3 * std::sin(yaw), 1e-12);
  EXPECT_NEAR(odometry[3].position[1], 1.5 * half + 1.5 + 3 * std::cos(yaw), 1e-12);
  EXPECT_NEAR(odometry[3].position[2], 0, 1e-12);

  // No drift: the truth itself.
  const std::vector<CameraPose> exact = DriftedOdometry(truth, {0, 0, 0});
  for (size_t i = 0; i < truth.size(); ++i) {
    EXPECT_NEAR(cv::norm(exact[i].position - truth[i].position), 0, 1e-12) << i;
    EXPECT_NEAR(exact[i].quaternion[3], 1, 1e-12) << i;
  }
  EXPECT_TRUE(DriftedOdometry({}).empty());
}

}  // namespace
}  // namespace memloop
