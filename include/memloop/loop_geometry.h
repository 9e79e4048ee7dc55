// The geometry between the two views of a loop closure, from the visual words they share: the
// epipolar inliers (matched keypoints) and, given the camera's intrinsics, the relative pose from
// the essential matrix (rotation, and the direction of the translation: one camera cannot give
// its length). In Result (with camera.fx..cy set) and in `memloop export`.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "memloop/types.h"

namespace memloop {

// Pinhole intrinsics in pixels; all 0: unknown.
struct CameraIntrinsics {
  double fx = 0, fy = 0, cx = 0, cy = 0;
  bool known() const { return fx > 0 && fy > 0; }
  bool operator==(const CameraIntrinsics& other) const {
    return fx == other.fx && fy == other.fy && cx == other.cx && cy == other.cy;
  }
};
// "fx,fy,cx,cy" (four numbers, fx and fy over 0); ParameterError naming `--intrinsics` otherwise.
CameraIntrinsics ParseIntrinsics(const std::string& text);

struct PointPair {
  float query_x, query_y, match_x, match_y;  // pixels, in each image
};

struct LoopGeometry {
  // The two views compared: the images whose keypoints the two locations hold (each location's
  // first image; a location that absorbed others keeps its own view).
  ImageIndex query_view = kNoImage, match_view = kNoImage;
  int correspondences = 0;         // words each view holds once
  std::vector<PointPair> inliers;  // of the fundamental matrix (RANSAC, the map's verify.*)
  // With intrinsics: the query camera's pose in the match camera's frame (x_match = rotation *
  // x_query + translation), from the essential matrix (translation of unit norm), or from a
  // rotation alone when it explains the matches as well (a camera turned where it stands).
  bool has_pose = false;
  std::array<double, 9> rotation{};     // row-major
  std::array<double, 4> quaternion{};   // x, y, z, w of `rotation`
  std::array<double, 3> translation{};  // metres when translation_metric, else a unit direction
  // With the query image's depth (Detector::Process(image, depth)): from PnP, in metres.
  bool translation_metric = false;
  // False when a rotation alone explains the matches (a baseline too short for a direction).
  bool translation_known = false;
  int pose_inliers = 0;  // of the model chosen (essential: in front of both cameras)
  // Why there is no pose ("" when has_pose): too few correspondences or inliers, no model fits,
  // or the intrinsics are unknown.
  std::string pose_problem;
  // `memloop export`: the pose is the one the map kept from when the loop closure was accepted
  // (the two images' own keypoints), not one estimated from the map's locations now.
  bool pose_from_detection = false;
};

}  // namespace memloop
