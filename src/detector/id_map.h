// Per-location values in id order, stored in one array (boost::container::flat_map, the same
// interface as std::map). The filter's state, the likelihood and the neighbourhoods cover all of
// WM and are rebuilt or walked in id order at every image; a node-based map costs an allocation
// per location and a cache miss per step, which at WM 2,000 in a large heap took most of those
// stages' time (issue 9, docs/benchmarks.md). Insertions are at the end (new locations have the
// highest ids) but for the few retrieved locations per image.
#pragma once

#include <boost/container/flat_map.hpp>
#include <boost/container/flat_set.hpp>

#include "memloop/types.h"

namespace memloop {

template <typename Value>
using IdMap = boost::container::flat_map<LocationId, Value>;
using IdSet = boost::container::flat_set<LocationId>;

}  // namespace memloop
