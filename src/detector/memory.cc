#include "detector/memory.h"

#include <algorithm>
#include <cassert>

#include "memloop/errors.h"

namespace memloop {

std::vector<LocationId> Location::Links() const {
  std::vector<LocationId> links(neighbours.begin(), neighbours.end());
  links.insert(links.end(), loop_closures.begin(), loop_closures.end());
  std::sort(links.begin(), links.end());
  links.erase(std::unique(links.begin(), links.end()), links.end());
  return links;
}

size_t Location::ApproximateBytes() const {
  return sizeof(Location) + signature.words.size() * (sizeof(WordId) + sizeof(cv::KeyPoint)) +
         (neighbours.size() + loop_closures.size()) * 48 + images.size() * sizeof(ImageIndex);
}

Memory::Memory(DescriptorKind kind, int descriptor_dim, const DictionaryOptions& dictionary_options)
    : dictionary_(kind, descriptor_dim, dictionary_options) {}

Location& Memory::AddToStm(Signature signature, ImageIndex image, LocationId previous) {
  Location location;
  location.id = next_id_++;
  location.signature = std::move(signature);
  location.images = {image};
  if (previous != kNoLocation) {
    location.neighbours.insert(previous);
    if (Contains(previous)) at(previous).neighbours.insert(location.id);
  }
  ReferenceWords(location);
  stm_.push_back(location.id);
  changed_.insert(location.id);
  TouchGraph(location.id);
  TouchGraph(previous);
  return locations_[location.id] = std::move(location);
}

void Memory::MoveStmOverflowToWm(int stm_size) {
  while (static_cast<int>(stm_.size()) > stm_size) {
    working_memory_.insert(stm_.front());
    TouchGraph(stm_.front());
    stm_.pop_front();
  }
}

std::vector<WordId> Memory::ReplaceSignature(LocationId id, Signature signature) {
  Location& location = at(id);
  std::vector<WordId> orphans = UnreferenceWords(location);
  location.signature = std::move(signature);
  ReferenceWords(location);
  // A word of the old signature may be in the new one too.
  orphans.erase(std::remove_if(orphans.begin(), orphans.end(),
                               [&](WordId word) { return !dictionary_.References(word).empty(); }),
                orphans.end());
  return orphans;
}

std::vector<LinkToLtm> Memory::AddLinksOf(LocationId target, LocationId source,
                                          bool link_together) {
  std::vector<LinkToLtm> to_ltm;
  Location& to = at(target);
  const Location& from = at(source);
  for (const bool loop_closure : {false, true}) {
    for (LocationId id : loop_closure ? from.loop_closures : from.neighbours) {
      if (id == target) continue;
      auto& links = loop_closure ? to.loop_closures : to.neighbours;
      if (!links.insert(id).second) continue;
      TouchGraph(target);
      TouchGraph(id);
      if (Contains(id)) {
        (loop_closure ? at(id).loop_closures : at(id).neighbours).insert(target);
      } else {
        to_ltm.push_back({id, loop_closure});
      }
    }
  }
  if (link_together) {
    to.loop_closures.insert(source);
    at(source).loop_closures.insert(target);
    TouchGraph(target);
    TouchGraph(source);
  }
  return to_ltm;
}

std::vector<WordId> Memory::Absorb(LocationId survivor, LocationId absorbed) {
  AddLinksOf(survivor, absorbed, /*link_together=*/false);
  Location& kept = at(survivor);
  const Location& gone = at(absorbed);
  kept.images.insert(kept.images.end(), gone.images.begin(), gone.images.end());
  kept.neighbours.erase(absorbed);
  kept.loop_closures.erase(absorbed);
  TouchGraph(survivor);
  TouchGraph(absorbed);
  std::vector<WordId> orphans = UnreferenceWords(gone);
  Unlink(absorbed);
  stm_.erase(std::remove(stm_.begin(), stm_.end(), absorbed), stm_.end());
  working_memory_.erase(absorbed);
  locations_.erase(absorbed);
  changed_.insert(absorbed);  // gone: the checkpoint removes it
  return orphans;
}

Location Memory::Release(LocationId id, std::vector<WordId>* orphan_words) {
  assert(InWorkingMemory(id));
  TouchGraph(id);
  TouchLinksOf(locations_.at(id));  // their links to it now lead to LTM
  Location location = std::move(at(id));
  *orphan_words = UnreferenceWords(location);
  working_memory_.erase(id);
  locations_.erase(id);
  changed_.insert(id);  // gone: the checkpoint removes it
  return location;
}

void Memory::Restore(Location location) {
  const LocationId id = location.id;
  ReferenceWords(location);
  // Locations in memory keep their links to LTM locations, so the graph is whole again.
  for (LocationId link : location.neighbours) {
    if (Contains(link)) at(link).neighbours.insert(id);
  }
  for (LocationId link : location.loop_closures) {
    if (Contains(link)) at(link).loop_closures.insert(id);
  }
  working_memory_.insert(id);
  changed_.insert(id);
  TouchGraph(id);
  TouchLinksOf(location);
  locations_[id] = std::move(location);
}

void Memory::Reload(std::map<LocationId, Location> locations, const std::deque<LocationId>& stm,
                    LocationId next_id) {
  for (const auto& [id, location] : locations) {
    if (id != location.id || id <= kNoLocation || id >= next_id) {
      throw Error("location " + std::to_string(id) + " is out of the map's id range");
    }
    for (WordId word : location.signature.words) {
      if (!dictionary_.Contains(word)) {
        throw Error("word " + std::to_string(word) + " of location " + std::to_string(id) +
                    " is not in the dictionary");
      }
    }
  }
  locations_ = std::move(locations);
  stm_.clear();
  working_memory_.clear();
  for (LocationId id : stm) {
    if (!locations_.count(id)) throw Error("STM location " + std::to_string(id) + " is missing");
    stm_.push_back(id);
  }
  for (const auto& [id, location] : locations_) {
    ReferenceWords(location);
    if (std::find(stm_.begin(), stm_.end(), id) == stm_.end()) working_memory_.insert(id);
  }
  next_id_ = next_id;
  graph_touched_.clear();
  graph_all_touched_ = true;
}

std::vector<LocationId> Memory::LinksOf(LocationId id) const { return at(id).Links(); }

Neighbourhood Memory::WmNeighbourhood(LocationId id, int range) const {
  // Links through STM count too (a loop closure links an STM location to old ones), but only WM
  // locations are states of the filter.
  Neighbourhood in_memory = FindNeighbourhood(id, range, [this](LocationId node) {
    std::vector<LocationId> links = LinksOf(node);
    links.erase(std::remove_if(links.begin(), links.end(),
                               [this](LocationId link) { return !Contains(link); }),
                links.end());
    return links;
  });
  Neighbourhood in_wm;
  for (const auto& entry : in_memory) {
    if (InWorkingMemory(entry.first)) in_wm.push_back(entry);
  }
  return in_wm;
}

Neighbourhoods Memory::WmNeighbourhoods(int range) const {
  // Dense indices in id order (locations_ is sorted): sorting indices sorts ids, and a link's
  // index is found by binary search in `ids`.
  std::vector<LocationId> ids;
  std::vector<const Location*> nodes;
  ids.reserve(locations_.size());
  nodes.reserve(locations_.size());
  for (const auto& [id, location] : locations_) {
    ids.push_back(id);
    nodes.push_back(&location);
  }
  // The adjacency in one array: node i's links are links[first_link[i] .. first_link[i + 1]).
  std::vector<int> first_link(ids.size() + 1, 0);
  std::vector<int> links;
  std::vector<char> in_wm(ids.size(), 0);
  auto wm = working_memory_.begin();  // sorted as ids: walked alongside, not searched
  for (size_t i = 0; i < ids.size(); ++i) {
    first_link[i] = static_cast<int>(links.size());
    for (const auto* linked : {&nodes[i]->neighbours, &nodes[i]->loop_closures}) {
      for (LocationId link : *linked) {
        const auto found = std::lower_bound(ids.begin(), ids.end(), link);
        if (found != ids.end() && *found == link) {
          links.push_back(static_cast<int>(found - ids.begin()));
        }
      }
    }
    if (wm != working_memory_.end() && *wm == ids[i]) {
      in_wm[i] = 1;
      ++wm;
    }
  }
  first_link[ids.size()] = static_cast<int>(links.size());
  Neighbourhoods result;
  result.reserve(working_memory_.size());
  std::vector<int> seen_from(ids.size(), -1);  // the start whose search last reached it
  std::vector<int> frontier, next;
  Neighbourhood neighbourhood;  // built here, then copied at its size: one allocation each
  for (int start = 0; start < static_cast<int>(ids.size()); ++start) {
    if (!in_wm[start]) continue;
    const LocationId id = ids[start];
    neighbourhood.assign(1, {id, 0});
    seen_from[start] = start;
    frontier.assign(1, start);
    for (int distance = 1; distance <= range && !frontier.empty(); ++distance) {
      next.clear();
      for (int node : frontier) {
        for (int k = first_link[node]; k < first_link[node + 1]; ++k) {
          const int link = links[k];
          if (seen_from[link] != start) {
            seen_from[link] = start;
            next.push_back(link);
          }
        }
      }
      std::sort(next.begin(), next.end());
      for (int node : next) {
        if (in_wm[node]) neighbourhood.emplace_back(ids[node], distance);
      }
      frontier.swap(next);
    }
    result.emplace_hint(result.end(), id, neighbourhood);
  }
  return result;
}

void Memory::ReferenceWords(const Location& location) {
  for (WordId word : location.signature.words) dictionary_.AddReference(word, location.id);
}

std::vector<WordId> Memory::UnreferenceWords(const Location& location) {
  std::vector<WordId> orphans;
  for (const auto& [word, count] : location.signature.Histogram()) {
    if (dictionary_.RemoveReferences(word, location.id)) orphans.push_back(word);
  }
  return orphans;
}

void Memory::Unlink(LocationId id) {
  for (LocationId link : at(id).Links()) {
    if (!Contains(link)) continue;
    TouchGraph(link);
    at(link).neighbours.erase(id);
    at(link).loop_closures.erase(id);
  }
}

void Memory::TouchGraph(LocationId id) {
  if (id == kNoLocation || graph_all_touched_) return;
  graph_touched_.insert(id);
  if (graph_touched_.size() > locations_.size() + 64) {  // nobody reads them: stop listing
    graph_touched_.clear();
    graph_all_touched_ = true;
  }
}

void Memory::TouchLinksOf(const Location& location) {
  for (const auto* links : {&location.neighbours, &location.loop_closures}) {
    for (LocationId link : *links) {
      if (Contains(link)) TouchGraph(link);
    }
  }
}

Memory::GraphChanges Memory::TakeGraphChanges() {
  GraphChanges changes;
  changes.touched.swap(graph_touched_);
  changes.all = graph_all_touched_;
  graph_all_touched_ = false;
  return changes;
}

}  // namespace memloop
