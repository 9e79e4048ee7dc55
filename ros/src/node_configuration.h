// The memloop node's configuration from its private parameters, apart from ROS: the parameters
// come in as (name, value) pairs as ROS names them ("memory/time_limit_ms"), so that a ROS 2
// node would use this file as it is.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "memloop/detector.h"
#include "memloop/options.h"

namespace memloop::node {

struct NodeConfiguration {
  Options options;
  MapMode mode = MapMode::kNew;
  std::string database;  // the map file (~database)
  bool queue = false;    // ~queue: every image in order; false: the newest (LiveDetector)
  std::string image_transport = "raw";  // ~image_transport: raw or compressed
  // ~depth: each image with the depth map of the depth topic stamped nearest it (raw images).
  bool depth = false;
  double depth_units_per_metre = 1000;  // ~depth_scale: a 16UC1 map's units per metre
  std::string notice;                   // a line for the log ("resuming map.db ..."), "" for none
};

// The node's own parameters, beside the registry's.
const std::vector<std::string>& NodeParameterNames();

// `parameters`: every private parameter set, as (name below the node, value as text). Order: the
// preset (~preset) or, resuming / adding a session / localizing, the map's own parameters; then
// ~config (a parameter file, as `memloop run --config`); then each registry parameter. Throws
// ParameterError or InputError naming the parameter as ~name: an unknown name, an invalid value,
// a combination the CLI refuses too (~resume with ~new_session, ~preset with an existing map).
// ~resume on a map file that does not exist yet starts a new map there (a robot's first start).
NodeConfiguration Configure(const std::vector<std::pair<std::string, std::string>>& parameters,
                            const std::string& default_database);

}  // namespace memloop::node
