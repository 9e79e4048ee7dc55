#include "node_configuration.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <map>

#include "memloop/errors.h"
#include "memloop/params.h"
#include "util/output_files.h"

namespace memloop::node {
namespace {

// "memory/time_limit_ms" -> "memory.time_limit_ms".
std::string RegistryKey(std::string name) {
  std::replace(name.begin(), name.end(), '/', '.');
  return name;
}

bool IsTrue(const std::string& name, const std::string& value) {
  if (value == "true" || value == "1") return true;
  if (value == "false" || value == "0") return false;
  throw ParameterError(name, "~" + name + ": '" + value + "' is not true or false");
}

}  // namespace

const std::vector<std::string>& NodeParameterNames() {
  static const std::vector<std::string> names = {
      "database",        "resume", "new_session", "localization", "queue",
      "image_transport", "depth",  "depth_scale", "preset",       "config"};
  return names;
}

NodeConfiguration Configure(const std::vector<std::pair<std::string, std::string>>& parameters,
                            const std::string& default_database) {
  std::map<std::string, std::string> own;
  std::vector<std::pair<std::string, std::string>> registry;
  for (const auto& [name, value] : parameters) {
    const auto& names = NodeParameterNames();
    if (std::find(names.begin(), names.end(), name) != names.end()) {
      own[name] = value;
    } else if (FindParameter(RegistryKey(name)) != nullptr) {
      registry.emplace_back(name, value);
    } else {
      throw ParameterError(
          name,
          "~" + name +
              ": unknown parameter (the node's own: ~database, ~resume, "
              "~new_session, ~localization, ~queue, ~image_transport, "
              "~depth, ~depth_scale, ~preset, ~config; the detector's: `memloop params`, with "
              "'/' for '.')");
    }
  }
  const auto flag = [&](const std::string& name) {
    return own.count(name) > 0 && IsTrue(name, own[name]);
  };
  NodeConfiguration configuration;
  configuration.database = own.count("database") ? own["database"] : default_database;
  configuration.queue = flag("queue");
  if (own.count("image_transport")) configuration.image_transport = own["image_transport"];
  if (configuration.image_transport != "raw" && configuration.image_transport != "compressed") {
    throw ParameterError("image_transport", "~image_transport: '" + configuration.image_transport +
                                                "' is not raw or compressed");
  }
  configuration.depth = flag("depth");
  if (configuration.depth && configuration.image_transport != "raw") {
    throw ParameterError("depth",
                         "~depth pairs raw images with raw depth maps: leave "
                         "~image_transport raw");
  }
  if (own.count("depth_scale")) {
    char* end = nullptr;
    const double units = std::strtod(own["depth_scale"].c_str(), &end);
    if (end == own["depth_scale"].c_str() || *end != '\0' || !std::isfinite(units) || units <= 0) {
      throw ParameterError("depth_scale", "~depth_scale: '" + own["depth_scale"] +
                                              "' is not a 16UC1 depth map's units per metre "
                                              "(over 0)");
    }
    configuration.depth_units_per_metre = units;
  }
  const bool resume = flag("resume");
  const bool new_session = flag("new_session");
  const bool localization = flag("localization");
  if (resume + new_session + localization > 1) {
    throw ParameterError("resume", "~resume, ~new_session and ~localization: set one at most");
  }
  const std::string& database = configuration.database;
  std::error_code error;
  const bool exists = std::filesystem::exists(database, error);
  const bool extends = (resume && exists) || new_session || localization;
  if (extends && own.count("preset")) {
    throw ParameterError("preset", "~preset: the map " + database +
                                       " exists, and its own parameters apply (~resume, "
                                       "~new_session and ~localization use them)");
  }
  if (!own.count("config")) own["config"] = "";
  CheckOutputsAreNotInputs({{"~config", own["config"]}}, {{"~database", database}});
  configuration.options =
      extends ? ReadMapOptions(database) : Preset(own.count("preset") ? own["preset"] : "default");
  if (!own["config"].empty()) ApplyParameterFile(configuration.options, own["config"]);
  for (const auto& [name, value] : registry) {
    try {
      SetParameter(configuration.options, RegistryKey(name) + "=" + value);
    } catch (const ParameterError& refused) {
      throw ParameterError(name, "~" + name + ": " + refused.what());
    }
  }
  if (localization) configuration.options.memory.localization = 1;
  configuration.mode = new_session        ? MapMode::kNewSession
                       : resume && exists ? MapMode::kResume
                                          : MapMode::kNew;
  if (resume && !exists) {
    configuration.notice = "no map at " + database + " yet: a new map is started there";
  }
  return configuration;
}

}  // namespace memloop::node
