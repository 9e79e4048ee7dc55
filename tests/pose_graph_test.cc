// A back-end that closes the loop: a run's loop closures, exported as a g2o pose graph over the
// odometry, optimized by examples/03_pose_graph (Ceres), on the generated route whose true
// trajectory and drifting odometry `memloop generate --layout tum` writes.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include "cli_helpers.h"
#include "temp_dir.h"

namespace memloop {
namespace {

const std::string kExample = std::string(MEMLOOP_BUILD_DIR) + "/examples/03_pose_graph";

struct Ate {
  double odometry = -1, optimized = -1;
};

// The example's "ATE over N poses: odometry X m, optimized Y m" line.
Ate Optimize(const std::string& arguments) {
  const Outcome outcome = Shell(kExample + " " + arguments);
  EXPECT_EQ(outcome.exit_code, 0) << outcome.output;
  Ate ate;
  const size_t at = outcome.output.find("ATE over ");
  if (at == std::string::npos || std::sscanf(outcome.output.c_str() + at,
                                             "ATE over %*d poses: odometry %lf m, optimized %lf m",
                                             &ate.odometry, &ate.optimized) != 2) {
    ADD_FAILURE() << "no ATE line in: " << outcome.output;
  }
  return ate;
}

class PoseGraphTest : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!std::filesystem::exists(kExample)) {
      GTEST_SKIP() << kExample << " was not built (Ceres, libceres-dev, is missing)";
    }
  }
  testing::TempDir dir_;
};

// Measured: ATE 2.34 m with the odometry, 0.33 m optimized (260 poses, 118 loop closures); with
// one false loop closure added, 0.33 m with the robust loss and 8.7 m without.
TEST_F(PoseGraphTest, LoopClosuresUndoTheOdometrysDriftAndAFalseOneDoesNotUndoThat) {
  const std::string walk = dir_.File("walk"), map = dir_.File("map.db");
  ASSERT_EQ(Memloop("generate " + walk + " --layout tum").exit_code, 0);
  const Outcome run = Memloop("run " + walk + " --config " + walk + "/camera.conf --db " + map +
                              " --set memory.time_limit_ms=0");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const std::string graph = dir_.File("graph.g2o");
  const Outcome exported =
      Memloop("export " + map + " --format g2o --poses " + walk + "/odometry.txt --out " + graph);
  ASSERT_EQ(exported.exit_code, 0) << exported.output;

  const std::string truth = walk + "/groundtruth.txt", optimized = dir_.File("optimized.txt");
  const Ate ate = Optimize(graph + " " + map + " " + optimized + " " + truth);
  EXPECT_GT(ate.odometry, 1.0);  // the drift is there to correct
  EXPECT_LT(ate.optimized, ate.odometry / 2);
  std::printf("ATE: odometry %.3f m, optimized %.3f m\n", ate.odometry, ate.optimized);
  // The optimized trajectory: a TUM line per image.
  int lines = 0;
  std::ifstream in(optimized);
  for (std::string line; std::getline(in, line);) lines += !line.empty();
  EXPECT_EQ(lines, 260);

  // A false loop closure, as confident as the others, between places 20 m apart.
  const std::string with_false = dir_.File("with_false.g2o");
  std::ofstream(with_false) << ReadFile(graph)
                            << "EDGE_SE3:QUAT 40 230 0 0 0 0 0 0 1 1111 0 0 0 0 0 1111 0 0 0 0 "
                               "1111 0 0 0 1600 0 0 1600 0 1600\n";
  const Ate robust = Optimize(with_false + " " + map + " " + optimized + " " + truth);
  EXPECT_LT(robust.optimized, ate.odometry / 2);
  const Ate plain =
      Optimize("--no-robust-loss " + with_false + " " + map + " " + optimized + " " + truth);
  EXPECT_GT(plain.optimized, 3 * robust.optimized);  // what the robust loss prevents
}

TEST_F(PoseGraphTest, GraphsItCannotReadAreRefusedByName) {
  const std::string bad = dir_.File("bad.g2o");
  std::ofstream(bad) << "VERTEX_SE3:QUAT 0 0 0 0 0 0 0 1\nEDGE_SE3:QUAT 0 1 0 0\n";
  Outcome outcome = Shell(kExample + " " + bad + " map.db out.txt");
  EXPECT_EQ(outcome.exit_code, 1);
  EXPECT_TRUE(Contains(outcome.output, bad + ": line 2: not a g2o record this reads"))
      << outcome.output;
  std::string information;
  for (int i = 0; i < 21; ++i) information += " 1";
  std::ofstream(bad) << "# loop closures only\nEDGE_SE3:QUAT 3 9 0 0 0 0 0 0 1" << information
                     << "\n";
  outcome = Shell(kExample + " " + bad + " map.db out.txt");
  EXPECT_EQ(outcome.exit_code, 1);
  EXPECT_TRUE(Contains(outcome.output, "no VERTEX_SE3:QUAT (export with --poses"))
      << outcome.output;
  outcome = Shell(kExample + " " + dir_.File("missing.g2o") + " map.db out.txt");
  EXPECT_TRUE(Contains(outcome.output, "missing.g2o: cannot be read")) << outcome.output;
  EXPECT_EQ(Shell(kExample).exit_code, 2);  // usage
}

}  // namespace
}  // namespace memloop
