// The filter's neighbourhoods (graph.h) of every WM location, kept from one image to the next.
// Searching all of them again at every image cost more than the rest of the filter, and grew
// faster than WM: at 2,000 WM locations, 85% of the filter step (`bench/scale.sh`). An image
// changes the graph near a few locations (the new one, a transfer, a merge, a retrieval), so
// only the neighbourhoods near those are searched again; the result is the same as a search of
// all (Memory::WmNeighbourhoods), which the tests and Detector::CheckConsistency compare.
#pragma once

#include "detector/graph.h"
#include "detector/memory.h"

namespace memloop {

class NeighbourhoodCache {
 public:
  // The neighbourhoods within `range` links of every WM location of `memory` as it is now. Takes
  // memory's graph changes (Memory::TakeGraphChanges): one cache per Memory.
  const Neighbourhoods& Update(Memory& memory, int range);
  // How many neighbourhoods the last Update searched (all of WM when it searched them all).
  size_t searched() const { return searched_; }

 private:
  Neighbourhoods neighbourhoods_;
  int range_ = -1;
  size_t searched_ = 0;
};

}  // namespace memloop
