#include "memloop/map_info.h"

#include <algorithm>

#include "detector/checkpoint.h"
#include "memloop/loop_closure_edits.h"
#include "storage/ltm_database.h"

namespace memloop {

namespace {

// The images and locations of the last checkpoint not yet in LTM (a map not closed: a run
// killed, or going on).
void AddCheckpoint(LtmDatabase& database, MapInfo& info) {
  const auto checkpoint = database.ReadMemoryLocations();
  info.checkpoint_locations = static_cast<long long>(checkpoint.size());
  const std::vector<LocationId> in_ltm = database.ReadLocationIds();  // sorted
  for (const auto& [id, bytes] : checkpoint) {
    if (std::binary_search(in_ltm.begin(), in_ltm.end(), id)) continue;  // counted there
    const Location location = DecodeLocation(bytes);
    info.images += static_cast<long long>(location.images.size());
    for (ImageIndex image : location.images) info.last_image = std::max(info.last_image, image);
  }
  if (const auto counters = ReadCheckpointCounters(database)) {
    info.last_image = std::max(info.last_image, counters->last_image);
  }
}

}  // namespace

MapInfo InspectMap(const std::string& path, MapCheck check) {
  // kRead checks identity and runs quick_check; kPeek checks identity only.
  LtmDatabase database(
      path, check == MapCheck::kFull ? LtmDatabase::Mode::kRead : LtmDatabase::Mode::kPeek);
  MapInfo info;
  info.path = path;
  info.writer_pid = MapWriterProcess(path);
  database.Begin();  // one snapshot: a writer's later commits are not half seen
  info.format_version = database.format_version();
  const std::string checkpoint_problem =
      check == MapCheck::kFull ? CheckpointProblem(database) : std::string();
  info.integrity = !checkpoint_problem.empty()
                       ? "resume checkpoint damaged (" + checkpoint_problem + ")"
                   : check == MapCheck::kFull ? "ok"
                                              : "not checked here (memloop inspect checks it)";
  info.locations = database.CountLocations();
  info.words = check == MapCheck::kFull ? database.CountWords() : -1;  // a scan of every word
  info.whole_images = database.CountWholeImages();
  info.neighbour_links = database.QueryNumber("SELECT count(*) FROM links WHERE type=0");
  info.loop_closure_links = database.QueryNumber("SELECT count(*) FROM links WHERE type=1");
  info.images = database.QueryNumber("SELECT count(DISTINCT image) FROM location_images");
  info.last_image = static_cast<ImageIndex>(
      database.QueryNumber("SELECT coalesce(max(image), -1) FROM location_images"));
  if (checkpoint_problem.empty()) AddCheckpoint(database, info);  // else what LTM holds alone
  for (const ForeignPlace& place : database.ReadForeignPlaces()) ++info.foreign_places[place.robot];
  const std::vector<MapLoopClosure> detected = database.ReadLoopClosures();
  const std::vector<LoopClosureEdit> edits = database.ReadEdits();
  info.loop_closures = EditedLoopClosures(detected, edits);
  long long added = 0;
  for (MapLoopClosure& loop : info.loop_closures) {
    if (loop.added_by_edit == 0) continue;
    ++added;
    loop.query_location = database.ReadHolder(loop.query_image);
    loop.match_location = database.ReadHolder(loop.match_image);
  }
  info.rejected_loop_closures =
      static_cast<long long>(detected.size() + added - info.loop_closures.size());
  info.edits = std::count_if(edits.begin(), edits.end(), [](const LoopClosureEdit& edit) {
    return !edit.undone && edit.action != EditAction::kUndo;
  });
  info.sessions = database.ReadSessions();
  for (auto& [key, value] : database.ReadInfoWithPrefix("param.")) {
    info.parameters.emplace_back(key.substr(6), value);
  }
  database.Commit();
  return info;
}

std::vector<MapImage> ReadMapImages(const std::string& path) {
  LtmDatabase database(path, LtmDatabase::Mode::kRead);
  return database.ReadImages();
}

}  // namespace memloop
