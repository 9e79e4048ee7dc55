#include "view/map_view.h"

#include <algorithm>
#include <filesystem>
#include <optional>

#include "detector/checkpoint.h"
#include "detector/loop_geometry.h"
#include "storage/ltm_database.h"

namespace memloop {

namespace {

using nlohmann::json;

json Stamp(double t) { return HasTimestamp(t) ? json(t) : json(nullptr); }

json PoseJson(const LoopClosurePose& pose) {
  if (!pose.estimated) return nullptr;
  json out = {{"inliers", pose.inliers}, {"reason", pose.reason}};
  if (pose.has_pose) {
    out["translation"] = pose.translation;
    out["quaternion_xyzw"] = pose.quaternion;
    out["metric"] = pose.metric;
  }
  return out;
}

std::vector<LoopClosureEdit> InForce(const std::vector<LoopClosureEdit>& edits) {
  std::vector<LoopClosureEdit> in_force;
  for (const LoopClosureEdit& edit : edits) {
    if (!edit.undone && edit.action != EditAction::kUndo) in_force.push_back(edit);
  }
  return in_force;
}

}  // namespace

MapView::MapView(const std::string& map_path)
    : path_(map_path), loaded_(Load()), loaded_state_(FileState()) {}

std::string MapView::FileState() const {
  std::string state;
  for (const std::string& file : {path_, path_ + "-wal"}) {
    std::error_code error;
    const auto size = std::filesystem::file_size(file, error);
    const auto time = std::filesystem::last_write_time(file, error);
    state += std::to_string(error ? 0 : size) + ":" +
             std::to_string(error ? 0 : time.time_since_epoch().count()) + ";";
  }
  return state;
}

void MapView::ReloadIfChanged() {
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    if (FileState() == loaded_state_) return;
  }
  Reload();
}

MapView::Loaded MapView::Load() const {
  Loaded loaded;
  // A clear error when the file is not a memloop map; its pages are not all read (a large map
  // opens in a fraction of a second: memloop inspect checks them).
  loaded.info = InspectMap(path_, MapCheck::kQuick);
  LtmDatabase database(path_, LtmDatabase::Mode::kPeek);
  database.Begin();
  loaded.images = database.ReadImages();
  for (const auto& [image, location] : database.ReadHolders()) loaded.holder[image] = location;
  for (const auto& [id, bytes] : database.ReadMemoryLocations()) {
    for (ImageIndex image : DecodeLocation(bytes).images) loaded.holder.emplace(image, id);
  }
  if (loaded.images.empty()) {  // a map made before images were recorded: indices alone
    for (const auto& [image, location] : loaded.holder) {
      MapImage unnamed;
      unnamed.index = image;
      loaded.images.push_back(unnamed);
    }
  }
  loaded.edits = database.ReadEdits();
  loaded.detected = database.ReadLoopClosures();
  for (ForeignPlace& place : database.ReadForeignPlaces()) {
    loaded.foreign[place.location] = std::move(place);
  }
  database.Commit();
  return loaded;
}

void MapView::Reload() {
  const std::string state = FileState();  // before reading: a later change is seen next time
  Loaded loaded = Load();
  const std::lock_guard<std::mutex> lock(mutex_);
  loaded_ = std::move(loaded);
  loaded_state_ = state;
}

const MapImage* MapView::FindImage(ImageIndex index) const {
  const auto found = std::lower_bound(
      loaded_.images.begin(), loaded_.images.end(), index,
      [](const MapImage& image, ImageIndex wanted) { return image.index < wanted; });
  return found != loaded_.images.end() && found->index == index ? &*found : nullptr;
}

std::optional<MapImage> MapView::Image(ImageIndex index) const {
  const std::lock_guard<std::mutex> lock(mutex_);
  const MapImage* found = FindImage(index);
  if (found == nullptr) return std::nullopt;
  return *found;
}

std::vector<MapImage> MapView::AllImages() const {
  const std::lock_guard<std::mutex> lock(mutex_);
  return loaded_.images;
}

json MapView::ImageJson(const MapImage& image) const {
  const auto holder = loaded_.holder.find(image.index);
  return {{"index", image.index},
          {"name", image.name},
          {"session", image.session},
          {"timestamp", Stamp(image.timestamp)},
          {"location", holder != loaded_.holder.end() ? json(holder->second) : json(nullptr)}};
}

json MapView::Summary() const {
  const std::lock_guard<std::mutex> lock(mutex_);
  const MapInfo& info = loaded_.info;
  json sessions = json::array();
  for (const MapSession& session : info.sessions) {
    sessions.push_back({{"id", session.id},
                        {"first_image", session.first_image},
                        {"last_image", session.last_image},
                        {"images", session.images},
                        {"first_name", session.first_name},
                        {"last_name", session.last_name},
                        {"first_timestamp", Stamp(session.first_timestamp)},
                        {"last_timestamp", Stamp(session.last_timestamp)}});
  }
  if (sessions.empty() && !loaded_.images.empty()) {  // images not recorded: one session
    sessions.push_back({{"id", 0},
                        {"first_image", loaded_.images.front().index},
                        {"last_image", loaded_.images.back().index},
                        {"images", loaded_.images.size()}});
  }
  json parameters = json::object();
  for (const auto& [name, value] : info.parameters) parameters[name] = value;
  return {{"path", info.path},
          {"format_version", info.format_version},
          {"integrity", info.integrity},
          {"images", info.images},
          {"last_image", info.last_image},
          {"ltm_locations", info.locations},
          {"checkpoint_locations", info.checkpoint_locations},
          {"words", info.words},
          {"neighbour_links", info.neighbour_links},
          {"loop_closure_links", info.loop_closure_links},
          {"loop_closures", info.loop_closures.size()},
          {"detected_loop_closures", loaded_.detected.size()},
          {"rejected_loop_closures", info.rejected_loop_closures},
          {"edits", info.edits},
          {"writer_pid", info.writer_pid},
          {"sessions", sessions},
          {"parameters", parameters}};
}

json MapView::Images(int session, long long offset, long long limit) const {
  const std::lock_guard<std::mutex> lock(mutex_);
  json page = json::array();
  long long total = 0;
  for (const MapImage& image : loaded_.images) {
    if (image.session != session) continue;
    if (total >= offset && total < offset + limit) page.push_back(ImageJson(image));
    ++total;
  }
  return {{"session", session}, {"offset", offset}, {"total", total}, {"images", page}};
}

json MapView::Location(LocationId id) const {
  std::optional<memloop::Location> location;
  std::string where = "LTM";
  {
    LtmDatabase database(path_, LtmDatabase::Mode::kPeek);
    database.Begin();
    location = database.ReadLocation(id);
    if (!location) {
      for (const auto& [held, bytes] : database.ReadMemoryLocations()) {
        if (held == id) location = DecodeLocation(bytes);
      }
      where = "STM/WM at the last checkpoint";
    }
    database.Commit();
  }
  if (!location) return nullptr;
  const std::lock_guard<std::mutex> lock(mutex_);
  json images = json::array();
  for (ImageIndex index : location->images) {
    if (const MapImage* found = FindImage(index)) {
      images.push_back(ImageJson(*found));
    } else {
      images.push_back({{"index", index}, {"name", ""}, {"location", id}});
    }
  }
  json loops = json::array();
  const std::vector<MapLoopClosure> edited = EditedLoopClosures(loaded_.detected, loaded_.edits);
  for (const MapLoopClosure& loop : edited) {
    const bool here =
        std::count(location->images.begin(), location->images.end(), loop.query_image) ||
        (loop.match_robot.empty()
             ? std::count(location->images.begin(), location->images.end(), loop.match_image) > 0
             : loop.match_location == id);
    if (here)
      loops.push_back(
          LoopJson(loop, loop.added_by_edit ? "added" : "detected", loop.added_by_edit));
  }
  // Another robot's place: that robot's name and images.
  const auto foreign = loaded_.foreign.find(id);
  return {{"id", id},
          {"robot", foreign == loaded_.foreign.end() ? json(nullptr) : json(foreign->second.robot)},
          {"robot_images",
           foreign == loaded_.foreign.end() ? json::array() : json(foreign->second.images)},
          {"in", where},
          {"weight", location->weight},
          {"words", location->signature.words.size()},
          {"view_image", ViewOf(*location)},
          {"images", images},
          {"neighbours", location->neighbours},
          {"loop_closure_links", location->loop_closures},
          {"loop_closures", loops}};
}

json MapView::LoopJson(const MapLoopClosure& loop, const std::string& state, long long edit) const {
  const auto name = [&](ImageIndex index) {
    const MapImage* found = FindImage(index);
    return found != nullptr ? found->name : std::string();
  };
  // The location that holds the image now (Rehearsal and loop closures merge locations after
  // the loop closure was recorded), else the one recorded then.
  const auto holder = [&](ImageIndex index, LocationId recorded) {
    const auto found = loaded_.holder.find(index);
    if (found != loaded_.holder.end()) return json(found->second);
    return recorded != kNoLocation ? json(recorded) : json(nullptr);
  };
  // Another robot's place (a fleet's map): its image is that robot's, its location never merged.
  const bool foreign = !loop.match_robot.empty();
  return {{"query_image", loop.query_image},
          {"match_image", loop.match_image},
          {"match_robot", foreign ? json(loop.match_robot) : json(nullptr)},
          {"query_name", name(loop.query_image)},
          {"match_name", foreign ? std::string() : name(loop.match_image)},
          {"query_location", holder(loop.query_image, loop.query_location)},
          {"match_location",
           foreign ? json(loop.match_location) : holder(loop.match_image, loop.match_location)},
          {"probability", loop.probability},
          {"pose", PoseJson(loop.pose)},
          {"state", state},
          {"edit", edit}};
}

json MapView::LoopClosures(long long offset, long long limit) const {
  const std::lock_guard<std::mutex> lock(mutex_);
  // The detected ones in their order, each as it stands now, then those added by hand.
  const std::vector<MapLoopClosure> edited = EditedLoopClosures(loaded_.detected, loaded_.edits);
  const std::vector<LoopClosureEdit> in_force = InForce(loaded_.edits);
  std::vector<json> all;
  for (const MapLoopClosure& loop : loaded_.detected) {
    long long rejected_by = 0;
    for (const LoopClosureEdit& edit : in_force) {
      const bool same =
          (edit.query_image == loop.query_image && edit.match_image == loop.match_image) ||
          (edit.query_image == loop.match_image && edit.match_image == loop.query_image);
      if (edit.action == EditAction::kReject && same) rejected_by = edit.id;
    }
    all.push_back(LoopJson(loop, rejected_by ? "rejected" : "detected", rejected_by));
  }
  for (const MapLoopClosure& loop : edited) {
    if (loop.added_by_edit) all.push_back(LoopJson(loop, "added", loop.added_by_edit));
  }
  json page = json::array();
  for (long long i = offset; i < static_cast<long long>(all.size()) && i < offset + limit; ++i) {
    page.push_back({{"n", i}});
    page.back().update(all[i]);
  }
  return {{"offset", offset},
          {"total", all.size()},
          {"in_force", edited.size()},
          {"loop_closures", page}};
}

json MapView::Edits() const {
  const std::lock_guard<std::mutex> lock(mutex_);
  json edits = json::array();
  for (const LoopClosureEdit& edit : loaded_.edits) {
    json row = {{"id", edit.id},
                {"action", EditActionName(edit.action)},
                {"who", edit.who},
                {"time", edit.time},
                {"undone", edit.undone}};
    if (edit.action == EditAction::kUndo) {
      row["undone_edit"] = edit.undone_edit;
    } else {
      row["query_image"] = edit.query_image;
      row["match_image"] = edit.match_image;
    }
    edits.push_back(row);
  }
  return {{"edits", edits}};
}

json MapView::Find(const std::string& text) const {
  const std::lock_guard<std::mutex> lock(mutex_);
  const MapImage* contains = nullptr;
  for (const MapImage& image : loaded_.images) {
    if (image.name == text || std::to_string(image.index) == text) return ImageJson(image);
    if (contains == nullptr && !text.empty() && image.name.find(text) != std::string::npos) {
      contains = &image;
    }
  }
  return contains != nullptr ? ImageJson(*contains) : json(nullptr);
}

}  // namespace memloop
