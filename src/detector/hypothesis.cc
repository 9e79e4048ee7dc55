#include "detector/hypothesis.h"

namespace memloop {

Hypothesis SelectHypothesis(const IdMap<double>& posterior, double virtual_place,
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
  if (options.hypothesis_value == "loop_mass") {
    best.value = 1.0 - virtual_place;
  } else {
    for (const auto& [neighbour, distance] : neighbourhoods.at(best.id)) {
      if (distance > options.neighbour_range) continue;
      const auto found = posterior.find(neighbour);
      if (found != posterior.end()) best.value += found->second;
    }
  }
  best.eligible = static_cast<int>(posterior.size()) >= options.min_hypotheses;
  best.accepted = best.eligible && best.value > options.loop_threshold;
  return best;
}

void RequireSharedWords(const Signature& z_t, const Signature& z_i, int min_words,
                        Hypothesis& hypothesis) {
  if (min_words <= 0 || hypothesis.id == kNoLocation) return;
  if (CountWordPairs(z_t.Histogram(), z_i.Histogram()) < min_words) hypothesis.Refuse();
}

void CheckLtmNeighbours(const std::vector<LocationId>& links,
                        const std::function<bool(LocationId)>& in_ltm,
                        const std::function<double(LocationId)>& looks_like_image,
                        Hypothesis& hypothesis) {
  if (hypothesis.id == kNoLocation) return;
  const double own = looks_like_image ? looks_like_image(hypothesis.id) : 0;
  for (LocationId neighbour : links) {
    if (!in_ltm(neighbour)) continue;
    if (!looks_like_image || looks_like_image(neighbour) > own) return hypothesis.Refuse();
  }
}

}  // namespace memloop
