// A location L: a node of the map graph (paper III-A).
#pragma once

#include <set>
#include <vector>

#include "memloop/types.h"
#include "vocabulary/signature.h"

namespace memloop {

struct Location {
  LocationId id = kNoLocation;
  Signature signature;
  // Rehearsals and loop closures it absorbed (paper III-B, III-D); starts at 0.
  int weight = 0;
  // Bidirectional links: to the previous and next locations, and to loop-closure matches.
  std::set<LocationId> neighbours;
  std::set<LocationId> loop_closures;
  // Images the location stands for: the one that created it, then those of absorbed locations.
  std::vector<ImageIndex> images;

  // Neighbour and loop-closure links together, sorted.
  std::vector<LocationId> Links() const;
  // About the memory it holds (queues and caches bounded in bytes count with it).
  size_t ApproximateBytes() const;
};

}  // namespace memloop
