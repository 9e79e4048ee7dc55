// A fleet's runs against the ground truth of the places robots share (memloop fleet eval): the
// loop closures a robot made with another robot's places (RunRow::matched_robot), judged by the
// images both robots gave. Each run's loop closures with its own places are `memloop eval`'s.
#pragma once

#include <map>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "memloop/run_csv.h"

namespace memloop {

// Which images of two robots show the same place: (robot, image name) -> (other robot, image
// name), both ways.
using FleetTruth =
    std::map<std::pair<std::string, std::string>, std::set<std::pair<std::string, std::string>>>;

// Reads "robot,image,other,other_image" lines after that header (memloop generate --robots
// writes fleet_pairs.csv). Throws InputError naming the file and line: unreadable, another header,
// a line without four fields, an empty name, a robot paired with itself.
FleetTruth ReadFleetPairs(const std::string& path);

struct FleetRun {
  std::string robot;
  std::vector<RunRow> rows;
};

// A fleet's ground truth: the pairs that show the same place, and (as a data set's
// ground_truth_ignore.csv) those a detection on which counts neither as true nor as false.
struct FleetGroundTruth {
  FleetTruth same_place;
  FleetTruth ignored;
};

struct FleetRobotEvaluation {
  std::string robot;
  int images = 0;
  // Its images that show a place another robot of the runs saw (the truth's, whatever the order
  // the robots went in: one that came first could not find the others' places).
  int shared_images = 0;
  int detections = 0;  // loop closures with another robot's place
  int true_positives = 0;
  int false_positives = 0;
  int ignored = 0;       // detections on the ignored band only
  int found_images = 0;  // shared images with a true one
};

struct FleetEvaluation {
  std::vector<FleetRobotEvaluation> robots;  // in the order of the runs
  FleetRobotEvaluation total;                // robot "all"
};

// A detection is true when an image it matched shows the same place, ignored when one is on the
// ignored band, false otherwise. Throws InputError when a run names a robot whose run is not
// given, or an image that run does not hold.
FleetEvaluation EvaluateFleet(const std::vector<FleetRun>& runs, const FleetGroundTruth& truth);

}  // namespace memloop
