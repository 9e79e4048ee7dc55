// The built-in demo and the integration tests' data: a camera moving along a procedurally
// textured world that loops, so the route passes the same places again, with small changes of
// viewpoint and exposure at every frame, and the exact ground truth of which frames show the
// same place. Everything is generated from a seed: the same options give the same images.
//
// The route: a first lap of the loop, a detour through places seen once, a second lap, another
// detour, then part of a third lap.
#pragma once

#include <functional>
#include <opencv2/core.hpp>
#include <string>
#include <utility>
#include <vector>

#include "memloop/generated_layout.h"
#include "memloop/ground_truth.h"

namespace memloop {

struct SyntheticRouteOptions {
  int seed = 7;
  int image_width = 320;
  int image_height = 240;
  int lap_frames = 80;        // frames per lap of the loop
  int detour_frames = 30;     // frames of each detour through places seen once
  int third_lap_frames = 40;  // frames of the third lap
  double step_px = 160;       // camera motion between frames, in world pixels
  // Two frames of different visits (or the end and the start of one lap) show the same place when
  // their views are this close: 0.6 of
  // the image width, i.e. views overlapping by at least 40%.
  double same_place_fraction = 0.6;
  // A street front under the textures (blocks of their own gray and height): large-scale
  // structure, which the day-night tests need (a change of light leaves it, not the small shapes).
  bool facades = false;
  // The camera that sees it, for metric depth and poses: focal length in pixels (the principal
  // point at the image centre) and the distance from the camera to the textured wall, in metres.
  // The loop is a circle, the wall a cylinder around it; the detours go into the circle and back.
  double focal_px = 300;
  double wall_distance_m = 2;
};

// A stretch of a route: `frames` steps along the loop or the detours' corridor, from step
// `first_step` (a step is SyntheticRouteOptions::step_px).
struct RouteSegment {
  bool in_loop = true;
  int first_step = 0;
  int frames = 0;
};

// A camera pose in a world frame (z up): position in metres and the camera's rotation as a
// quaternion x, y, z, w (camera frame: x right, y down, z forward), as a TUM trajectory gives it.
struct CameraPose {
  cv::Vec3d position;
  cv::Vec4d quaternion;
};

class SyntheticRoute {
 public:
  explicit SyntheticRoute(const SyntheticRouteOptions& options = {});
  // Another route over the same world (the options' seed; the detours' corridor `detour_steps`
  // long): `plan`'s segments in order, each pass of the loop a visit of its own. `robot` > 0 sees
  // it with other jitter and noise (fleet_routes.h); robot 0 with the default plan is the route
  // above. Pose() assumes the default plan's detours. Throws Error for a detour past the corridor.
  SyntheticRoute(const SyntheticRouteOptions& options, const std::vector<RouteSegment>& plan,
                 int robot, int detour_steps);
  static std::vector<RouteSegment> DefaultPlan(const SyntheticRouteOptions& options);
  static int DetourSteps(const std::vector<RouteSegment>& plan);

  int size() const { return static_cast<int>(frames_.size()); }
  // Frame `index` (0-based), 8-bit BGR, image_width x image_height.
  cv::Mat Render(int index) const;
  // The same frame, 8-bit gray.
  cv::Mat RenderGray(int index) const;
  // True when frame `query` shows the same place as the earlier frame `match`, seen on another
  // visit (frames of one pass are neighbours, not loop closures, except a lap's last frames,
  // back at its start).
  bool IsLoop(int query, int match) const;
  // The same as ground truth over the route's images (for memloop::Evaluate).
  memloop::GroundTruth Truth() const;
  // Every (query, match) with match < query and IsLoop(query, match).
  std::vector<std::pair<int, int>> GroundTruthPairs() const;
  // Whether frame `frame` and frame `other_frame` of `other`, a route over the same world, show
  // the same place (both on the loop, their views this close: same_place_fraction).
  bool SamePlace(int frame, const SyntheticRoute& other, int other_frame) const;
  // Where the camera was at frame `index`: the ground truth of a pose graph.
  CameraPose Pose(int index) const;
  // The depth of every pixel of frame `index`, in metres: the wall, square on, at the frame's
  // distance (its zoom jitter moves the camera).
  double Depth(int index) const;
  // Writes images/1.png .. images/N.png and ground_truth_pairs.csv ("query,match" file names)
  // into `folder`, the layout of the data sets in ../shared/datasets; a TUM folder also gets
  // depth/N.png with depth.txt, groundtruth.txt (Pose), odometry.txt (DriftedOdometry's) and
  // camera.conf (the camera.* parameters).
  // `written`, when given, is called after each image with the number written so far.
  void Write(const std::string& folder, const std::function<void(int)>& written = {},
             GeneratedLayout layout = GeneratedLayout::kImages) const;

 private:
  void WriteRgbd(const std::string& folder) const;

  struct Frame {
    double x;  // world position of the view's left edge (loop coordinate when in_loop)
    bool in_loop;
    int visit;                                        // lap number, or -1 on the detour
    double dx, dy, scale, angle_degrees, gain, bias;  // the view's jitter
  };

  SyntheticRouteOptions options_;
  int robot_ = 0;
  double loop_length_ = 0;
  cv::Mat world_;  // [loop | first view widths of the loop again | detour], gray
  std::vector<Frame> frames_;
};

}  // namespace memloop
