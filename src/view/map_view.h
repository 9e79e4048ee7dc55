// What `memloop view` shows of a map, as JSON: its summary, its images by session a page at a
// time, a location, the loop closures (as edited, the rejected ones marked), the edits. Every
// answer reads the map afresh (a run may be writing it, an edit may have just changed it); the
// images' list and their locations are read once, at start and after an edit.
#pragma once

#include <map>
#include <mutex>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "memloop/loop_closure_edits.h"
#include "memloop/map_info.h"

namespace memloop {

class MapView {
 public:
  // Throws DatabaseError naming the file when it is not a readable memloop map.
  explicit MapView(const std::string& map_path);

  const std::string& path() const { return path_; }

  nlohmann::json Summary() const;
  // The images of `session` from `offset` on (at most `limit`), with the locations holding them.
  nlohmann::json Images(int session, long long offset, long long limit) const;
  // kNoLocation's JSON is null.
  nlohmann::json Location(LocationId id) const;
  // Detected and added loop closures in the map's order (added last), each with its state:
  // "detected", "added" or "rejected", and the edit that made it so.
  nlohmann::json LoopClosures(long long offset, long long limit) const;
  nlohmann::json Edits() const;
  // An image by its index or its name (exact, else the first whose name contains `text`);
  // null when none.
  nlohmann::json Find(const std::string& text) const;

  std::optional<MapImage> Image(ImageIndex index) const;
  std::vector<MapImage> AllImages() const;

  // After an edit: the map is read again.
  void Reload();
  // Reads the map again when its file or its write-ahead log changed since (a run writing it).
  void ReloadIfChanged();

 private:
  struct Loaded {
    MapInfo info;
    std::vector<MapImage> images;             // by index
    std::map<ImageIndex, LocationId> holder;  // LTM and the last checkpoint
    std::vector<LoopClosureEdit> edits;
    std::vector<MapLoopClosure> detected;        // as the detector recorded them
    std::map<LocationId, ForeignPlace> foreign;  // a fleet's map: other robots' places, by id
  };
  Loaded Load() const;
  const MapImage* FindImage(ImageIndex index) const;  // in loaded_, by index; mutex_ held
  std::string FileState() const;  // sizes and modification times of the map and its log
  nlohmann::json ImageJson(const MapImage& image) const;
  nlohmann::json LoopJson(const MapLoopClosure& loop, const std::string& state,
                          long long edit) const;

  std::string path_;
  mutable std::mutex mutex_;
  Loaded loaded_;
  std::string loaded_state_;
};

}  // namespace memloop
