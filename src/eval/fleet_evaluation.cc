#include "memloop/fleet_evaluation.h"

#include <fstream>
#include <unordered_map>

#include "eval/csv_line.h"
#include "memloop/errors.h"

namespace memloop {

FleetTruth ReadFleetPairs(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path, "cannot be read");
  std::string line;
  if (!std::getline(in, line) ||
      SplitCsvLine(line) != std::vector<std::string>{"robot", "image", "other", "other_image"}) {
    throw InputError(path, "not a fleet's pairs (the header is not robot,image,other,other_image)");
  }
  FleetTruth truth;
  for (int number = 2; std::getline(in, line); ++number) {
    if (line.empty() || line == "\r") continue;
    const std::vector<std::string> fields = SplitCsvLine(line);
    const std::string where = "line " + std::to_string(number) + ": ";
    if (fields.size() != 4) {
      throw InputError(path, where + "has " + std::to_string(fields.size()) + " fields, not 4");
    }
    for (const std::string& field : fields) {
      if (field.empty()) throw InputError(path, where + "a field is empty");
    }
    if (fields[0] == fields[2]) {
      throw InputError(path, where + "pairs robot " + fields[0] +
                                 " with itself (its own loop closures are its ground truth's)");
    }
    truth[{fields[0], fields[1]}].insert({fields[2], fields[3]});
    truth[{fields[2], fields[3]}].insert({fields[0], fields[1]});
  }
  return truth;
}

namespace {

void Add(const FleetRobotEvaluation& robot, FleetRobotEvaluation& total) {
  total.images += robot.images;
  total.shared_images += robot.shared_images;
  total.detections += robot.detections;
  total.true_positives += robot.true_positives;
  total.false_positives += robot.false_positives;
  total.ignored += robot.ignored;
  total.found_images += robot.found_images;
}

}  // namespace

FleetEvaluation EvaluateFleet(const std::vector<FleetRun>& runs, const FleetGroundTruth& ground) {
  const FleetTruth& truth = ground.same_place;
  // Each robot's image names by index, as its run gave them.
  std::map<std::string, std::unordered_map<ImageIndex, std::string>> names;
  for (const FleetRun& run : runs) {
    auto& by_index = names[run.robot];
    for (const RunRow& row : run.rows) by_index[row.image] = row.name;
  }
  FleetEvaluation evaluation;
  evaluation.total.robot = "all";
  for (const FleetRun& run : runs) {
    FleetRobotEvaluation robot;
    robot.robot = run.robot;
    for (const RunRow& row : run.rows) {
      ++robot.images;
      const auto same = truth.find({run.robot, row.name});
      bool shared = false;
      if (same != truth.end()) {
        for (const auto& [other, image] : same->second) shared = shared || names.count(other) > 0;
      }
      robot.shared_images += shared;
      if (row.matched_robot.empty() || row.matched_images.empty()) continue;
      const auto other = names.find(row.matched_robot);
      if (other == names.end()) {
        throw InputError(run.robot, "image " + row.name + " closed a loop with robot " +
                                        row.matched_robot + "'s place: give that robot's run too");
      }
      bool correct = false, ignored = false;
      const auto band = ground.ignored.find({run.robot, row.name});
      for (ImageIndex match : row.matched_images) {
        const auto name = other->second.find(match);
        if (name == other->second.end()) {
          throw InputError(run.robot, "image " + row.name + " names image " +
                                          std::to_string(match) + " of robot " + row.matched_robot +
                                          ", which its run does not hold");
        }
        const std::pair<std::string, std::string> matched(row.matched_robot, name->second);
        correct = correct || (same != truth.end() && same->second.count(matched) > 0);
        ignored = ignored || (band != ground.ignored.end() && band->second.count(matched) > 0);
      }
      if (!correct && ignored) {
        ++robot.ignored;
        continue;
      }
      ++robot.detections;
      robot.true_positives += correct;
      robot.false_positives += !correct;
      robot.found_images += correct && shared;
    }
    Add(robot, evaluation.total);
    evaluation.robots.push_back(robot);
  }
  return evaluation;
}

}  // namespace memloop
