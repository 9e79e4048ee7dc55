// The geometry of each loop closure for a SLAM back-end: in Result as it is found (camera.fx..cy
// set), and from the map by `ExportLoopClosures`, the same for the same two views.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <opencv2/imgcodecs.hpp>
#include <sstream>

#include "cli_helpers.h"
#include "memloop/detector.h"
#include "memloop/errors.h"
#include "memloop/map_export.h"
#include "memloop/synthetic_route.h"
#include "short_route.h"
#include "temp_dir.h"

namespace memloop {
namespace {

Options WithCamera() {
  Options options;
  options.memory.time_limit_ms = 0;
  options.camera = {300, 300, 160, 120};
  return options;
}

// The short route mapped into `map` with the camera known: its accepted loop closures.
std::vector<Result> AcceptedOnTheShortRoute(const std::string& map) {
  const SyntheticRoute route(testing::ShortRoute());
  Detector detector(WithCamera(), map);
  std::vector<Result> accepted;
  for (int i = 0; i < route.size(); ++i) {
    Result result = detector.Process(route.Render(i), i);
    if (result.HasLoopClosure()) accepted.push_back(std::move(result));
  }
  return accepted;
}

// A run CSV's rows as column name -> cell (a quoted cell keeps its quotes).
std::vector<std::map<std::string, std::string>> CsvTable(const std::string& path) {
  std::istringstream in(ReadFile(path));
  std::string line;
  std::getline(in, line);
  std::vector<std::string> names;
  std::istringstream header(line);
  for (std::string name; std::getline(header, name, ',');) names.push_back(name);
  std::vector<std::map<std::string, std::string>> rows;
  while (std::getline(in, line)) {
    std::istringstream row(line);
    std::map<std::string, std::string>& cells = rows.emplace_back();
    size_t column = 0;
    for (std::string cell; column < names.size() && std::getline(row, cell, ',');) {
      cells[names[column++]] = cell;
    }
    for (; column < names.size(); ++column) cells[names[column]];
  }
  return rows;
}

TEST(LoopGeometryResultTest, AcceptedLoopClosuresCarryTheGeometryTheExportGives) {
  testing::TempDir dir;
  const std::string map = dir.File("map.db");
  const std::vector<Result> accepted = AcceptedOnTheShortRoute(map);
  ASSERT_GT(accepted.size(), 20u);
  int with_inliers = 0;
  int posed = 0;
  for (const Result& result : accepted) {
    const LoopGeometry& g = result.loop_closure_geometry;
    // The images whose keypoints the two locations hold: the image or one Rehearsal merged into
    // its location, and one of the matched location's images.
    EXPECT_LE(g.query_view, result.image_index);
    EXPECT_NE(std::find(result.loop_closure_images.begin(), result.loop_closure_images.end(),
                        g.match_view),
              result.loop_closure_images.end());
    EXPECT_GE(g.correspondences, static_cast<int>(g.inliers.size()));
    with_inliers += !g.inliers.empty();
    if (!g.has_pose) continue;
    ++posed;
    // A rotation (R R^T = I) and a direction.
    for (int row = 0; row < 3; ++row) {
      for (int column = 0; column < 3; ++column) {
        double dot = 0;
        for (int k = 0; k < 3; ++k) dot += g.rotation[row * 3 + k] * g.rotation[column * 3 + k];
        EXPECT_NEAR(dot, row == column ? 1 : 0, 1e-6);
      }
    }
    EXPECT_NEAR(std::hypot(g.translation[0], g.translation[1], g.translation[2]),
                g.translation_known ? 1 : 0, 1e-6);
    EXPECT_LE(g.pose_inliers, static_cast<int>(g.inliers.size()));
  }
  EXPECT_GT(with_inliers, 0);
  EXPECT_GT(posed, 0);

  // The export of the closed map: each loop closure between the same two images, with the pose
  // found at detection.
  const std::vector<ExportedLoopClosure> exported = ExportLoopClosures(map, {300, 300, 160, 120});
  ASSERT_EQ(exported.size(), accepted.size());
  for (size_t k = 0; k < accepted.size(); ++k) {
    const LoopGeometry& found = accepted[k].loop_closure_geometry;
    EXPECT_EQ(exported[k].query.index, accepted[k].image_index);
    EXPECT_EQ(exported[k].match.index, found.match_view);
    ASSERT_EQ(exported[k].geometry.has_pose, found.has_pose);
    EXPECT_EQ(exported[k].loop.pose.inliers, static_cast<int>(found.inliers.size()));
    for (int i = 0; i < 9 && found.has_pose; ++i) {
      EXPECT_NEAR(exported[k].geometry.rotation[i], found.rotation[i], 1e-9);
    }
  }
}

// Each accepted loop closure's geometry is kept in the map as it was found (before Rehearsal
// merges its views): the export gives every one the pose the Result had, or the reason it had
// none (before: the export estimated it from the merged locations, and most had none).
TEST(LoopGeometryResultTest, TheMapKeepsEachLoopClosuresPoseOrWhyNot) {
  testing::TempDir dir;
  const std::string map = dir.File("map.db");
  const std::vector<Result> accepted = AcceptedOnTheShortRoute(map);
  const std::vector<ExportedLoopClosure> exported = ExportLoopClosures(map);
  ASSERT_EQ(exported.size(), accepted.size());
  int posed = 0, posed_before = 0;
  for (size_t k = 0; k < accepted.size(); ++k) {
    const LoopGeometry& found = accepted[k].loop_closure_geometry;
    const LoopClosurePose& kept = exported[k].loop.pose;
    EXPECT_EQ(exported[k].loop.query_image, accepted[k].image_index);
    EXPECT_TRUE(kept.estimated);
    EXPECT_EQ(kept.has_pose, found.has_pose);
    EXPECT_EQ(kept.inliers, static_cast<int>(found.inliers.size()));
    EXPECT_EQ(kept.has_pose, kept.reason.empty()) << kept.reason;
    EXPECT_EQ(kept.reason, found.pose_problem);
    const LoopGeometry& g = exported[k].geometry;
    EXPECT_TRUE(g.pose_from_detection);
    EXPECT_EQ(g.has_pose, found.has_pose);
    if (found.has_pose) {
      ++posed;
      for (int i = 0; i < 4; ++i) EXPECT_DOUBLE_EQ(kept.quaternion[i], found.quaternion[i]);
      for (int i = 0; i < 9; ++i) EXPECT_NEAR(g.rotation[i], found.rotation[i], 1e-9);
    }
  }
  // What an export from the merged locations alone finds, for comparison.
  for (const ExportedLoopClosure& loop : ExportLoopClosures(map, {301, 300, 160, 120})) {
    posed_before += loop.geometry.has_pose;
    EXPECT_FALSE(loop.geometry.pose_from_detection);  // other intrinsics: estimated anew
  }
  EXPECT_GT(posed, posed_before);
  std::printf(
      "loop closures with a pose: %d of %zu kept at detection, %d from the map's locations\n",
      posed, accepted.size(), posed_before);
}

TEST(LoopGeometryResultTest, NoIntrinsicsNoGeometryAndBothFocalLengthsNeeded) {
  testing::TempDir dir;
  const SyntheticRoute route(testing::ShortRoute());
  Options options = WithCamera();
  options.camera = {};
  {
    Detector detector(options, dir.File("plain.db"));
    for (int i = 0; i < 60; ++i) {
      const Result result = detector.Process(route.Render(i), i);
      EXPECT_EQ(result.loop_closure_geometry.correspondences, 0);
      EXPECT_TRUE(result.loop_closure_geometry.inliers.empty());
      if (result.HasLoopClosure()) {
        EXPECT_EQ(result.loop_closure_geometry.pose_problem,
                  "the camera's intrinsics are not set (camera.fx..cy)");
      }
    }
  }
  options.camera.fx = 300;
  EXPECT_THROW(Detector(options, dir.File("half.db")), ParameterError);
}

// The run CSV: every loop closure's row has the relative pose (rel_tx..rel_qw, rel_metric) or the
// reason it has none; the inliers column has the views' inliers (before: -1 on every row).
TEST(LoopGeometryResultTest, EveryLoopClosureRowHasAPoseOrAReason) {
  testing::TempDir dir;
  SyntheticRoute(testing::ShortRoute()).Write(dir.path().string());
  const std::string csv = dir.File("run.csv");
  const Outcome run = Memloop("run " + dir.File("images") + " --out " + csv +
                              " --set memory.time_limit_ms=0 camera.fx=300 camera.fy=300 "
                              "camera.cx=160 camera.cy=120");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  int loops = 0, posed = 0;
  for (const auto& row : CsvTable(csv)) {
    if (row.at("matched_image").empty()) {
      EXPECT_TRUE(row.at("rel_qw").empty() && row.at("pose_reason").empty());
      continue;
    }
    ++loops;
    const bool has_pose = !row.at("rel_qw").empty();
    posed += has_pose;
    EXPECT_NE(has_pose, row.at("pose_reason").size() > 2) << row.at("image");  // quoted
    EXPECT_EQ(row.at("rel_metric"), has_pose ? "0" : "") << row.at("image");   // no depth
    EXPECT_GE(std::stoi(row.at("inliers")), 0) << row.at("image");
  }
  EXPECT_GT(loops, 20);
  EXPECT_GT(posed, 0);
}

// Writes `folder`/NAME.png for each image NAME of a TUM folder's rgb.txt: 16-bit depth maps of
// `image_size`, all `value` (the generated route is a flat world seen square on: one depth fits
// it), and with `listing`, `folder`/../depth.txt giving them by the images' time stamps.
void WriteFlatDepth(const std::string& tum, const std::string& folder, uint16_t value,
                    bool listing) {
  std::filesystem::create_directories(folder);
  std::ofstream depth_txt;
  if (listing) depth_txt.open(tum + "/depth.txt");
  std::istringstream images(ReadFile(tum + "/rgb.txt"));
  for (std::string line; std::getline(images, line);) {
    if (line.empty() || line[0] == '#') continue;
    const std::string stamp = line.substr(0, line.find(' '));
    const std::string stem = std::filesystem::path(line.substr(line.find(' ') + 1)).stem();
    const cv::Mat image = cv::imread(tum + "/" + line.substr(line.find(' ') + 1));
    cv::imwrite(folder + "/" + stem + ".png", cv::Mat(image.size(), CV_16UC1, cv::Scalar(value)));
    if (listing) depth_txt << stamp << " depth/" << stem << ".png\n";
  }
}

// With depth maps (a TUM folder's depth.txt, or --depth DIR), loop closures' translations are in
// metres: the same loop closures, twice the depth, twice the translation.
TEST(LoopGeometryResultTest, WithDepthTranslationsAreInMetres) {
  testing::TempDir dir;
  const std::string walk = dir.File("walk");
  ASSERT_EQ(Memloop("generate " + walk + " --layout tum").exit_code, 0);
  WriteFlatDepth(walk, walk + "/depth", 10000, true);  // TUM's 5000 a metre: 2 m
  WriteFlatDepth(walk, dir.File("mm"), 4000, false);   // --depth's 1000 a metre: 4 m
  const std::string settings =
      " --set memory.time_limit_ms=0 camera.fx=300 camera.fy=300 camera.cx=160 camera.cy=120";
  const Outcome at_2m = Memloop("run " + walk + " --out " + dir.File("2m.csv") + settings);
  ASSERT_EQ(at_2m.exit_code, 0) << at_2m.output;
  const Outcome at_4m = Memloop("run " + walk + " --depth " + dir.File("mm") + " --out " +
                                dir.File("4m.csv") + settings);
  ASSERT_EQ(at_4m.exit_code, 0) << at_4m.output;
  const auto near = CsvTable(dir.File("2m.csv")), far = CsvTable(dir.File("4m.csv"));
  ASSERT_EQ(near.size(), far.size());
  int metric = 0, loops = 0;
  for (size_t i = 0; i < near.size(); ++i) {
    ASSERT_EQ(near[i].at("matched_image"), far[i].at("matched_image"));  // detection unchanged
    if (near[i].at("matched_image").empty()) continue;
    ++loops;
    if (near[i].at("rel_metric") != "1") continue;
    ++metric;
    ASSERT_EQ(far[i].at("rel_metric"), "1") << i;
    for (const char* axis : {"rel_tx", "rel_ty", "rel_tz"}) {
      EXPECT_NEAR(std::stod(far[i].at(axis)), 2 * std::stod(near[i].at(axis)), 1e-4)
          << i << " " << axis;
    }
    EXPECT_NEAR(std::stod(far[i].at("rel_qw")), std::stod(near[i].at("rel_qw")), 1e-6) << i;
  }
  EXPECT_GT(loops, 20);
  EXPECT_GE(metric, loops * 9 / 10);
}

// `export --format g2o --poses TRAJECTORY` of a run: a vertex per image, the first fixed, an
// odometry edge between consecutive images, and an edge per loop closure with a pose.
TEST(LoopGeometryResultTest, ExportWithATrajectoryIsAWholePoseGraph) {
  testing::TempDir dir;
  ASSERT_EQ(Memloop("generate " + dir.File("walk") + " --layout tum").exit_code, 0);
  const std::string map = dir.File("map.db");
  ASSERT_EQ(Memloop("run " + dir.File("walk") + " --db " + map +
                    " --set memory.time_limit_ms=0 camera.fx=300 camera.fy=300 camera.cx=160 "
                    "camera.cy=120")
                .exit_code,
            0);
  std::ofstream trajectory(dir.File("odometry.txt"));  // the listing's stamps, 10 cm apart
  std::istringstream listing(ReadFile(dir.File("walk/rgb.txt")));
  int images = 0;
  for (std::string line; std::getline(listing, line);) {
    if (line.empty() || line[0] == '#') continue;
    trajectory << line.substr(0, line.find(' ')) << " " << 0.1 * images++ << " 0 0 0 0 0 1\n";
  }
  trajectory.close();
  const Outcome outcome = Memloop("export " + map + " --format g2o --poses " +
                                  dir.File("odometry.txt") + " --out " + dir.File("graph.g2o"));
  ASSERT_EQ(outcome.exit_code, 0) << outcome.output;
  std::map<std::string, int> records;
  int loops = 0;
  std::istringstream graph(ReadFile(dir.File("graph.g2o")));
  for (std::string line; std::getline(graph, line);) {
    const std::string tag = line.substr(0, line.find(' '));
    ++records[tag];
    int from = 0, to = 0;
    if (tag == "EDGE_SE3:QUAT" &&
        std::sscanf(line.c_str(), "EDGE_SE3:QUAT %d %d", &from, &to) == 2) {
      loops += to != from + 1;
    }
  }
  EXPECT_EQ(records["VERTEX_SE3:QUAT"], images);
  EXPECT_EQ(records["FIX"], 1);
  EXPECT_EQ(records["EDGE_SE3:QUAT"] - loops, images - 1);  // odometry
  EXPECT_GT(loops, 20);
  EXPECT_TRUE(Contains(outcome.output, "(" + std::to_string(loops) + " with a relative pose)"))
      << outcome.output;
}

}  // namespace
}  // namespace memloop
