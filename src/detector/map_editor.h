// Every change of the map that reaches beyond one structure goes through here: a location that
// leaves memory (merged into another by Rehearsal or as a past match, or transferred to LTM), and
// links made in memory that reach LTM locations. One owner keeps the edges in agreement:
// - words no location in memory refers to leave the dictionary, kept in LTM (with their
//   descriptors) when LTM locations refer to them (III-F);
// - links are symmetric across memory and LTM (a link to an LTM location is written there too,
//   and links to a merged location are redirected to its survivor);
// - the filter's states are exactly WM (a location leaving WM leaves the filter);
// - past matches waiting to be absorbed (III-D) follow their matcher when it is merged.
#pragma once

#include <set>
#include <utility>
#include <vector>

#include "detector/bayes_filter.h"
#include "detector/memory.h"
#include "storage/long_term_memory.h"
#include "vocabulary/appearance_index.h"

namespace memloop {

// A past match L_i waiting to be absorbed into the location that matched it.
struct PastMatch {
  LocationId matched = kNoLocation;  // L_i
  LocationId matcher = kNoLocation;  // the location that closed the loop with it
};

class MapEditor {
 public:
  // `appearance` (retrieval by appearance; null when off) searches exactly the LTM locations.
  MapEditor(Memory& memory, LongTermMemory& ltm, BayesFilter& filter,
            AppearanceIndex* appearance = nullptr);

  // III-D: L_t takes L_i's links (neighbours and loop closures) and a loop-closure link to L_i,
  // both ways, in LTM too. L_i then waits to be absorbed into L_t (AbsorbPastMatches), unless
  // not `absorbed`: a place of another robot stays as it is, the other robot's place.
  void LinkLoopClosure(LocationId t, LocationId i, bool absorbed = true);

  // Rehearsal (III-B): z_t becomes `signature`; words left without reference are released.
  void ReplaceSignature(LocationId id, Signature signature);

  // `absorbed` disappears into `survivor`: its images and links go to the survivor (in memory and
  // LTM), its orphan words are released, it leaves the filter, and past matches it had made
  // now belong to the survivor. Weights are the caller's (Rehearsal and loop closure differ).
  void Merge(LocationId survivor, LocationId absorbed);

  // Past matches not in `keep` (the highest hypothesis' neighbourhood) are merged into their
  // matcher. One that left WM, or whose matcher did, is dropped and stays as it is.
  void AbsorbPastMatches(const std::set<LocationId>& keep);

  // III-F: a WM location goes to LTM with the words only it held.
  void TransferToLtm(LocationId id);

  const std::vector<PastMatch>& past_matches() const { return past_matches_; }
  // Resuming a map: the past matches it had.
  void SetPastMatches(std::vector<PastMatch> past_matches) {
    past_matches_ = std::move(past_matches);
  }

 private:
  // Words no location in memory refers to leave the dictionary (to LTM when LTM refers to them).
  void ReleaseWords(const std::vector<WordId>& orphans);

  Memory& memory_;
  LongTermMemory& ltm_;
  BayesFilter& filter_;
  AppearanceIndex* appearance_;
  std::vector<PastMatch> past_matches_;
};

}  // namespace memloop
