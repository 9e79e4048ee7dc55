// memloop inspect MAP.db [--json]: what a map holds, read without changing it.
#include <cstdio>
#include <iostream>
#include <nlohmann/json.hpp>

#include "commands.h"
#include "memloop/errors.h"
#include "memloop/map_info.h"

namespace memloop::cli {
namespace {

nlohmann::json Json(const MapInfo& info) {
  nlohmann::json loops = nlohmann::json::array();
  for (const MapLoopClosure& loop : info.loop_closures) {
    loops.push_back({{"query_image", loop.query_image},
                     {"match_image", loop.match_image},
                     {"query_location", loop.query_location},
                     {"match_location", loop.match_location},
                     {"probability", loop.probability},
                     {"added_by_edit", loop.added_by_edit},
                     {"match_robot", loop.match_robot.empty() ? nlohmann::json(nullptr)
                                                              : nlohmann::json(loop.match_robot)}});
  }
  nlohmann::json parameters = nlohmann::json::object();
  for (const auto& [name, value] : info.parameters) parameters[name] = value;
  nlohmann::json sessions = nlohmann::json::array();
  for (const MapSession& session : info.sessions) {
    const auto stamp = [](double t) { return HasTimestamp(t) ? nlohmann::json(t) : nullptr; };
    sessions.push_back({{"id", session.id},
                        {"first_image", session.first_image},
                        {"last_image", session.last_image},
                        {"images", session.images},
                        {"first_name", session.first_name},
                        {"last_name", session.last_name},
                        {"first_timestamp", stamp(session.first_timestamp)},
                        {"last_timestamp", stamp(session.last_timestamp)}});
  }
  return {{"path", info.path},
          {"writer_pid",
           info.writer_pid == 0 ? nlohmann::json(nullptr) : nlohmann::json(info.writer_pid)},
          {"format_version", info.format_version},
          {"integrity", info.integrity},
          {"images", info.images},
          {"last_image", info.last_image},
          {"ltm_locations", info.locations},
          {"checkpoint_locations", info.checkpoint_locations},
          {"words", info.words},
          {"whole_image_descriptors", info.whole_images},
          {"neighbour_links", info.neighbour_links},
          {"loop_closure_links", info.loop_closure_links},
          {"sessions", sessions},
          {"loop_closures", loops},
          {"edits", info.edits},
          {"rejected_loop_closures", info.rejected_loop_closures},
          {"foreign_places", info.foreign_places},
          {"parameters", parameters}};
}

void PrintText(const MapInfo& info) {
  std::printf("map %s (format %d, integrity: %s)\n", info.path.c_str(), info.format_version,
              info.integrity.c_str());
  if (info.writer_pid != 0) {
    std::printf(
        "being written by another process%s: what it has committed so far\n",
        info.writer_pid > 0 ? (" (pid " + std::to_string(info.writer_pid) + ")").c_str() : "");
  }
  std::printf("images: %lld (last: %d)\n", info.images, info.last_image);
  std::printf("locations: %lld in LTM, %lld in STM/WM at the last checkpoint\n", info.locations,
              info.checkpoint_locations);
  std::printf("words in LTM: %lld\n", info.words);
  if (info.whole_images > 0) {
    std::printf("whole-image descriptors in LTM: %lld\n", info.whole_images);
  }
  std::printf("links: %lld neighbour, %lld loop closure\n", info.neighbour_links,
              info.loop_closure_links);
  for (const auto& [robot, places] : info.foreign_places) {
    std::printf("places of robot %s: %lld\n", robot.c_str(), places);
  }
  std::printf("sessions: %zu\n", info.sessions.size());
  for (const MapSession& session : info.sessions) {
    std::printf("  session %d: images %d to %d (%lld), '%s' to '%s'", session.id,
                session.first_image, session.last_image, session.images, session.first_name.c_str(),
                session.last_name.c_str());
    if (HasTimestamp(session.first_timestamp) && HasTimestamp(session.last_timestamp)) {
      std::printf(", %.3f s to %.3f s", session.first_timestamp, session.last_timestamp);
    }
    std::printf("\n");
  }
  std::printf("loop closures: %zu", info.loop_closures.size());
  if (info.edits > 0) {
    std::printf(" (as edited: %lld edits, %lld detected ones rejected)", info.edits,
                info.rejected_loop_closures);
  }
  std::printf("\n");
  for (const MapLoopClosure& loop : info.loop_closures) {
    const std::string robot = loop.match_robot.empty() ? "" : "robot " + loop.match_robot + " ";
    std::printf("  image %d -> %simage %d (location %d -> %d), ", loop.query_image, robot.c_str(),
                loop.match_image, loop.query_location, loop.match_location);
    if (loop.added_by_edit > 0) {
      std::printf("added by edit %lld\n", loop.added_by_edit);
    } else {
      std::printf("p=%.3f\n", loop.probability);
    }
  }
  std::printf("parameters:\n");
  for (const auto& [name, value] : info.parameters) {
    std::printf("  %s = %s\n", name.c_str(), value.c_str());
  }
}

}  // namespace

void AddInspectCommand(CLI::App& app) {
  struct Arguments {
    std::string map;
    bool json = false;
  };
  auto arguments = std::make_shared<Arguments>();
  CLI::App* inspect =
      app.add_subcommand("inspect",
                         "What a map file holds: images, locations, words, links, loop closures, "
                         "parameters, format and integrity (the file is opened read-only)");
  inspect->add_option("map", arguments->map, "Map database file (--db of a run)")->required();
  inspect->add_flag("--json", arguments->json, "JSON object");
  inspect->callback([arguments] {
    const MapInfo info = InspectMap(arguments->map);
    if (arguments->json) {
      std::cout << Json(info).dump(2) << "\n";
    } else {
      PrintText(info);
    }
    // What is shown is readable, but the map cannot be resumed: a nonzero exit for scripts.
    if (info.integrity != "ok")
      throw DatabaseError(info.path, info.integrity + ": --resume refuses it");
  });
}

}  // namespace memloop::cli
