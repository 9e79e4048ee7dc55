// The geometry between two views of a loop closure, from the words they share: the fundamental
// matrix's inliers and, given the intrinsics, the relative pose (essential matrix).
#pragma once

#include <array>
#include <opencv2/core.hpp>

#include "detector/location.h"
#include "memloop/loop_geometry.h"
#include "memloop/map_info.h"
#include "memloop/options.h"
#include "vocabulary/signature.h"

namespace memloop {

// The image a location's keypoints were seen in: its signature's (Rehearsal gives a newer
// location an older one's signature), else, in maps made before it was recorded, its first.
inline ImageIndex ViewOf(const Location& location) {
  return location.signature.image != kNoImage ? location.signature.image : location.images.front();
}

// A rotation matrix's quaternion x, y, z, w (w >= 0), and the rotation of a quaternion (of any
// norm but 0).
std::array<double, 4> QuaternionOf(const cv::Matx33d& rotation);
cv::Matx33d RotationOf(const std::array<double, 4>& quaternion);

// What the map keeps of a loop closure's geometry (LoopClosurePose): `estimated` when the
// intrinsics were known, else a reason saying they were not.
LoopClosurePose KeptPose(const LoopGeometry& geometry, bool intrinsics_known);

// RANSAC is seeded: the same views give the same geometry.
LoopGeometry EstimateLoopGeometry(const Signature& query, const Signature& match,
                                  const CameraIntrinsics& intrinsics,
                                  const VerificationOptions& options);

}  // namespace memloop
