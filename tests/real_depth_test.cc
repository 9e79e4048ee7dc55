// Loop closures' metric transforms on real RGB-D data: tum_fr1_rpy (../shared/datasets, or the
// folder MEMLOOP_DATASETS names) with its depth maps and calibration, against the motion capture's
// relative poses. A fresh clone has no data set: the test skips, saying so.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "cli_helpers.h"
#include "detector/loop_geometry.h"
#include "memloop/detector.h"
#include "memloop/image_sequence.h"
#include "memloop/odometry_drift.h"
#include "temp_dir.h"

namespace memloop {
namespace {

std::string TumRpy() {
  const char* given = std::getenv("MEMLOOP_DATASETS");
  return std::string(given != nullptr && *given != '\0' ? given : MEMLOOP_DATASETS) +
         "/tum_fr1_rpy";
}

struct Rigid {
  cv::Matx33d rotation;
  cv::Vec3d translation;
  double timestamp = 0;
  cv::Vec4d quaternion;
};

// poses.csv: file,timestamp,source_file,tx,ty,tz,qx,qy,qz,qw (the camera in the mocap frame).
std::map<std::string, Rigid> ReadPoses(const std::string& path) {
  std::ifstream in(path);
  std::map<std::string, Rigid> poses;
  std::string line;
  std::getline(in, line);
  while (std::getline(in, line)) {
    std::vector<std::string> cells;
    std::istringstream row(line);
    for (std::string cell; std::getline(row, cell, ',');) cells.push_back(cell);
    if (cells.size() != 10) continue;
    const cv::Vec4d q(std::stod(cells[6]), std::stod(cells[7]), std::stod(cells[8]),
                      std::stod(cells[9]));
    poses["images/" + cells[0]] = {
        RotationOf({q[0], q[1], q[2], q[3]}),
        cv::Vec3d(std::stod(cells[3]), std::stod(cells[4]), std::stod(cells[5])),
        std::stod(cells[1]), q};
  }
  return poses;
}

double Percentile(std::vector<double> values, double fraction) {
  std::sort(values.begin(), values.end());
  return values[static_cast<size_t>(std::lround(fraction * (values.size() - 1)))];
}

struct TransformErrors {
  int loops = 0, metric = 0;
  std::vector<double> degrees, metres;
};

// The frames of index `parity` modulo 2 (each half a run of its own, on images the other never
// sees), with depth and the benchmark's calibration; each metric loop closure's transform
// against inverse(T_match) T_query from the motion capture.
TransformErrors RunHalf(int parity, const std::map<std::string, Rigid>& poses,
                        const std::string& map) {
  Options options;
  options.memory.time_limit_ms = 0;
  options.camera = {517.3, 516.5, 318.6, 255.3};
  Detector detector(options, map);
  auto sequence = ImageSequence::Open(TumRpy());  // rgb.txt and depth.txt
  TransformErrors errors;
  Frame frame;
  while (sequence->Next(&frame)) {
    if (frame.index % 2 != parity || !frame.error.empty()) continue;
    const Result result =
        detector.Process(frame.image, frame.depth, {frame.index, frame.name, frame.timestamp});
    if (!result.HasLoopClosure()) continue;
    ++errors.loops;
    const LoopGeometry& g = result.loop_closure_geometry;
    if (!g.has_pose || !g.translation_metric) continue;
    ++errors.metric;
    const Rigid& query = poses.at(frame.name);
    const Rigid& match = poses.at(sequence->NameOf(g.match_view));
    const cv::Matx33d true_rotation = match.rotation.t() * query.rotation;
    const cv::Vec3d true_translation = match.rotation.t() * (query.translation - match.translation);
    const cv::Matx33d error = true_rotation.t() * RotationOf(g.quaternion);
    const double cosine = std::clamp((cv::trace(error) - 1) / 2, -1.0, 1.0);
    errors.degrees.push_back(std::acos(cosine) * 180 / CV_PI);
    errors.metres.push_back(cv::norm(
        cv::Vec3d(g.translation[0], g.translation[1], g.translation[2]) - true_translation));
  }
  return errors;
}

// TUM-format lines "time tx ty tz qx qy qz qw".
std::string TumLines(const std::vector<double>& stamps, const std::vector<CameraPose>& poses) {
  std::string text;
  char line[256];
  for (size_t i = 0; i < poses.size(); ++i) {
    const CameraPose& p = poses[i];
    std::snprintf(line, sizeof(line), "%.6f %.6f %.6f %.6f %.9f %.9f %.9f %.9f\n", stamps[i],
                  p.position[0], p.position[1], p.position[2], p.quaternion[0], p.quaternion[1],
                  p.quaternion[2], p.quaternion[3]);
    text += line;
  }
  return text;
}

// `map`'s loop closures over odometry made from the motion capture with a known drift, optimized
// by examples/03_pose_graph: the trajectory error before and after. Measured on the even frames:
// rotation RMSE 10.5 degrees with the drifting odometry, 2.2 optimized; positions (the camera
// moves 0.2 m in all) 6.7 mm and 14.8 mm: the loop closures' centimetre noise.
void ExpectThePoseGraphUndoesTheDrift(const std::string& map,
                                      const std::map<std::string, Rigid>& poses) {
  const char* kSigma = "0.01,0.02";  // per frame of a hand-held camera at 30 Hz
  const std::string example = std::string(MEMLOOP_BUILD_DIR) + "/examples/03_pose_graph";
  if (!std::filesystem::exists(example)) {
    std::cout << example << " was not built (Ceres): no pose graph\n";
    return;
  }
  testing::TempDir dir;
  std::vector<std::pair<double, CameraPose>> by_time;
  for (const auto& [name, pose] : poses) {
    by_time.push_back({pose.timestamp, {pose.translation, pose.quaternion}});
  }
  std::sort(by_time.begin(), by_time.end(),
            [](const auto& a, const auto& b) { return a.first < b.first; });
  std::vector<double> stamps;
  std::vector<CameraPose> truth;
  for (const auto& [stamp, pose] : by_time) stamps.push_back(stamp), truth.push_back(pose);
  std::ofstream(dir.File("truth.txt")) << TumLines(stamps, truth);
  // A hand-held camera turning where it stands: a gyroscope's bias, 0.05 degrees a frame.
  OdometryDrift drift;
  drift.yaw_degrees_per_step = 0.05;
  std::ofstream(dir.File("odometry.txt")) << TumLines(stamps, DriftedOdometry(truth, drift));
  const Outcome exported =
      Memloop("export " + map + " --format g2o --poses " + dir.File("odometry.txt") +
              " --odometry-sigma " + kSigma + " --out " + dir.File("graph.g2o"));
  ASSERT_EQ(exported.exit_code, 0) << exported.output;
  const Outcome optimized = Shell(example + " " + dir.File("graph.g2o") + " " + map + " " +
                                  dir.File("optimized.txt") + " " + dir.File("truth.txt"));
  ASSERT_EQ(optimized.exit_code, 0) << optimized.output;
  double before = -1, after = -1, degrees_before = -1, degrees_after = -1;
  const size_t at = optimized.output.find("ATE over ");
  ASSERT_NE(at, std::string::npos) << optimized.output;
  ASSERT_EQ(std::sscanf(optimized.output.c_str() + at,
                        "ATE over %*d poses: odometry %lf m, optimized %lf m; rotation RMSE: "
                        "odometry %lf deg, optimized %lf deg",
                        &before, &after, &degrees_before, &degrees_after),
            4)
      << optimized.output;
  // The camera hardly moves (0.2 m in all): what drifts and what the loop closures correct is
  // its rotation.
  EXPECT_LT(degrees_after, degrees_before / 2);
  std::cout << optimized.output;
}

// Measured on all frames (bench/pose_error.py): 174 of 176 loop closures metric, rotation error
// median 0.91 degrees (95th percentile 2.4), translation 1.4 cm (95th 2.8 cm). Each half of the
// frames, run alone, must hold the medians the issue set (2 degrees, 3 cm); the even half's map
// then closes a pose graph (one test: ctest runs each in a process of its own, and the runs are
// the cost).
TEST(RealDepthTest, TumRpyTransformsMatchTheMotionCaptureAndCloseAPoseGraph) {
  if (!std::filesystem::exists(TumRpy() + "/depth.txt")) {
    GTEST_SKIP() << TumRpy() << " with depth is absent (it ships beside the project)";
  }
  const std::map<std::string, Rigid> poses = ReadPoses(TumRpy() + "/poses.csv");
  testing::TempDir dir;
  for (int parity : {0, 1}) {
    const std::string map = dir.File("half" + std::to_string(parity) + ".db");
    const TransformErrors errors = RunHalf(parity, poses, map);
    ASSERT_GT(errors.loops, 30) << parity;
    EXPECT_GE(errors.metric, errors.loops * 9 / 10) << parity;
    EXPECT_LE(Percentile(errors.degrees, 0.5), 2.0) << parity;
    EXPECT_LE(Percentile(errors.metres, 0.5), 0.03) << parity;
    std::cout << (parity == 0 ? "even" : "odd") << " frames: " << errors.metric << " of "
              << errors.loops << " loop closures metric; rotation error median "
              << Percentile(errors.degrees, 0.5) << " deg (95th "
              << Percentile(errors.degrees, 0.95) << "), translation median "
              << Percentile(errors.metres, 0.5) << " m (95th " << Percentile(errors.metres, 0.95)
              << ")\n";
    if (parity == 0) ExpectThePoseGraphUndoesTheDrift(map, poses);
  }
}

}  // namespace
}  // namespace memloop
