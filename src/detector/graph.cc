#include "detector/graph.h"

#include <algorithm>
#include <unordered_set>

namespace memloop {

Neighbourhood FindNeighbourhood(LocationId start, int range, const LinksFunction& links_of) {
  Neighbourhood result = {{start, 0}};
  std::unordered_set<LocationId> seen = {start};
  std::vector<LocationId> frontier = {start};
  for (int distance = 1; distance <= range && !frontier.empty(); ++distance) {
    std::vector<LocationId> next;
    for (LocationId id : frontier) {
      for (LocationId link : links_of(id)) {
        if (seen.insert(link).second) next.push_back(link);
      }
    }
    std::sort(next.begin(), next.end());
    for (LocationId id : next) result.emplace_back(id, distance);
    frontier = std::move(next);
  }
  return result;
}

}  // namespace memloop
