// Robots of a fleet find the places other robots mapped: three robot processes at once on the
// generated fleet's routes (memloop generate --robots 3), against a real PostgreSQL server the
// tests start (fleet_fixture.h).
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>

#include <chrono>
#include <fstream>
#include <iostream>
#include <thread>

#include "cli_helpers.h"
#include "fleet_fixture.h"
#include "memloop/fleet_evaluation.h"
#include "memloop/fleet_routes.h"
#include "memloop/map_info.h"
#include "memloop/run_csv.h"

namespace memloop {
namespace {

using testing::FleetTest;
using testing::PostgresServer;
using testing::Server;

// Waits for `child`; its exit code, or -signal.
int ExitCode(pid_t child) {
  int status = 0;
  waitpid(child, &status, 0);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -WTERMSIG(status);
}

// Waits until `csv` has `rows` rows or `child` has ended; false when it ended first.
bool WaitForRows(pid_t child, const std::string& csv, int rows) {
  while (CsvRows(csv) < rows) {
    int status = 0;
    if (waitpid(child, &status, WNOHANG) == child) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  return true;
}

double Recall(const FleetRobotEvaluation& robot) {
  return robot.shared_images == 0 ? 0 : 1.0 * robot.found_images / robot.shared_images;
}

// Robot a maps the whole loop (at a camera's 20 Hz, its WM bounded so that its places reach the
// server as it goes); b and c, which pass stretches of it after detours of their own, start
// while a is still running, once a has put its loop on the server (a's progress, not time, says
// when), and catch up with the fleet before their first image. b is killed with -9 on the way
// and resumed. Whatever the machine's speed: every loop closure with another robot's place is
// true, and b and c find most of the images they share with a.
TEST_F(FleetTest, ThreeRobotsAtOnceCloseLoopsWithEachOthersPlaces) {
  const std::string fleet = NewFleet("three", {"a", "b", "c"});
  testing::TempDir dir;
  const FleetRoutes routes(3);
  routes.Write(dir.path().string());
  const std::string uri = Server().Uri("", fleet);
  const auto run = [&](const std::string& robot, std::vector<std::string> extra) {
    std::vector<std::string> arguments = {
        "run",   dir.File(robot + "/images"), "--db", uri, "--robot", robot,
        "--out", dir.File(robot + ".csv")};
    arguments.insert(arguments.end(), extra.begin(), extra.end());
    arguments.insert(arguments.end(), {"--set", "memory.time_limit_ms=0"});
    return Start(arguments, dir.File(robot + ".log"));
  };
  const pid_t a = run("a", {"--pace", "20", "--set", "memory.max_wm_locations=20"});
  const int a_images = routes.route(0).size();
  ASSERT_TRUE(WaitForRows(a, dir.File("a.csv"), a_images - 15)) << ReadFile(dir.File("a.log"));
  const pid_t b = run("b", {"--fleet-catch-up"});
  const pid_t c = run("c", {"--fleet-catch-up"});
  // a, paced at 20 Hz, has 15 images (at least 0.75 s) to go: the three run at once. Not
  // asserted: a test process descheduled that long would see a ended, and no verdict below
  // depends on it.
  const int b_killed = SignalAfterRows(b, dir.File("b.csv"), 45, SIGKILL);
  EXPECT_EQ(ExitCode(a), 0) << ReadFile(dir.File("a.log"));
  EXPECT_EQ(ExitCode(c), 0) << ReadFile(dir.File("c.log"));
  ASSERT_TRUE(WIFSIGNALED(b_killed)) << ReadFile(dir.File("b.log"));
  EXPECT_TRUE(Contains(ReadFile(dir.File("b.log")), "places of other robots joined the map"))
      << ReadFile(dir.File("b.log"));
  const Outcome resumed = Memloop("run " + dir.File("b/images") + " --db '" + uri +
                                  "' --robot b --resume --out " + dir.File("b.csv"));
  ASSERT_EQ(resumed.exit_code, 0) << resumed.output;
  EXPECT_TRUE(Contains(resumed.output, "(robot a image ")) << resumed.output;

  std::vector<FleetRun> runs;
  for (const std::string robot : {"a", "b", "c"}) {
    runs.push_back({robot, ReadRunCsv(dir.File(robot + ".csv"))});
  }
  const FleetEvaluation evaluation =
      EvaluateFleet(runs, {ReadFleetPairs(dir.File("fleet_pairs.csv")), {}});
  ASSERT_EQ(evaluation.robots.size(), 3u);
  EXPECT_EQ(evaluation.total.false_positives, 0);
  for (int robot : {1, 2}) {
    const FleetRobotEvaluation& found = evaluation.robots[robot];
    EXPECT_EQ(found.shared_images, routes.route(robot).size() - 30) << found.robot;
    EXPECT_GE(Recall(found), 0.75)
        << found.robot << ": " << found.found_images << " of " << found.shared_images;
    std::cout << "robot " << found.robot << ": inter-robot recall " << Recall(found) << " ("
              << found.found_images << "/" << found.shared_images << "), " << found.false_positives
              << " false\n";
  }
  // Each stored once, in the robot's map, naming the other robot's place and image.
  const MapInfo map = InspectMap(Server().Uri("b", fleet));
  EXPECT_EQ(map.integrity, "ok");
  EXPECT_GT(map.foreign_places.at("a"), 20);
  int with_others = 0;  // a's places, and c's once c has stored them
  for (const MapLoopClosure& loop : map.loop_closures) with_others += !loop.match_robot.empty();
  EXPECT_EQ(with_others, evaluation.robots[1].detections);
  const Outcome inspect = Memloop("inspect '" + Server().Uri("b", fleet) + "'");
  EXPECT_TRUE(Contains(inspect.output, "places of robot a: ")) << inspect.output;
  EXPECT_TRUE(Contains(inspect.output, "-> robot a image ")) << inspect.output;
  const Outcome exported =
      Memloop("export '" + Server().Uri("c", fleet) + "' --out " + dir.File("c.json"));
  ASSERT_EQ(exported.exit_code, 0) << exported.output;
  EXPECT_TRUE(Contains(ReadFile(dir.File("c.json")), "\"match_robot\": \"a\""));
  const Outcome table = Memloop("fleet eval " + dir.path().string() + " a=" + dir.File("a.csv") +
                                " b=" + dir.File("b.csv") + " c=" + dir.File("c.csv"));
  EXPECT_EQ(table.exit_code, 0) << table.output;
  EXPECT_TRUE(Contains(table.output, "precision")) << table.output;
}

// The tool's refusals, one line each.
TEST(FleetEvalTool, RefusesWhatItCannotJudge) {
  testing::TempDir dir;
  const std::string pairs = dir.File("pairs.csv");
  std::ofstream(pairs) << "robot,image,other,other_image\na,1.png,a,2.png\n";
  Outcome refused = Memloop("fleet eval " + pairs + " a=x.csv");
  EXPECT_NE(refused.exit_code, 0);
  EXPECT_TRUE(Contains(refused.output, "line 2: pairs robot a with itself")) << refused.output;
  std::ofstream(pairs) << "query,match\n1.png,2.png\n";
  refused = Memloop("fleet eval " + pairs + " a=x.csv");
  EXPECT_TRUE(Contains(refused.output, "not a fleet's pairs")) << refused.output;
  std::ofstream(pairs) << "robot,image,other,other_image\na,1.png,b\n";
  refused = Memloop("fleet eval " + pairs + " a=x.csv");
  EXPECT_TRUE(Contains(refused.output, "line 2: has 3 fields, not 4")) << refused.output;
  std::ofstream(pairs) << "robot,image,other,other_image\na,1.png,b,1.png\n";
  refused = Memloop("fleet eval " + pairs + " a.csv");
  EXPECT_TRUE(Contains(refused.output, "a.csv: not ROBOT=RUN.csv")) << refused.output;
}

}  // namespace
}  // namespace memloop
