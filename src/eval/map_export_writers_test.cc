#include <gtest/gtest.h>

#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "memloop/errors.h"
#include "memloop/map_export.h"
#include "temp_dir.h"

namespace memloop {
namespace {

ExportedLoopClosure Loop(ImageIndex query, ImageIndex match, bool posed) {
  ExportedLoopClosure loop;
  loop.query.index = query;
  loop.match.index = match;
  loop.geometry.has_pose = posed;
  loop.geometry.translation = {1, 0, 0};
  loop.geometry.quaternion = {0, 0, 0, 1};
  if (!posed) loop.geometry.pose_problem = "5 word correspondences";
  return loop;
}

std::vector<MapImage> Images(const std::vector<double>& stamps) {
  std::vector<MapImage> images;
  for (size_t i = 0; i < stamps.size(); ++i) {
    MapImage image;
    image.index = static_cast<ImageIndex>(i);
    image.timestamp = stamps[i];
    images.push_back(image);
  }
  return images;
}

std::vector<std::string> Lines(const std::string& path) {
  std::ifstream in(path);
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("# memloop", 0) != 0) lines.push_back(line);
  }
  return lines;
}

// A trajectory makes the g2o file a graph g2o loads as it is: a vertex per image it holds (the
// nearest stamp within 10 ms), the first fixed, odometry edges between consecutive vertices, and
// the loop closures; the rotation's information in g2o's convention (half the angle).
TEST(PoseGraphExportTest, VerticesOdometryAndLoopClosuresWithAFixedFirstVertex) {
  testing::TempDir dir;
  const std::string trajectory = dir.File("odometry.txt");
  std::ofstream(trajectory) << "# timestamp tx ty tz qx qy qz qw\n"
                               "1.0 0 0 0 0 0 0 1\n"
                               "2.0 1 0 0 0 0 0 1\n"
                               "3.0 2 0 0 0 0 0.7071067811865476 0.7071067811865476\n";
  PoseGraphOptions graph;
  graph.trajectory = trajectory;
  const std::string out = dir.File("graph.g2o");
  WriteLoopClosures({Loop(2, 0, true), Loop(3, 1, false)}, ExportFormat::kG2o, {300, 300, 160, 120},
                    out, Images({1.0, 2.0, 3.004, 10.0}), graph);
  const std::string odometry_information =
      " 400 0 0 0 0 0 400 0 0 0 0 400 0 0 0 10000 0 0 10000 0 10000";
  EXPECT_EQ(Lines(out),
            (std::vector<std::string>{
                "VERTEX_SE3:QUAT 0 0.000000000 0.000000000 0.000000000 0.000000000 0.000000000 "
                "0.000000000 1.000000000",
                "VERTEX_SE3:QUAT 1 1.000000000 0.000000000 0.000000000 0.000000000 0.000000000 "
                "0.000000000 1.000000000",
                "VERTEX_SE3:QUAT 2 2.000000000 0.000000000 0.000000000 0.000000000 0.000000000 "
                "0.707106781 0.707106781",
                "FIX 0",
                "EDGE_SE3:QUAT 0 1 1.000000000 0.000000000 0.000000000 0.000000000 0.000000000 "
                "0.000000000 1.000000000" +
                    odometry_information,
                "EDGE_SE3:QUAT 1 2 1.000000000 0.000000000 0.000000000 0.000000000 0.000000000 "
                "0.707106781 0.707106781" +
                    odometry_information,
                "EDGE_SE3:QUAT 0 2 1.000000000 0.000000000 0.000000000 0.000000000 0.000000000 "
                "0.000000000 1.000000000 1e-06 0 0 0 0 0 1e-06 0 0 0 0 1e-06 0 0 0 1600 0 0 1600 "
                "0 1600",
                "# image 3 -> image 1: no relative pose (5 word correspondences)"}));
}

// The camera turned 90 degrees about the base's z axis: a loop closure's translation, a
// direction along the camera's x, is along the base's y; a rotation about that axis stays one.
TEST(PoseGraphExportTest, CameraToBaseTurnsLoopClosuresIntoTheBasesFrame) {
  testing::TempDir dir;
  PoseGraphOptions graph;
  graph.camera_to_base = ParsePose("0.5,0,0.2,0,0,0.7071067811865476,0.7071067811865476", "x");
  ExportedLoopClosure loop = Loop(2, 0, true);
  loop.geometry.quaternion = {0, 0, 0.25881904510252074, 0.9659258262890683};  // 30 deg about z
  const std::string out = dir.File("graph.g2o");
  WriteLoopClosures({loop}, ExportFormat::kG2o, {300, 300, 160, 120}, out, {}, graph);
  std::istringstream edge(Lines(out).at(0));
  std::string tag;
  int from = 0, to = 0;
  double pose[7];
  edge >> tag >> from >> to;
  for (double& value : pose) edge >> value;
  EXPECT_NEAR(pose[0], 0, 1e-9);
  EXPECT_NEAR(pose[1], 1, 1e-9);
  EXPECT_NEAR(pose[2], 0, 1e-9);
  EXPECT_NEAR(pose[5], 0.25881904510252074, 1e-9);
  EXPECT_NEAR(pose[6], 0.9659258262890683, 1e-9);
}

// With depth, a translation in metres: the edge takes the lever arm too (X C X^-1), and its
// translation information is 1 / (3 cm)^2 instead of a direction's 1e-6; pairs say metric 1.
TEST(PoseGraphExportTest, MetricLoopClosuresTakeTheWholeChangeOfFrame) {
  testing::TempDir dir;
  PoseGraphOptions graph;
  // The camera 0.5 m ahead of the base, turned 90 degrees about z.
  graph.camera_to_base = ParsePose("0.5,0,0,0,0,0.7071067811865476,0.7071067811865476", "x");
  ExportedLoopClosure loop = Loop(2, 0, true);
  loop.geometry.translation_metric = true;
  loop.geometry.translation = {0.2, 0, 0};  // 20 cm along the camera's x
  loop.geometry.quaternion = {0, 0, 0.7071067811865476, 0.7071067811865476};  // 90 deg about z
  const std::string out = dir.File("graph.g2o");
  WriteLoopClosures({loop}, ExportFormat::kG2o, {300, 300, 160, 120}, out, {}, graph);
  std::istringstream edge(Lines(out).at(0));
  std::string tag;
  int from = 0, to = 0;
  double values[7 + 21];
  edge >> tag >> from >> to;
  for (double& value : values) edge >> value;
  // X C X^-1 with X = (R_z(90), (0.5, 0, 0)), C = (R_z(90), (0.2, 0, 0)): the translation is
  // R_X t_C + t_X - R_X R_C R_X^T t_X = (0, 0.2, 0) + (0.5, 0, 0) - (0, 0.5, 0) = (0.5, -0.3, 0).
  EXPECT_NEAR(values[0], 0.5, 1e-9);
  EXPECT_NEAR(values[1], -0.3, 1e-9);
  EXPECT_NEAR(values[2], 0, 1e-9);
  EXPECT_NEAR(values[5], 0.7071067811865476, 1e-9);
  EXPECT_EQ(values[7], 1111);   // translation information, x
  EXPECT_EQ(values[22], 1600);  // rotation information, x

  WriteLoopClosures({loop}, ExportFormat::kPairs, {300, 300, 160, 120}, dir.File("pairs.txt"));
  const std::string pair = Lines(dir.File("pairs.txt")).at(0);
  EXPECT_EQ(pair.substr(pair.size() - 2), " 1") << pair;  // metric
}

TEST(PoseGraphExportTest, OdometrySigmaSetsTheOdometryInformation) {
  PoseGraphOptions graph;
  ParseOdometrySigma("0.01,0.1", graph);
  EXPECT_DOUBLE_EQ(graph.odometry_sigma_metres, 0.01);
  EXPECT_DOUBLE_EQ(graph.odometry_sigma_radians, 0.1);
  testing::TempDir dir;
  const std::string trajectory = dir.File("odometry.txt");
  std::ofstream(trajectory) << "1.0 0 0 0 0 0 0 1\n2.0 1 0 0 0 0 0 1\n";
  graph.trajectory = trajectory;
  WriteLoopClosures({}, ExportFormat::kG2o, {300, 300, 160, 120}, dir.File("g.g2o"),
                    Images({1.0, 2.0}), graph);
  // 1 / 0.01^2 and 4 / 0.1^2.
  EXPECT_NE(Lines(dir.File("g.g2o"))
                .at(3)
                .find(" 10000 0 0 0 0 0 10000 0 0 0 0 10000 0 0 0 400 0 0 400 0 400"),
            std::string::npos)
      << Lines(dir.File("g.g2o")).at(3);
  for (const char* bad : {"0.05", "0,0.02", "0.05,-1", "a,b", "0.05,0.02,1", "nan,0.02"}) {
    EXPECT_THROW(ParseOdometrySigma(bad, graph), ParameterError) << bad;
  }
}

TEST(PoseGraphExportTest, BadTrajectoriesPosesAndTheTumFormatAreRefusedSayingWhy) {
  testing::TempDir dir;
  const std::string bad = dir.File("bad.txt");
  std::ofstream(bad) << "1.0 0 0 0 0 0 0 1\n2.0 1 0 0\n";
  PoseGraphOptions graph;
  graph.trajectory = bad;
  try {
    WriteLoopClosures({}, ExportFormat::kG2o, {300, 300, 160, 120}, dir.File("g.g2o"),
                      Images({1.0}), graph);
    ADD_FAILURE() << "a malformed trajectory was read";
  } catch (const InputError& error) {
    EXPECT_EQ(std::string(error.what()),
              bad + ": line 2: expected 'time tx ty tz qx qy qz qw' (a TUM trajectory)");
  }
  std::ofstream(bad, std::ios::trunc) << "100.0 0 0 0 0 0 0 1\n";
  EXPECT_THROW(WriteLoopClosures({}, ExportFormat::kG2o, {300, 300, 160, 120}, dir.File("g.g2o"),
                                 Images({1.0}), graph),
               InputError);  // no image at its time stamps
  EXPECT_FALSE(std::filesystem::exists(dir.File("g.g2o")));
  EXPECT_THROW(ParsePose("1,2,3", "--camera-to-base"), ParameterError);
  EXPECT_THROW(ParsePose("0,0,0,0,0,0,0", "--camera-to-base"), ParameterError);
  try {
    ParseExportFormat("tum");
    ADD_FAILURE() << "tum accepted";
  } catch (const ParameterError& error) {
    EXPECT_NE(std::string(error.what()).find("--format pairs writes them"), std::string::npos);
  }
}

}  // namespace
}  // namespace memloop
