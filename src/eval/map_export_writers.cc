// The files `memloop export` writes for a SLAM back-end (docs/export.md): a g2o pose graph (the
// loop-closure edges, and with a trajectory its vertices and odometry edges) and the loop
// closures as pairs of images with their relative pose. (Its JSON is written by the tool.)
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <opencv2/core.hpp>
#include <sstream>

#include "detector/loop_geometry.h"
#include "memloop/errors.h"
#include "memloop/map_export.h"
#include "util/output_files.h"

namespace memloop {
namespace {

// Information of a loop-closure edge's rotation. g2o's EDGE_SE3:QUAT error takes the vector part
// of the error quaternion, about half the angle: an angle of sigma 0.05 rad (about the 90th
// percentile measured on tum_fr1_rpy) is 1 / (0.05 / 2)^2. Its translation, with depth, is in
// metres: 3 cm (about the 95th percentile there), 1 / 0.03^2; without, a direction whose length
// odometry gives: information 1e-6.
constexpr double kLoopRotationInformation = 1600;
constexpr double kLoopMetricTranslationInformation = 1111;
constexpr double kLoopDirectionInformation = 1e-6;
// A trajectory pose stands for an image when their time stamps are this close, in seconds.
constexpr double kStampTolerance = 0.01;

struct Rigid {
  cv::Matx33d rotation = cv::Matx33d::eye();
  cv::Vec3d translation;

  static Rigid Of(const PoseArray& pose) {
    return {RotationOf({pose[3], pose[4], pose[5], pose[6]}), cv::Vec3d(pose[0], pose[1], pose[2])};
  }
  Rigid operator*(const Rigid& other) const {
    return {rotation * other.rotation, rotation * other.translation + translation};
  }
  Rigid Inverse() const { return {rotation.t(), -(rotation.t() * translation)}; }
  PoseArray Array() const {
    const std::array<double, 4> q = QuaternionOf(rotation);
    return {translation[0], translation[1], translation[2], q[0], q[1], q[2], q[3]};
  }
};

// "image " or, for another robot's place (a fleet's map), "robot b image ".
std::string MatchName(const ExportedLoopClosure& loop) {
  return loop.loop.match_robot.empty() ? "image " : "robot " + loop.loop.match_robot + " image ";
}

// A loop closure without a pose, as a comment line saying why.
void WriteNoPose(const ExportedLoopClosure& loop, std::ostream& out) {
  out << "# image " << loop.query.index << " -> " << MatchName(loop) << loop.match.index
      << ": no relative pose (" << loop.geometry.pose_problem << ")\n";
}

// "EDGE_SE3:QUAT from to tx ty tz qx qy qz qw" and the information's upper triangle.
void WriteEdge(std::ostream& out, int from, int to, const PoseArray& pose, double translation,
               double rotation) {
  char text[512];
  std::snprintf(text, sizeof(text),
                "EDGE_SE3:QUAT %d %d %.9f %.9f %.9f %.9f %.9f %.9f %.9f %g 0 0 0 0 0 %g 0 0 0 0 "
                "%g 0 0 0 %g 0 0 %g 0 %g\n",
                from, to, pose[0], pose[1], pose[2], pose[3], pose[4], pose[5], pose[6],
                translation, translation, translation, rotation, rotation, rotation);
  out << text;
}

// The trajectory's poses by time stamp.
std::map<double, PoseArray> ReadTrajectory(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path, "cannot read the trajectory");
  std::map<double, PoseArray> poses;
  std::string line;
  for (int number = 1; std::getline(in, line); ++number) {
    const size_t first = line.find_first_not_of(" \t\r");
    if (first == std::string::npos || line[first] == '#') continue;
    std::istringstream fields(line);
    double stamp = 0;
    PoseArray pose{};
    std::string extra;
    bool read = static_cast<bool>(fields >> stamp);
    for (double& value : pose) read = read && static_cast<bool>(fields >> value);
    if (!read || (fields >> extra) || !std::isfinite(stamp)) {
      throw InputError(path, "line " + std::to_string(number) +
                                 ": expected 'time tx ty tz qx qy qz qw' (a TUM trajectory)");
    }
    poses[stamp] = pose;
  }
  if (poses.empty()) throw InputError(path, "the trajectory holds no pose");
  return poses;
}

std::map<ImageIndex, Rigid> Vertices(const std::vector<MapImage>& images,
                                     const std::string& trajectory) {
  std::map<ImageIndex, Rigid> vertices;
  for (const auto& [image, pose] : TrajectoryAtImages(images, trajectory)) {
    vertices[image] = Rigid::Of(pose);
  }
  return vertices;
}

// A loop closure between cameras as an edge between bases: B_match^-1 B_query =
// X C_match^-1 C_query X^-1 for the camera's pose X in the base frame. A metric translation
// (depth) takes the whole change of frame; a direction of unit length (one camera) is rotated
// into the base frame, not moved by the lever arm, which needs a length.
PoseArray BaseEdge(const LoopGeometry& g, const Rigid& camera_to_base) {
  const Rigid between =
      Rigid::Of({g.translation[0], g.translation[1], g.translation[2], g.quaternion[0],
                 g.quaternion[1], g.quaternion[2], g.quaternion[3]});
  if (g.translation_metric) return (camera_to_base * between * camera_to_base.Inverse()).Array();
  const Rigid in_base{camera_to_base.rotation * between.rotation * camera_to_base.rotation.t(),
                      camera_to_base.rotation * between.translation};
  return in_base.Array();
}

void WriteG2o(const std::vector<ExportedLoopClosure>& loops, const std::vector<MapImage>& images,
              const PoseGraphOptions& graph, std::ostream& out) {
  out << "# memloop: vertices are image indices; EDGE_SE3:QUAT from to = the pose of 'to' in "
         "'from''s frame, information's upper triangle (docs/export.md)\n";
  const Rigid camera_to_base = Rigid::Of(graph.camera_to_base);
  if (!graph.trajectory.empty()) {
    const std::map<ImageIndex, Rigid> vertices = Vertices(images, graph.trajectory);
    for (const auto& [index, pose] : vertices) {
      const PoseArray p = pose.Array();
      char text[256];
      std::snprintf(text, sizeof(text), "VERTEX_SE3:QUAT %d %.9f %.9f %.9f %.9f %.9f %.9f %.9f\n",
                    index, p[0], p[1], p[2], p[3], p[4], p[5], p[6]);
      out << text;
    }
    out << "FIX " << vertices.begin()->first << "\n";
    for (auto at = vertices.begin(); std::next(at) != vertices.end(); ++at) {
      const auto next = std::next(at);
      // g2o's rotation error is about half the angle: information 4 / sigma^2.
      WriteEdge(out, at->first, next->first, (at->second.Inverse() * next->second).Array(),
                1 / (graph.odometry_sigma_metres * graph.odometry_sigma_metres),
                4 / (graph.odometry_sigma_radians * graph.odometry_sigma_radians));
    }
  }
  for (const ExportedLoopClosure& loop : loops) {
    const LoopGeometry& g = loop.geometry;
    if (!g.has_pose) {
      WriteNoPose(loop, out);
      continue;
    }
    if (!loop.loop.match_robot.empty()) {  // not a vertex of this robot's graph
      out << "# image " << loop.query.index << " -> " << MatchName(loop) << loop.match.index
          << ": another robot's place (its pose: memloop export --format pairs or json)\n";
      continue;
    }
    WriteEdge(out, loop.match.index, loop.query.index, BaseEdge(g, camera_to_base),
              g.translation_metric ? kLoopMetricTranslationInformation : kLoopDirectionInformation,
              kLoopRotationInformation);
  }
}

// One line per loop closure: both images' time stamps (their indices when the map has none),
// then the query camera's pose in the match camera's frame.
void WritePairs(const std::vector<ExportedLoopClosure>& loops, std::ostream& out) {
  out << "# memloop loop closures: query_timestamp match_timestamp tx ty tz qx qy qz qw metric "
         "(the query camera in the match camera's frame; metric 1: translation in metres, 0: of "
         "unit length or 0 0 0)\n";
  const auto stamp = [](const MapImage& image) {
    return HasTimestamp(image.timestamp) ? image.timestamp : image.index;
  };
  for (const ExportedLoopClosure& loop : loops) {
    const LoopGeometry& g = loop.geometry;
    if (!g.has_pose) {
      WriteNoPose(loop, out);
      continue;
    }
    char text[512];
    std::snprintf(text, sizeof(text), "%.6f %.6f %.9f %.9f %.9f %.9f %.9f %.9f %.9f %d",
                  stamp(loop.query), stamp(loop.match), g.translation[0], g.translation[1],
                  g.translation[2], g.quaternion[0], g.quaternion[1], g.quaternion[2],
                  g.quaternion[3], g.translation_metric ? 1 : 0);
    out << text;
    // Another robot's place: the line ends with that robot's name (its time stamp is its own).
    if (!loop.loop.match_robot.empty()) out << " " << loop.loop.match_robot;
    out << "\n";
  }
}

}  // namespace

std::map<ImageIndex, PoseArray> TrajectoryAtImages(const std::vector<MapImage>& images,
                                                   const std::string& trajectory) {
  const std::map<double, PoseArray> poses = ReadTrajectory(trajectory);
  std::map<ImageIndex, PoseArray> at_images;
  for (const MapImage& image : images) {
    if (!HasTimestamp(image.timestamp)) continue;
    auto after = poses.lower_bound(image.timestamp);
    auto nearest = after;
    if (after == poses.end() ||
        (after != poses.begin() &&
         image.timestamp - std::prev(after)->first < after->first - image.timestamp)) {
      nearest = std::prev(after);
    }
    if (std::abs(nearest->first - image.timestamp) <= kStampTolerance) {
      at_images[image.index] = nearest->second;
    }
  }
  if (at_images.empty()) {
    throw InputError(trajectory,
                     "holds no pose at the time stamp of any of the map's images (within 10 ms)");
  }
  return at_images;
}

void ParseOdometrySigma(const std::string& text, PoseGraphOptions& graph) {
  std::stringstream fields(text);
  double metres = 0, radians = 0;
  char comma = 0;
  std::string rest;
  if (!(fields >> metres >> comma >> radians) || comma != ',' || (fields >> rest) ||
      !std::isfinite(metres) || !std::isfinite(radians) || metres <= 0 || radians <= 0) {
    throw ParameterError("--odometry-sigma",
                         "--odometry-sigma: expected METRES,RADIANS, both over 0 (e.g. "
                         "0.05,0.02), not '" +
                             text + "'");
  }
  graph.odometry_sigma_metres = metres;
  graph.odometry_sigma_radians = radians;
}

PoseArray ParsePose(const std::string& text, const std::string& option) {
  PoseArray pose{};
  std::stringstream fields(text);
  size_t count = 0;
  for (std::string field; std::getline(fields, field, ',');) {
    char* end = nullptr;
    const double value = std::strtod(field.c_str(), &end);
    if (field.empty() || *end != '\0' || !std::isfinite(value) || count == pose.size()) {
      count = pose.size() + 1;
      break;
    }
    pose[count++] = value;
  }
  const double norm = std::hypot(pose[3], pose[4], pose[5]) + std::abs(pose[6]);
  if (count != pose.size() || norm == 0) {
    throw ParameterError(option, option + ": '" + text +
                                     "' is not seven numbers tx,ty,tz,qx,qy,qz,qw (a quaternion "
                                     "not all 0)");
  }
  return pose;
}

void WriteLoopClosures(const std::vector<ExportedLoopClosure>& loops, ExportFormat format,
                       const CameraIntrinsics& intrinsics, const std::string& path,
                       const std::vector<MapImage>& images, const PoseGraphOptions& graph) {
  if (format == ExportFormat::kJson) {
    throw Error("WriteLoopClosures writes g2o and pairs; JSON is the tool's (memloop export)");
  }
  if (!intrinsics.known()) {
    throw ParameterError("--intrinsics", std::string("--format ") +
                                             (format == ExportFormat::kG2o ? "g2o" : "pairs") +
                                             " writes relative poses: give the camera's "
                                             "--intrinsics fx,fy,cx,cy");
  }
  std::ostringstream out;
  if (format == ExportFormat::kG2o) {
    WriteG2o(loops, images, graph, out);
  } else {
    WritePairs(loops, out);
  }
  WriteWholeFile(path, "the export file", out.str());
}

}  // namespace memloop
