// A map's loop closures for a SLAM back-end (`memloop export`): each with both images' names,
// indices, time stamps and sessions, the hypothesis value, the epipolar inliers between the two
// views' shared words and, given the camera's intrinsics, the relative pose from the essential
// matrix (rotation and the direction of the translation: one camera cannot give its scale).
#pragma once

#include <array>
#include <map>
#include <string>
#include <vector>

#include "memloop/loop_geometry.h"
#include "memloop/map_info.h"

namespace memloop {

struct ExportedLoopClosure {
  MapLoopClosure loop;
  MapImage query, match;  // index kNoImage... when the map does not record the image
  // Empty (no correspondences) when a view's location is not in the map's LTM (a map not
  // closed: STM and WM are only in its checkpoint).
  LoopGeometry geometry;
};

// Reads the map read-only. Each loop closure's geometry is estimated from the map's locations
// with `intrinsics` (the inliers); its pose is the one kept when it was accepted where the map
// kept one with the same intrinsics (the map's camera.*; `intrinsics` unknown means those).
// Throws DatabaseError as InspectMap does.
std::vector<ExportedLoopClosure> ExportLoopClosures(const std::string& map_path,
                                                    const CameraIntrinsics& intrinsics = {});

enum class ExportFormat { kJson, kG2o, kPairs };
// "json", "g2o", "pairs"; ParameterError naming `--format` otherwise ("tum" too, saying why: a TUM
// trajectory has 8 columns, a loop closure is a pair of images).
ExportFormat ParseExportFormat(const std::string& name);

// A rigid transform: translation, then rotation as a quaternion x, y, z, w.
using PoseArray = std::array<double, 7>;
// "tx,ty,tz,qx,qy,qz,qw"; ParameterError naming `option` otherwise.
PoseArray ParsePose(const std::string& text, const std::string& option);

// The pose of each of `images` whose time stamp a TUM trajectory ("time tx ty tz qx qy qz qw"
// lines, '#' comments) holds within 10 ms, by image index. Throws InputError naming the file: not
// readable, a malformed line, or no pose at the time of any image.
std::map<ImageIndex, PoseArray> TrajectoryAtImages(const std::vector<MapImage>& images,
                                                   const std::string& trajectory);

// What turns loop-closure edges into a pose graph g2o loads as it is (docs/export.md).
struct PoseGraphOptions {
  // A TUM trajectory ("time tx ty tz qx qy qz qw" lines, '#' comments) of the map's images: each
  // image whose time stamp it holds (within 10 ms) becomes a vertex at that pose, consecutive
  // vertices are joined by odometry edges, the first is fixed. "": loop-closure edges only.
  std::string trajectory;
  // The camera's pose in the frame the trajectory's poses are of (the robot's base): loop
  // closures, measured between cameras, are turned into edges between bases.
  PoseArray camera_to_base{0, 0, 0, 0, 0, 0, 1};
  // The odometry edges' standard deviations, per edge: translation (metres, each axis) and
  // rotation (radians), written as g2o information (1/sigma^2 and, for its half-angle rotation
  // error, 4/sigma^2).
  double odometry_sigma_metres = 0.05;
  double odometry_sigma_radians = 0.02;
};

// "METRES,RADIANS" for PoseGraphOptions' odometry sigmas, both over 0; ParameterError naming
// `--odometry-sigma` otherwise.
void ParseOdometrySigma(const std::string& text, PoseGraphOptions& graph);

// Writes `loops` to `path` as a g2o pose graph or as pairs of images with their relative pose
// (docs/export.md): both need the relative poses, so `intrinsics` must be known (ParameterError).
// `images` (ReadMapImages) gives the vertices' time stamps. Throws InputError when the trajectory
// cannot be read or the file cannot be written. (`memloop export --format json` writes
// everything, poses or not.)
void WriteLoopClosures(const std::vector<ExportedLoopClosure>& loops, ExportFormat format,
                       const CameraIntrinsics& intrinsics, const std::string& path,
                       const std::vector<MapImage>& images = {},
                       const PoseGraphOptions& graph = {});

}  // namespace memloop
