// Odometry that drifts in a known way, made from a true trajectory: what a pose-graph back-end
// gets from wheels or visual odometry, to show (and test) what memloop's loop closures correct.
#pragma once

#include <vector>

#include "memloop/synthetic_route.h"  // CameraPose

namespace memloop {

struct OdometryDrift {
  double scale_error = 0.03;           // each step's distance over-read by 3%
  double yaw_degrees_per_metre = 0.1;  // a turn about the world's z axis per metre travelled
  double yaw_degrees_per_step = 0.02;  // and per step (a gyroscope's bias)
};

// The poses odometry would report along `truth` (in its order, from its first pose): each step's
// motion, over-read by the scale error, turned by the yaw accumulated so far about the world's z
// axis (up in a gravity-aligned frame), and each orientation turned the same way.
std::vector<CameraPose> DriftedOdometry(const std::vector<CameraPose>& truth,
                                        const OdometryDrift& drift = {});

}  // namespace memloop
