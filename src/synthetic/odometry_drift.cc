#include "memloop/odometry_drift.h"

#include <cmath>

#include "detector/loop_geometry.h"

namespace memloop {

std::vector<CameraPose> DriftedOdometry(const std::vector<CameraPose>& truth,
                                        const OdometryDrift& drift) {
  std::vector<CameraPose> odometry;
  if (truth.empty()) return odometry;
  odometry.push_back(truth.front());
  double yaw = 0;  // radians, accumulated
  for (size_t i = 1; i < truth.size(); ++i) {
    const cv::Vec3d step = truth[i].position - truth[i - 1].position;
    yaw +=
        (drift.yaw_degrees_per_metre * cv::norm(step) + drift.yaw_degrees_per_step) * CV_PI / 180;
    const cv::Matx33d turn(std::cos(yaw), -std::sin(yaw), 0, std::sin(yaw), std::cos(yaw), 0, 0, 0,
                           1);
    const cv::Vec4d& q = truth[i].quaternion;
    const std::array<double, 4> turned = QuaternionOf(turn * RotationOf({q[0], q[1], q[2], q[3]}));
    odometry.push_back({odometry.back().position + (1 + drift.scale_error) * (turn * step),
                        cv::Vec4d(turned[0], turned[1], turned[2], turned[3])});
  }
  return odometry;
}

}  // namespace memloop
