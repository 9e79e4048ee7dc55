#include "detector/neighbourhood_cache.h"

#include <set>
#include <vector>

namespace memloop {

// Which neighbourhoods can have changed. Let T be the touched locations: both ends of every link
// added or removed, every location added, removed or moved between STM and WM, and, for a removed
// one, the locations linked to it. If X's neighbourhood changed, some location of T still in
// memory is within `range` links of X in the graph as it is now:
// - a location reached now by a path that did not exist before: the path holds an added link, or
//   a location that joined (both in T), at most `range` links from X;
// - a location no longer reached, or reached further: every old shortest path lost a link or a
//   location; the part of such a path before its first loss is still there, shorter than `range`,
//   and ends at a location of T (an end of the lost link, or linked to the lost location);
// - a location that joined or left WM while still in memory: it is in T, within `range` of X.
// So one search of depth `range` from T, over the graph as it is now, finds every such X.
const Neighbourhoods& NeighbourhoodCache::Update(Memory& memory, int range) {
  const Memory::GraphChanges changes = memory.TakeGraphChanges();
  // Past a quarter of WM, one search of all is cheaper than many searches of a few.
  if (range != range_ || changes.all ||
      changes.touched.size() * 4 > memory.working_memory().size()) {
    neighbourhoods_ = memory.WmNeighbourhoods(range);
    range_ = range;
    searched_ = neighbourhoods_.size();
    return neighbourhoods_;
  }
  const Memory& graph = memory;
  std::set<LocationId> stale;
  std::vector<LocationId> frontier, next;
  for (LocationId id : changes.touched) {
    if (!graph.InWorkingMemory(id)) neighbourhoods_.erase(id);
    if (graph.Contains(id) && stale.insert(id).second) frontier.push_back(id);
  }
  for (int distance = 1; distance <= range && !frontier.empty(); ++distance) {
    next.clear();
    for (LocationId id : frontier) {
      for (LocationId link : graph.LinksOf(id)) {
        if (graph.Contains(link) && stale.insert(link).second) next.push_back(link);
      }
    }
    frontier.swap(next);
  }
  searched_ = 0;
  for (LocationId id : stale) {
    if (!graph.InWorkingMemory(id)) continue;
    neighbourhoods_[id] = graph.WmNeighbourhood(id, range);
    ++searched_;
  }
  return neighbourhoods_;
}

}  // namespace memloop
