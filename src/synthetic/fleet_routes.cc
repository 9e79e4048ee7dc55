#include "memloop/fleet_routes.h"

#include <algorithm>
#include <filesystem>

#include "memloop/errors.h"
#include "synthetic/synthetic_view.h"
#include "util/output_files.h"

namespace memloop {
namespace {

constexpr int kCorridorGap = 4;  // steps between two robots' detours: no overlap

std::vector<RouteSegment> PlanOf(int robot, const SyntheticRouteOptions& options) {
  const int lap = options.lap_frames, detour = options.detour_frames;
  if (robot == 0) return {{true, 0, lap}, {false, 0, detour}};
  // A stretch of half the loop, a quarter further on for each robot (within the loop).
  const int stretch = lap / 2;
  const int first = lap / 10 + ((robot - 1) * lap / 4) % (lap - stretch - lap / 10);
  return {{false, robot * (detour + kCorridorGap), detour}, {true, first, stretch}};
}

}  // namespace

FleetRoutes::FleetRoutes(int robots, const SyntheticRouteOptions& options) {
  if (robots < 2 || robots > 26) throw Error("a generated fleet has 2 to 26 robots");
  std::vector<std::vector<RouteSegment>> plans;
  int detour_steps = 0;
  for (int robot = 0; robot < robots; ++robot) {
    plans.push_back(PlanOf(robot, options));
    detour_steps = std::max(detour_steps, SyntheticRoute::DetourSteps(plans.back()));
  }
  for (int robot = 0; robot < robots; ++robot) {
    routes_.emplace_back(options, plans[robot], robot, detour_steps);
  }
}

std::string FleetRoutes::RobotName(int robot) {
  return std::string(1, static_cast<char>('a' + robot));
}

std::vector<FleetPair> FleetRoutes::Pairs() const {
  std::vector<FleetPair> pairs;
  for (int robot = 0; robot < robots(); ++robot) {
    for (int other = 0; other < robots(); ++other) {
      if (other == robot) continue;
      for (int frame = 0; frame < routes_[robot].size(); ++frame) {
        for (int other_frame = 0; other_frame < routes_[other].size(); ++other_frame) {
          if (routes_[robot].SamePlace(frame, routes_[other], other_frame)) {
            pairs.push_back({robot, frame, other, other_frame});
          }
        }
      }
    }
  }
  return pairs;
}

void FleetRoutes::Write(const std::string& folder, const std::function<void(int)>& written) const {
  const std::string pairs_path = folder + "/fleet_pairs.csv";
  std::error_code error;
  if (std::filesystem::exists(pairs_path, error)) {
    throw InputError(pairs_path,
                     "exists: generate writes a new fleet and overwrites nothing; "
                     "give a new or empty folder");
  }
  int done = 0;
  for (int robot = 0; robot < robots(); ++robot) {
    const SyntheticRoute& route = routes_[robot];
    route.Write(folder + "/" + RobotName(robot), [&](int count) {
      if (written) written(done + count);
    });
    done += route.size();
  }
  std::string csv = "robot,image,other,other_image\n";
  for (const FleetPair& pair : Pairs()) {
    csv += RobotName(pair.robot) + "," + FrameName(GeneratedLayout::kImages, pair.frame) + "," +
           RobotName(pair.other) + "," + FrameName(GeneratedLayout::kImages, pair.other_frame) +
           "\n";
  }
  WriteWholeFile(pairs_path, "the fleet's ground truth", csv);
}

}  // namespace memloop
