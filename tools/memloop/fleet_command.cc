// memloop fleet init URI [--robot NAME ...]: a PostgreSQL database made ready for a fleet's map.
// memloop fleet eval PAIRS ROBOT=RUN.csv ...: the loop closures robots made with each other's
// places, against the places they share.
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <nlohmann/json.hpp>

#include "commands.h"
#include "memloop/errors.h"
#include "memloop/fleet.h"
#include "memloop/fleet_evaluation.h"
#include "storage/sql_connection.h"

namespace memloop::cli {

namespace {

double Percent(int part, int whole) { return whole == 0 ? 0 : 100.0 * part / whole; }

nlohmann::json ToJson(const FleetRobotEvaluation& robot) {
  return {
      {"robot", robot.robot},
      {"images", robot.images},
      {"shared_images", robot.shared_images},
      {"detections", robot.detections},
      {"true_positives", robot.true_positives},
      {"false_positives", robot.false_positives},
      {"ignored", robot.ignored},
      {"precision", robot.detections == 0 ? 1.0 : 1.0 * robot.true_positives / robot.detections},
      {"recall", robot.shared_images == 0 ? 0.0 : 1.0 * robot.found_images / robot.shared_images}};
}

void AddFleetEvalCommand(CLI::App& fleet) {
  struct Arguments {
    std::string pairs;
    std::vector<std::string> runs;
    std::string ignore;
    bool json = false;
  };
  auto arguments = std::make_shared<Arguments>();
  CLI::App* eval = fleet.add_subcommand(
      "eval",
      "The loop closures each robot made with other robots' places: precision, and recall over "
      "its images that show a place another robot saw");
  eval->add_option("pairs", arguments->pairs,
                   "fleet_pairs.csv (robot,image,other,other_image), or the folder memloop "
                   "generate --robots wrote")
      ->required();
  eval->add_option("runs", arguments->runs, "ROBOT=RUN.csv for each robot (memloop run --out)")
      ->required();
  eval->add_option("--ignore", arguments->ignore,
                   "Pairs in the same format on which a detection counts neither as true nor as "
                   "false (default: fleet_ignore.csv beside the pairs, when there)");
  eval->add_flag("--json", arguments->json, "Print JSON");
  eval->callback([arguments] {
    std::string pairs = arguments->pairs;
    std::error_code error;
    if (std::filesystem::is_directory(pairs, error)) pairs += "/fleet_pairs.csv";
    FleetGroundTruth truth{ReadFleetPairs(pairs), {}};
    std::string ignore = arguments->ignore;
    const std::string beside =
        (std::filesystem::path(pairs).parent_path() / "fleet_ignore.csv").string();
    if (ignore.empty() && std::filesystem::exists(beside, error)) ignore = beside;
    if (!ignore.empty()) truth.ignored = ReadFleetPairs(ignore);
    std::vector<FleetRun> runs;
    for (const std::string& run : arguments->runs) {
      const size_t equals = run.find('=');
      if (equals == std::string::npos || equals == 0 || equals + 1 == run.size()) {
        throw InputError(run, "not ROBOT=RUN.csv");
      }
      runs.push_back({run.substr(0, equals), ReadRunCsv(run.substr(equals + 1))});
    }
    const FleetEvaluation evaluation = EvaluateFleet(runs, truth);
    if (arguments->json) {
      nlohmann::json robots = nlohmann::json::array();
      for (const FleetRobotEvaluation& robot : evaluation.robots) robots.push_back(ToJson(robot));
      std::cout << nlohmann::json{{"robots", robots}, {"all", ToJson(evaluation.total)}}.dump(2)
                << "\n";
      return;
    }
    std::printf("%-8s %7s %7s %10s %5s %5s %7s %10s %8s\n", "robot", "images", "shared",
                "detections", "true", "false", "ignored", "precision", "recall");
    std::vector<FleetRobotEvaluation> rows = evaluation.robots;
    rows.push_back(evaluation.total);
    for (const FleetRobotEvaluation& robot : rows) {
      std::printf("%-8s %7d %7d %10d %5d %5d %7d %9.1f%% %7.1f%%\n", robot.robot.c_str(),
                  robot.images, robot.shared_images, robot.detections, robot.true_positives,
                  robot.false_positives, robot.ignored,
                  robot.detections == 0 ? 100.0 : Percent(robot.true_positives, robot.detections),
                  Percent(robot.found_images, robot.shared_images));
    }
  });
}

}  // namespace

void AddFleetCommand(CLI::App& app) {
  CLI::App* fleet = app.add_subcommand("fleet",
                                       "A map that many robots share, on a PostgreSQL "
                                       "server (docs/fleet.md)");
  fleet->require_subcommand(1);
  struct Arguments {
    std::string uri;
    std::vector<std::string> robots;
  };
  auto arguments = std::make_shared<Arguments>();
  CLI::App* init = fleet->add_subcommand(
      "init",
      "Create the fleet's tables, their row-level security and the robots' roles in the "
      "database URI names (idempotent: a fleet's rows are kept)");
  init->add_option("uri", arguments->uri,
                   "postgresql://USER@HOST/DBNAME, connecting as a role that may create schemas "
                   "and roles")
      ->required()
      ->check([](const std::string& uri) {
        return IsServerMap(uri) ? std::string() : "not a postgresql:// URI: " + uri;
      });
  init->add_option("--robot", arguments->robots,
                   "A robot's name: its database role is created if missing (repeatable)");
  init->callback([arguments] {
    InitFleet(arguments->uri, arguments->robots);
    std::cout << "fleet ready in " << WithoutPassword(arguments->uri) << " ("
              << arguments->robots.size() << " robot role(s) added or kept)\n";
  });
  AddFleetEvalCommand(*fleet);
}

}  // namespace memloop::cli
