// memloop export MAP.db [--format json|g2o|pairs] [--intrinsics fx,fy,cx,cy] [--poses TRAJECTORY]
// [--camera-to-base tx,ty,tz,qx,qy,qz,qw] --out FILE: the map's loop closures for a SLAM back-end,
// read without changing the map.
#include <iostream>
#include <nlohmann/json.hpp>

#include "command_files.h"
#include "commands.h"
#include "memloop/detector.h"
#include "memloop/errors.h"
#include "memloop/map_export.h"
#include "memloop/map_info.h"

namespace memloop::cli {
namespace {

nlohmann::json Stamp(double timestamp) {
  return HasTimestamp(timestamp) ? nlohmann::json(timestamp) : nlohmann::json(nullptr);
}

nlohmann::json ImageJson(const MapImage& image, LocationId location) {
  return {{"image", image.index},
          {"name", image.name},
          {"timestamp", Stamp(image.timestamp)},
          {"session", image.session},
          {"location", location}};
}

nlohmann::json Json(const std::vector<ExportedLoopClosure>& loops,
                    const CameraIntrinsics& intrinsics) {
  nlohmann::json rows = nlohmann::json::array();
  for (const ExportedLoopClosure& loop : loops) {
    const LoopGeometry& g = loop.geometry;
    nlohmann::json inliers = nlohmann::json::array();
    for (const PointPair& pair : g.inliers) {
      inliers.push_back({pair.query_x, pair.query_y, pair.match_x, pair.match_y});
    }
    nlohmann::json pose = nullptr;
    if (g.has_pose) {
      pose = {{"rotation", g.rotation},
              {"quaternion_xyzw", g.quaternion},
              {"translation",
               g.translation_known ? nlohmann::json(g.translation) : nlohmann::json(nullptr)},
              {"translation_metric", g.translation_metric},
              {"inliers", g.pose_inliers},
              {"source", g.pose_from_detection ? "detection" : "export"}};
    }
    rows.push_back(
        {{"query", ImageJson(loop.query, loop.loop.query_location)},
         {"match", ImageJson(loop.match, loop.loop.match_location)},
         // A fleet's map: the robot whose image `match` is (null: this map's own).
         {"match_robot", loop.loop.match_robot.empty() ? nlohmann::json(nullptr)
                                                       : nlohmann::json(loop.loop.match_robot)},
         {"hypothesis_value", loop.loop.probability},
         {"added_by_edit", loop.loop.added_by_edit},  // 0: detected (memloop view's edits)
         {"views", {g.query_view, g.match_view}},
         {"correspondences", g.correspondences},
         {"inliers", inliers},
         {"pose", pose},
         {"pose_reason", g.has_pose ? nlohmann::json(nullptr) : nlohmann::json(g.pose_problem)}});
  }
  nlohmann::json camera = nullptr;
  if (intrinsics.known()) {
    camera = {
        {"fx", intrinsics.fx}, {"fy", intrinsics.fy}, {"cx", intrinsics.cx}, {"cy", intrinsics.cy}};
  }
  return {{"intrinsics", camera},
          {"pose_convention",
           "x_match = R x_query + t, |t| = 1 (the query camera in the match "
           "camera's frame; a single camera gives no scale)"},
          {"loop_closures", rows}};
}

CameraIntrinsics MapCamera(const std::string& map) {
  const CameraOptions camera = ReadMapOptions(map).camera;
  return {camera.fx, camera.fy, camera.cx, camera.cy};
}

}  // namespace

void AddExportCommand(CLI::App& app) {
  struct Arguments {
    std::string map;
    std::string format = "json";
    std::string intrinsics;
    std::string poses;
    std::string camera_to_base;
    std::string odometry_sigma;
    std::string out;
  };
  auto arguments = std::make_shared<Arguments>();
  CLI::App* command = app.add_subcommand(
      "export",
      "A map's loop closures for a SLAM back-end: both images (name, index, time stamp, session), "
      "the hypothesis value, the epipolar inliers and, with --intrinsics, the relative pose");
  command->add_option("map", arguments->map, "Map database file (--db of a run)")->required();
  command->add_option("--format", arguments->format,
                      "json (everything), g2o (a pose graph: loop-closure edges, with --poses "
                      "vertices and odometry edges) or pairs (both images' time stamps and the "
                      "relative pose per line); g2o and pairs need intrinsics");
  command->add_option("--intrinsics", arguments->intrinsics,
                      "Camera intrinsics fx,fy,cx,cy in pixels: the relative pose from the "
                      "essential matrix; default: the map's camera.fx..cy, if set");
  command->add_option("--poses", arguments->poses,
                      "g2o: a TUM trajectory (time tx ty tz qx qy qz qw) of the images' time "
                      "stamps, odometry or any estimate: a vertex per image it holds, odometry "
                      "edges between them, the first fixed");
  command->add_option("--camera-to-base", arguments->camera_to_base,
                      "g2o: the camera's pose tx,ty,tz,qx,qy,qz,qw in the frame of --poses (the "
                      "robot's base): loop closures become edges between bases");
  command->add_option("--odometry-sigma", arguments->odometry_sigma,
                      "g2o: the odometry edges' standard deviations METRES,RADIANS per edge "
                      "(default 0.05,0.02)");
  command->add_option("--out", arguments->out, "File to write")->required();
  command->callback([arguments] {
    const ExportFormat format = ParseExportFormat(arguments->format);
    std::vector<NamedPath> inputs = MapFiles(arguments->map, "the map");
    inputs.push_back({"the trajectory (--poses)", arguments->poses});
    CheckOutputsAreNotInputs(inputs, {{"--out", arguments->out}});
    PoseGraphOptions graph;
    graph.trajectory = arguments->poses;
    if (!arguments->camera_to_base.empty()) {
      graph.camera_to_base = ParsePose(arguments->camera_to_base, "--camera-to-base");
    }
    if (!arguments->odometry_sigma.empty()) ParseOdometrySigma(arguments->odometry_sigma, graph);
    if (format != ExportFormat::kG2o &&
        (!graph.trajectory.empty() || !arguments->camera_to_base.empty() ||
         !arguments->odometry_sigma.empty())) {
      throw ParameterError("--poses",
                           "--poses, --camera-to-base and --odometry-sigma make a g2o pose graph: "
                           "give --format g2o");
    }
    // Without --intrinsics, the map's own (camera.fx..cy, with which its poses were found).
    const CameraIntrinsics intrinsics = arguments->intrinsics.empty()
                                            ? MapCamera(arguments->map)
                                            : ParseIntrinsics(arguments->intrinsics);
    if (format != ExportFormat::kJson && !intrinsics.known()) {
      throw ParameterError("--intrinsics", "--format " + arguments->format +
                                               " writes relative poses: give the camera's "
                                               "--intrinsics fx,fy,cx,cy (the map has none)");
    }
    if (const long writer = MapWriterProcess(arguments->map); writer != 0) {
      std::cout << "note: " << arguments->map << " is being written by another process"
                << (writer > 0 ? " (pid " + std::to_string(writer) + ")" : std::string())
                << ": this exports what it has committed so far\n";
    }
    const std::vector<ExportedLoopClosure> loops = ExportLoopClosures(arguments->map, intrinsics);
    if (format == ExportFormat::kJson) {
      WriteWholeFile(arguments->out, "the export file", Json(loops, intrinsics).dump(2) + "\n");
    } else {
      WriteLoopClosures(loops, format, intrinsics, arguments->out, ReadMapImages(arguments->map),
                        graph);
    }
    int posed = 0;
    for (const ExportedLoopClosure& loop : loops) posed += loop.geometry.has_pose;
    std::cout << "exported " << loops.size() << " loop closures to " << arguments->out;
    if (intrinsics.known()) std::cout << " (" << posed << " with a relative pose)";
    std::cout << "\n";
  });
}

}  // namespace memloop::cli
