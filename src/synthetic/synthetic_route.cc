#include "memloop/synthetic_route.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "detector/loop_geometry.h"
#include "memloop/errors.h"
#include "memloop/odometry_drift.h"
#include "synthetic/synthetic_view.h"
#include "util/output_files.h"

namespace memloop {
namespace {

constexpr int kDetourGap = 4;  // steps: more than two image widths, no overlap

}  // namespace

std::vector<RouteSegment> SyntheticRoute::DefaultPlan(const SyntheticRouteOptions& options) {
  const int detour = options.detour_frames;
  // The second detour goes on to new places: a gap of kDetourGap steps from the first one's end.
  return {{true, 0, options.lap_frames},
          {false, 0, detour},
          {true, 0, options.lap_frames},
          {false, detour + kDetourGap, detour},
          {true, 0, options.third_lap_frames}};
}

int SyntheticRoute::DetourSteps(const std::vector<RouteSegment>& plan) {
  int steps = 0;
  for (const RouteSegment& segment : plan) {
    if (!segment.in_loop) steps = std::max(steps, segment.first_step + segment.frames);
  }
  return steps;
}

SyntheticRoute::SyntheticRoute(const SyntheticRouteOptions& options)
    : SyntheticRoute(options, DefaultPlan(options), 0, 2 * options.detour_frames + kDetourGap) {}

SyntheticRoute::SyntheticRoute(const SyntheticRouteOptions& options,
                               const std::vector<RouteSegment>& plan, int robot, int detour_steps)
    : options_(options), robot_(robot) {
  cv::RNG rng(static_cast<uint64_t>(options.seed));
  const int view_width = options.image_width;
  const int world_height = options.image_height + 60;  // room for vertical jitter
  loop_length_ = options.lap_frames * options.step_px;
  const int loop_width = static_cast<int>(std::ceil(loop_length_));
  const int wrap_width = 2 * view_width;
  const int detour_width = static_cast<int>(detour_steps * options.step_px) + wrap_width;

  const cv::Mat loop = MakeTexture(loop_width, world_height, rng, options.facades);
  const cv::Mat detour = MakeTexture(detour_width, world_height, rng, options.facades);
  world_ = cv::Mat(world_height, loop_width + wrap_width + detour_width, CV_8U);
  loop.copyTo(world_.colRange(0, loop_width));
  loop.colRange(0, wrap_width).copyTo(world_.colRange(loop_width, loop_width + wrap_width));
  detour.copyTo(world_.colRange(loop_width + wrap_width, world_.cols));

  // Robot 0's jitter follows the world's draws (the single route's images); another robot's its
  // own, so that two robots at one place see it differently.
  cv::RNG robot_rng(static_cast<uint64_t>(options.seed) * 7919u + static_cast<uint64_t>(robot));
  cv::RNG& jitter = robot == 0 ? rng : robot_rng;
  int visit = 0;
  for (const RouteSegment& segment : plan) {
    if (!segment.in_loop && segment.first_step + segment.frames > detour_steps) {
      throw Error("a route's detour goes past the world's");
    }
    for (int n = segment.first_step; n < segment.first_step + segment.frames; ++n) {
      const ViewJitter j = ViewJitter::Random(jitter);
      frames_.push_back({n * options.step_px, segment.in_loop, segment.in_loop ? visit : -1, j.dx,
                         j.dy, j.scale, j.angle_degrees, j.gain, j.bias});
    }
    visit += segment.in_loop;
  }
}

cv::Mat SyntheticRoute::Render(int index) const {
  const Frame& frame = frames_.at(index);
  const double x =
      frame.x + (frame.in_loop ? 0 : std::ceil(loop_length_) + 2 * options_.image_width);
  const ViewJitter jitter{frame.dx,   frame.dy,  frame.scale, frame.angle_degrees,
                          frame.gain, frame.bias};
  return RenderView(world_, x, 30, jitter, options_.image_width, options_.image_height,
                    static_cast<uint64_t>(options_.seed) * 1000003u + index +
                        static_cast<uint64_t>(robot_) * 100003u);
}

cv::Mat SyntheticRoute::RenderGray(int index) const {
  cv::Mat gray;
  cv::cvtColor(Render(index), gray, cv::COLOR_BGR2GRAY);
  return gray;
}

bool SyntheticRoute::IsLoop(int query, int match) const {
  const Frame& a = frames_.at(query);
  const Frame& b = frames_.at(match);
  if (match >= query || !a.in_loop || !b.in_loop) return false;
  const double same_place = options_.same_place_fraction * options_.image_width;
  const double direct = std::fabs((a.x + a.dx) - (b.x + b.dx));
  const double around = loop_length_ - direct;  // the loop closes on itself
  // Frames of one lap close to each other are neighbours, not loop closures; the lap's last
  // frames, back where it started, are.
  if (a.visit == b.visit) return direct > same_place && around <= same_place;
  return std::min(direct, around) <= same_place;
}

bool SyntheticRoute::SamePlace(int frame, const SyntheticRoute& other, int other_frame) const {
  const Frame& a = frames_.at(frame);
  const Frame& b = other.frames_.at(other_frame);
  if (!a.in_loop || !b.in_loop) return false;
  const double direct = std::fabs((a.x + a.dx) - (b.x + b.dx));
  return std::min(direct, loop_length_ - direct) <=
         options_.same_place_fraction * options_.image_width;
}

GroundTruth SyntheticRoute::Truth() const {
  cv::Mat labels(size(), size(), CV_8U, cv::Scalar(GroundTruth::kNone));
  for (const auto& [query, match] : GroundTruthPairs()) {
    labels.at<unsigned char>(query, match) = GroundTruth::kLoop;
  }
  return GroundTruth(labels);
}

std::vector<std::pair<int, int>> SyntheticRoute::GroundTruthPairs() const {
  std::vector<std::pair<int, int>> pairs;
  for (int query = 0; query < size(); ++query) {
    for (int match = 0; match < query; ++match) {
      if (IsLoop(query, match)) pairs.emplace_back(query, match);
    }
  }
  return pairs;
}

// The renderer draws a flat wall: the view's centre at texture (x + dx + W/2, 30 + dy + H/2),
// `wall_distance_m` / scale away, rolled by the jitter's angle. Here the loop is a circle and the
// wall a cylinder around it: locally flat, but two views a step apart (1.07 m with the defaults)
// are turned 4.5 degrees from each other, which their flat images do not show.
CameraPose SyntheticRoute::Pose(int index) const {
  const Frame& frame = frames_.at(index);
  const double metres_per_pixel = options_.wall_distance_m / options_.focal_px;
  const double distance = Depth(index);
  // The camera's circle is the loop's length: a step moves it as far as the images say.
  const double radius = loop_length_ * metres_per_pixel / (2 * CV_PI);
  cv::Vec3d position, right, down(0, 0, -1), forward;
  if (frame.in_loop) {
    // Facing the wall (outward); the image's right, where the texture goes on, is clockwise.
    const double angle =
        -2 * CV_PI * (frame.x + frame.dx + options_.image_width / 2.0) / loop_length_;
    forward = {std::cos(angle), std::sin(angle), 0};
    right = {std::sin(angle), -std::cos(angle), 0};
    position = (radius + options_.wall_distance_m - distance) * forward +
               metres_per_pixel * frame.dy * down;
  } else {
    // A detour: from the loop's start into the circle, facing one wall of a corridor, and back
    // facing the other; the second detour along another corridor, 30 degrees on.
    const int detour = index < options_.lap_frames + options_.detour_frames ? 0 : 1;
    const int first =
        detour == 0 ? options_.lap_frames : 2 * options_.lap_frames + options_.detour_frames;
    const int step = index - first, half = options_.detour_frames / 2;
    const double heading = CV_PI + detour * CV_PI / 6;
    const cv::Vec3d away(std::cos(heading), std::sin(heading), 0);
    const cv::Vec3d side = down.cross(away);  // to the left of `away`, seen from above
    const bool going = step < half;
    const double along =
        options_.step_px * metres_per_pixel * (going ? step + 1 : options_.detour_frames - step);
    right = going ? away : -away;
    forward = right.cross(down);
    position = radius * cv::Vec3d(1, 0, 0) + along * away + (going ? -0.5 : 0.5) * side;
  }
  // The roll: the image's x axis is the texture's (cos a, -sin a) (RenderView's rotation).
  const double roll = frame.angle_degrees * CV_PI / 180;
  const cv::Vec3d x = std::cos(roll) * right - std::sin(roll) * down;
  const cv::Vec3d y = std::sin(roll) * right + std::cos(roll) * down;
  const cv::Matx33d rotation(x[0], y[0], forward[0], x[1], y[1], forward[1], x[2], y[2],
                             forward[2]);
  const std::array<double, 4> q = QuaternionOf(rotation);
  return {position, cv::Vec4d(q[0], q[1], q[2], q[3])};
}

double SyntheticRoute::Depth(int index) const {
  return options_.wall_distance_m / frames_.at(index).scale;
}

void SyntheticRoute::Write(const std::string& folder, const std::function<void(int)>& written,
                           GeneratedLayout layout) const {
  WriteSequence(
      folder, size(), [this](int index) { return Render(index); }, GroundTruthPairs(), written,
      layout);
  if (layout == GeneratedLayout::kTum) WriteRgbd(folder);
}

// TUM RGB-D's files beside rgb.txt: depth maps (16-bit, 5000 a metre) and their listing, the
// camera's trajectory, and the camera's parameters as a --config file.
void SyntheticRoute::WriteRgbd(const std::string& folder) const {
  std::error_code error;
  std::filesystem::create_directories(folder + "/depth", error);
  if (error)
    throw InputError(folder + "/depth", "cannot create the folder (" + error.message() + ")");
  std::string depth_listing = "# depth maps\n# generated by memloop\n# timestamp filename\n";
  const char* kHeader = "# generated by memloop\n# timestamp tx ty tz qx qy qz qw\n";
  std::string trajectory = std::string("# ground truth trajectory\n") + kHeader;
  std::string odometry = std::string("# odometry (3% over-read, a yaw drift)\n") + kHeader;
  std::vector<CameraPose> poses;
  for (int index = 0; index < size(); ++index) poses.push_back(Pose(index));
  const std::vector<CameraPose> drifted = DriftedOdometry(poses);
  const auto pose_line = [](double stamp, const CameraPose& pose) {
    char text[256];
    std::snprintf(text, sizeof(text), "%.6f %.6f %.6f %.6f %.9f %.9f %.9f %.9f\n", stamp,
                  pose.position[0], pose.position[1], pose.position[2], pose.quaternion[0],
                  pose.quaternion[1], pose.quaternion[2], pose.quaternion[3]);
    return std::string(text);
  };
  char line[256];
  for (int index = 0; index < size(); ++index) {
    const std::string name = "depth/" + std::to_string(index + 1) + ".png";
    const cv::Mat depth(options_.image_height, options_.image_width, CV_16UC1,
                        cv::Scalar(std::round(Depth(index) * 5000)));
    WriteWholeFile(
        folder + "/" + name, "the depth map",
        [&](const std::string& temporary) {
          if (!cv::imwrite(temporary, depth)) {
            throw InputError(folder + "/" + name, "cannot write the depth map");
          }
        },
        /*sync=*/false);
    std::snprintf(line, sizeof(line), "%.6f %s\n", GeneratedStamp(index), name.c_str());
    depth_listing += line;
    trajectory += pose_line(GeneratedStamp(index), poses[index]);
    odometry += pose_line(GeneratedStamp(index), drifted[index]);
  }
  WriteWholeFile(folder + "/depth.txt", "the depth listing", depth_listing);
  WriteWholeFile(folder + "/groundtruth.txt", "the trajectory", trajectory);
  WriteWholeFile(folder + "/odometry.txt", "the odometry", odometry);
  std::snprintf(line, sizeof(line),
                "# the generated camera: memloop run --config camera.conf\n[camera]\nfx = %g\nfy = "
                "%g\ncx = %g\ncy = %g\n",
                options_.focal_px, options_.focal_px, options_.image_width / 2.0,
                options_.image_height / 2.0);
  WriteWholeFile(folder + "/camera.conf", "the camera's parameters", line);
}

}  // namespace memloop
