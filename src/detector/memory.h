// The memory held in RAM: the Short-Term Memory (STM) and the Working Memory (WM), their
// locations and the dictionary of their words (paper III). The Long-Term Memory is on disk
// (long_term_memory.h); this class only knows LTM locations by the links that point to them.
// Not thread-safe: the detector's thread owns it.
#pragma once

#include <deque>
#include <map>
#include <set>
#include <vector>

#include "detector/graph.h"
#include "detector/location.h"
#include "vocabulary/dictionary.h"

namespace memloop {

struct LinkToLtm {
  LocationId ltm_location = kNoLocation;
  bool loop_closure = false;
};

class Memory {
 public:
  Memory(DescriptorKind kind, int descriptor_dim, const DictionaryOptions& dictionary_options);

  Dictionary& dictionary() { return dictionary_; }
  const Dictionary& dictionary() const { return dictionary_; }

  // III-A: the new location L_t enters STM with weight 0 and a bidirectional link to L_t-1
  // (`previous`, which may be in STM, WM or LTM; kNoLocation for the first). Its words must be in
  // the dictionary; they get references to it.
  Location& AddToStm(Signature signature, ImageIndex image, LocationId previous);

  bool Contains(LocationId id) const { return locations_.count(id) > 0; }
  // Mutable access marks the location changed (for the checkpoint, which then encodes only
  // changed locations instead of all of STM and WM at every image).
  Location& at(LocationId id) {
    changed_.insert(id);
    return locations_.at(id);
  }
  const Location& at(LocationId id) const { return locations_.at(id); }
  bool InWorkingMemory(LocationId id) const { return working_memory_.count(id) > 0; }
  const std::deque<LocationId>& stm() const { return stm_; }  // oldest first
  const IdSet& working_memory() const { return working_memory_; }
  size_t size() const { return locations_.size(); }
  // Every location of STM and WM, by id.
  const std::map<LocationId, Location>& locations() const { return locations_; }

  // Moves the oldest STM locations to WM until STM holds at most `stm_size`.
  void MoveStmOverflowToWm(int stm_size);

  // Replaces the signature of `id` (Rehearsal copies z_c into z_t). Returns the words that no
  // longer have any reference.
  std::vector<WordId> ReplaceSignature(LocationId id, Signature signature);

  // Adds the links of `source` (neighbours and loop closures, both ways) to `target`, and a
  // loop-closure link between them when `link_together` (III-D). Returns the links made to
  // locations not in memory (in LTM): their side is the caller's to write.
  std::vector<LinkToLtm> AddLinksOf(LocationId target, LocationId source, bool link_together);

  // `absorbed` disappears into `survivor`: its links and images go to the survivor, links of other
  // locations in memory that pointed to it now point to the survivor. Returns the words left
  // without reference. Weights are the caller's: Rehearsal and loop closure differ.
  std::vector<WordId> Absorb(LocationId survivor, LocationId absorbed);

  // Transfer: takes a WM location out of memory. `orphan_words` receives its words that no
  // other location in memory refers to (they are still in the dictionary).
  Location Release(LocationId id, std::vector<WordId>* orphan_words);

  // Retrieval: a location from LTM enters WM. All its words must be in the dictionary.
  void Restore(Location location);

  // Resuming a map: STM (`stm`, oldest first) and WM (the other `locations`), and the next id to
  // give. The dictionary must hold every word of the locations; they get their references here.
  // Throws Error when the locations disagree with the dictionary or the ids.
  void Reload(std::map<LocationId, Location> locations, const std::deque<LocationId>& stm,
              LocationId next_id);
  LocationId next_id() const { return next_id_; }
  // An id for a location made outside memory (a place of another robot, imported into LTM).
  LocationId ReserveId() { return next_id_++; }

  // Locations given out mutably, added, restored or removed (transferred, absorbed) since
  // ClearChanged(): the checkpoint looks at these alone. ClearChanged() also clears the
  // dictionary's changed LTM marks.
  const std::set<LocationId>& changed() const { return changed_; }
  // Locations whose links or membership changed since the last call (a removed location and the
  // locations it was linked to included); `all` when they are too many to list (a reload).
  // NeighbourhoodCache is their one reader.
  struct GraphChanges {
    std::set<LocationId> touched;
    bool all = true;
  };
  GraphChanges TakeGraphChanges();
  void ClearChanged() {
    changed_.clear();
    dictionary_.ClearChangedMarks();
  }

  // Links of a location in memory (neighbours and loop closures), sorted.
  std::vector<LocationId> LinksOf(LocationId id) const;
  // WM locations within `range` links of a WM location, over links among STM and WM.
  Neighbourhood WmNeighbourhood(LocationId id, int range) const;
  // WmNeighbourhood of every WM location, the same answers computed together (the filter needs
  // all of them at every image: one adjacency of STM and WM instead of one per search).
  Neighbourhoods WmNeighbourhoods(int range) const;

 private:
  void ReferenceWords(const Location& location);
  std::vector<WordId> UnreferenceWords(const Location& location);
  void Unlink(LocationId id);
  void TouchGraph(LocationId id);
  void TouchLinksOf(const Location& location);

  Dictionary dictionary_;
  std::map<LocationId, Location> locations_;
  std::deque<LocationId> stm_;
  IdSet working_memory_;  // walked in id order at every image
  LocationId next_id_ = 1;
  std::set<LocationId> changed_;
  std::set<LocationId> graph_touched_;
  bool graph_all_touched_ = true;  // nothing was computed from the graph yet
};

}  // namespace memloop
