// A fleet's generated data (memloop generate FOLDER --robots N): routes of several robots over
// one generated world (synthetic_route.h), with the ground truth of which frames of two robots
// show the same place. Robot "a" maps the whole loop, then a detour of its own. Each other robot
// first goes through a detour of its own (places no other robot sees), then along a stretch of
// the loop, half its length, that robot "a" mapped; consecutive robots' stretches overlap.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "memloop/synthetic_route.h"

namespace memloop {

// Frame `frame` of robot `robot` shows the place frame `other_frame` of robot `other` shows.
struct FleetPair {
  int robot = 0;
  int frame = 0;
  int other = 0;
  int other_frame = 0;
};

class FleetRoutes {
 public:
  // Throws Error for fewer than 2 or more than 26 robots.
  explicit FleetRoutes(int robots, const SyntheticRouteOptions& options = {});

  int robots() const { return static_cast<int>(routes_.size()); }
  const SyntheticRoute& route(int robot) const { return routes_.at(robot); }
  // "a", "b", ...: the robot's folder and, by default, its role on the fleet's server.
  static std::string RobotName(int robot);
  // Every pair of frames of two different robots that show the same place, both ways.
  std::vector<FleetPair> Pairs() const;

  // Writes FOLDER/<robot>/images/1.png .. and FOLDER/<robot>/ground_truth_pairs.csv (the robot's
  // own loop closures), then FOLDER/fleet_pairs.csv: "robot,image,other,other_image" with the
  // robots' names and the images' file names, a line for each FleetPair. `written` is called
  // after each image with the number written so far (all robots).
  void Write(const std::string& folder, const std::function<void(int)>& written = {}) const;

 private:
  std::vector<SyntheticRoute> routes_;
};

}  // namespace memloop
