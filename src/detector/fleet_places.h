// A fleet's map (memloop, beyond the paper; docs/fleet.md): the places other robots mapped join
// this robot's map while they map them, so that the filter decides on them as on its own. A place
// read from the server (fleet_follower.h) enters WM as a retrieved place does (III-E): its
// features are quantized by this robot's dictionary (a feature that matches none becomes a word),
// it keeps its weight and its links to the places of its robot imported before it, and it starts
// with probability 0. From there the paper's memory management applies: when WM is over its
// budget, it goes to LTM like any place (and retrieval, by hypothesis or by appearance, brings it
// back). Where it came from is kept in the map (foreign_places), and a loop closure with it names
// the other robot and its images. The place is a copy: the other robot's rows are not changed.
#pragma once

#include <map>
#include <memory>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include "detector/bayes_filter.h"
#include "detector/memory.h"
#include "storage/fleet_follower.h"
#include "storage/long_term_memory.h"
#include "storage/ltm_database.h"
#include "vocabulary/appearance_index.h"

namespace memloop {

class FleetPlaces {
 public:
  // Resuming: the places the map imported before.
  void Reload(LtmDatabase& database);
  // Starts reading other robots' places from the server map `uri` in the background.
  void Follow(const std::string& uri, int descriptor_cv_type, int descriptor_dim);
  bool following() const { return follower_ != nullptr; }

  // Up to `count` places read since the last call join WM and the filter (`appearance`, when not
  // null, gets their descriptions, as for a new location). Returns their ids.
  // `image`: the image being processed.
  std::vector<LocationId> Import(size_t count, ImageIndex image, Memory& memory,
                                 LongTermMemory& ltm, BayesFilter& filter,
                                 AppearanceIndex* appearance);
  // Waits (up to `seconds` for each poll) until the places the server holds now are read, and
  // imports them all, whatever their number. Returns how many; throws DatabaseError when the
  // server did not answer in time.
  size_t CatchUp(double seconds, ImageIndex image, Memory& memory, LongTermMemory& ltm,
                 BayesFilter& filter, AppearanceIndex* appearance);
  // Lines to tell the user (places the robot cannot use).
  std::vector<std::string> TakeNotices();

  // The origin of location `id` when it is another robot's place, else null.
  const ForeignPlace* Find(LocationId id) const {
    const auto place = places_.find(id);
    return place == places_.end() ? nullptr : &place->second;
  }
  size_t size() const { return places_.size(); }

 private:
  LocationId ImportOne(const FleetLocation& place, ImageIndex image, Memory& memory,
                       LongTermMemory& ltm, BayesFilter& filter, AppearanceIndex* appearance);

  std::unordered_map<LocationId, ForeignPlace> places_;           // by this map's id
  std::map<std::pair<std::string, LocationId>, LocationId> ids_;  // (robot, its id) -> this map's
  std::unique_ptr<FleetFollower> follower_;
};

}  // namespace memloop
