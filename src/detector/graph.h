// Breadth-first neighbourhoods in the map graph, used by the transition model (III-C), the
// hypothesis sum (III-D) and the choice of locations to retrieve (III-E).
#pragma once

#include <functional>
#include <utility>
#include <vector>

#include "detector/id_map.h"
#include "memloop/types.h"

namespace memloop {

// (location, links away), the start at 0, sorted by distance then id.
using Neighbourhood = std::vector<std::pair<LocationId, int>>;
// WM location -> its neighbourhood within WM (itself at distance 0).
using Neighbourhoods = IdMap<Neighbourhood>;
using LinksFunction = std::function<std::vector<LocationId>(LocationId)>;

// Every location within `range` links of `start`, following `links_of`.
Neighbourhood FindNeighbourhood(LocationId start, int range, const LinksFunction& links_of);

}  // namespace memloop
