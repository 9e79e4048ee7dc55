#include "memloop/map_info.h"

#include <algorithm>

#include "detector/checkpoint.h"
#include "storage/ltm_database.h"

namespace memloop {

MapInfo InspectMap(const std::string& path) {
  LtmDatabase database(path, LtmDatabase::Mode::kRead);  // checks identity and quick_check
  MapInfo info;
  info.path = path;
  info.format_version = database.format_version();
  info.integrity = "ok";
  info.locations = database.CountLocations();
  info.words = database.CountWords();
  info.neighbour_links = database.QueryNumber("SELECT count(*) FROM links WHERE type=0");
  info.loop_closure_links = database.QueryNumber("SELECT count(*) FROM links WHERE type=1");
  info.images = database.QueryNumber("SELECT count(DISTINCT image) FROM location_images");
  ImageIndex last = static_cast<ImageIndex>(
      database.QueryNumber("SELECT coalesce(max(image), -1) FROM location_images"));
  // A map not closed (a run killed, or going on) keeps its newest locations in the checkpoint.
  const auto checkpoint = database.ReadMemoryLocations();
  info.checkpoint_locations = static_cast<long long>(checkpoint.size());
  const std::vector<LocationId> in_ltm = database.ReadLocationIds();  // sorted
  for (const auto& [id, bytes] : checkpoint) {
    if (std::binary_search(in_ltm.begin(), in_ltm.end(), id)) continue;  // counted there
    const Location location = DecodeLocation(bytes);
    info.images += static_cast<long long>(location.images.size());
    for (ImageIndex image : location.images) last = std::max(last, image);
  }
  if (const auto counters = ReadCheckpointCounters(database)) {
    last = std::max(last, counters->last_image);
  }
  info.last_image = last;
  info.loop_closures = database.ReadLoopClosures();
  for (auto& [key, value] : database.ReadInfoWithPrefix("param.")) {
    info.parameters.emplace_back(key.substr(6), value);
  }
  return info;
}

}  // namespace memloop
