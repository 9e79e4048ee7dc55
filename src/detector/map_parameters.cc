#include "detector/map_parameters.h"

#include "detector/checkpoint.h"
#include "memloop/detector.h"
#include "memloop/errors.h"
#include "memloop/params.h"

namespace memloop {

Options OptionsOf(LtmDatabase& database) {
  Options options;
  for (const Parameter& parameter : Parameters()) {
    const std::string value = database.ReadInfo("param." + parameter.key);
    if (value.empty()) continue;  // a parameter newer than the map: its default
    try {
      parameter.Set(options, value);
    } catch (const Error& error) {
      throw DatabaseError(database.path(),
                          std::string("its parameter table is damaged (") + error.what() + ")");
    }
  }
  return options;
}

void CheckMapParameters(LtmDatabase& database, const Options& options) {
  const char* use = options.memory.localization ? "localize against it" : "resume";
  const Options map_options = OptionsOf(database);
  std::string differences;
  for (const Parameter& parameter : Parameters()) {
    if (!parameter.DefinesMap()) continue;
    const std::string map_value = parameter.Get(map_options);
    const std::string value = parameter.Get(options);
    if (map_value == value) continue;
    differences += (differences.empty() ? "" : ", ") + parameter.key + " (map: " + map_value +
                   ", given: " + value + ")";
  }
  if (!differences.empty()) {
    throw ParameterError(
        "", database.path() + ": cannot " + use +
                " with other values of parameters that define the map: " + differences);
  }
}

MapProgress ReadMapProgress(const std::string& path) {
  LtmDatabase database(path, LtmDatabase::Mode::kRead);
  // A run killed before its first checkpoint leaves a map that holds nothing: resumed, it starts
  // afresh (Detector, MapMode::kResume).
  if (MapHoldsNoImage(database)) return MapProgress();
  const std::optional<DetectorCounters> counters = ReadCheckpointCounters(database);
  if (!counters) {
    throw DatabaseError(path,
                        "has no resume checkpoint (the run that made it stopped before its first "
                        "one was committed): start a new map instead");
  }
  MapProgress progress;
  progress.last_image = counters->last_image;
  progress.images_processed = counters->images_processed;
  const std::vector<MapSession> sessions = database.ReadSessions();
  if (!sessions.empty()) progress.last_session = sessions.back();
  return progress;
}

Options ReadMapOptions(const std::string& path) {
  LtmDatabase database(path, LtmDatabase::Mode::kRead);
  return OptionsOf(database);
}

}  // namespace memloop
