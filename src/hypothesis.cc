#include "hypothesis.h"

namespace memloop {

Hypothesis SelectHypothesis(const std::map<LocationId, double>& posterior,
                            const Neighbourhoods& neighbourhoods, const FilterOptions& options) {
  Hypothesis best;
  double best_own = -1;
  for (const auto& [id, own] : posterior) {
    if (own > best_own) {  // ascending ids: ties keep the older location
      best.id = id;
      best_own = own;
    }
  }
  if (best.id == kNoLocation) return best;
  for (const auto& [neighbour, distance] : neighbourhoods.at(best.id)) {
    if (distance > options.neighbour_range) continue;
    const auto found = posterior.find(neighbour);
    if (found != posterior.end()) best.value += found->second;
  }
  best.accepted = best.value > options.loop_threshold &&
                  static_cast<int>(posterior.size()) >= options.min_hypotheses;
  return best;
}

}  // namespace memloop
