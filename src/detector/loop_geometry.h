// The geometry between two views of a loop closure, from the words they share: the fundamental
// matrix's inliers and, given the intrinsics, the relative pose (essential matrix).
#pragma once

#include <array>
#include <opencv2/core.hpp>

#include "detector/descriptor_correspondences.h"
#include "detector/location.h"
#include "detector/word_correspondences.h"
#include "memloop/loop_geometry.h"
#include "memloop/map_info.h"
#include "memloop/options.h"
#include "vocabulary/signature.h"

namespace memloop {

// The image a location's keypoints were seen in: its signature's (Rehearsal gives a newer
// location an older one's signature), else, in maps made before it was recorded, its first.
inline ImageIndex ViewOf(const Location& location) {
  // kNoImage for another robot's place (fleet_places.h): no image of this map.
  if (location.signature.image != kNoImage || location.images.empty())
    return location.signature.image;
  return location.images.front();
}

// A rotation matrix's quaternion x, y, z, w (w >= 0), and the rotation of a quaternion (of any
// norm but 0).
std::array<double, 4> QuaternionOf(const cv::Matx33d& rotation);
cv::Matx33d RotationOf(const std::array<double, 4>& quaternion);

// What the map keeps of a loop closure's geometry (LoopClosurePose): `estimated` when the
// intrinsics were known, else a reason saying they were not.
LoopClosurePose KeptPose(const LoopGeometry& geometry, bool intrinsics_known);

// From keypoint correspondences (a: query, b: match): the fundamental matrix's inliers and, with
// the intrinsics, the pose: metric (PnP) when the query's points have depth, else from the
// essential matrix or a rotation alone. RANSAC is seeded: the same views give the same geometry.
LoopGeometry EstimateLoopGeometry(const WordCorrespondences& matched,
                                  const CameraIntrinsics& intrinsics,
                                  const VerificationOptions& options);
// The same from the words two signatures share (a map's locations, after the fact).
LoopGeometry EstimateLoopGeometry(const Signature& query, const Signature& match,
                                  const CameraIntrinsics& intrinsics,
                                  const VerificationOptions& options);

// An accepted loop closure's geometry: the image being processed (`image`, its own keypoints and
// descriptors, with depth its points: image_view.h) against the keypoints the matched location
// holds, described by their words. The views are the image and ViewOf(match), the image the
// pose is to. Without intrinsics (camera.fx..cy), the views and a reason only.
LoopGeometry DescribeLoopClosure(const DescribedView& image, ImageIndex image_index,
                                 const Location& match, const Dictionary& dictionary,
                                 const CameraIntrinsics& intrinsics,
                                 const VerificationOptions& options);

inline CameraIntrinsics IntrinsicsOf(const CameraOptions& camera) {
  return {camera.fx, camera.fy, camera.cx, camera.cy};
}

}  // namespace memloop
