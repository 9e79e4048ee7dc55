#include "memloop/synthetic_route.h"

#include <gtest/gtest.h>

#include <cmath>

#include "detector/loop_geometry.h"

namespace memloop {
namespace {

// The camera's optical axis (its rotation's third column) in the world.
cv::Vec3d Forward(const CameraPose& pose) {
  const cv::Vec4d& q = pose.quaternion;
  const cv::Matx33d r = RotationOf({q[0], q[1], q[2], q[3]});
  return {r(0, 2), r(1, 2), r(2, 2)};
}

// The loop is a circle of the loop's length (80 steps of 160 px at 2 m / 300 px a pixel: 85.3 m),
// the camera facing out at the wall; a lap's frame and the next lap's frame n are at one place.
TEST(SyntheticRouteTest, PosesGoRoundTheLoopFacingTheWall) {
  const SyntheticRouteOptions options;
  const SyntheticRoute route(options);
  const double metres_per_pixel = options.wall_distance_m / options.focal_px;
  const double radius = options.lap_frames * options.step_px * metres_per_pixel / (2 * CV_PI);
  const int second_lap = options.lap_frames + options.detour_frames;
  for (int n = 0; n < options.lap_frames; n += 7) {
    for (int index : {n, second_lap + n}) {
      const CameraPose pose = route.Pose(index);
      const cv::Vec3d out(pose.position[0], pose.position[1], 0);
      // Radius: the loop's, moved by the frame's zoom (depth) off the wall's distance.
      EXPECT_NEAR(cv::norm(out), radius + options.wall_distance_m - route.Depth(index), 1e-9);
      EXPECT_NEAR(Forward(pose).dot(out / cv::norm(out)), 1, 1e-9) << index;  // facing out
      EXPECT_GE(route.Depth(index), options.wall_distance_m / 1.05);
      EXPECT_LE(route.Depth(index), options.wall_distance_m / 0.95);
    }
    // One place on both laps: apart by the two frames' jitter only (12 px, 8 px, 5% zoom).
    const cv::Vec3d apart = route.Pose(n).position - route.Pose(second_lap + n).position;
    EXPECT_LT(cv::norm(apart), 24 * metres_per_pixel + 0.25) << n;
  }
  // One step along the lap: 160 px, 1.07 m along the circle, give or take the jitter.
  const double step = cv::norm(route.Pose(11).position - route.Pose(10).position);
  EXPECT_NEAR(step, options.step_px * metres_per_pixel, 24 * metres_per_pixel + 0.2);
}

}  // namespace
}  // namespace memloop
