#include "detector/hypothesis.h"

#include <algorithm>
#include <cmath>

namespace memloop {

namespace {

// The posterior summed over `id`'s neighbourhood (the transition model's range); with `centre`,
// the neighbour of highest posterior inside it (ties: the older).
double NeighbourSum(LocationId id, const IdMap<double>& posterior,
                    const Neighbourhoods& neighbourhoods, int range, LocationId* centre = nullptr) {
  double sum = 0, highest = -1;
  for (const auto& [neighbour, distance] : neighbourhoods.at(id)) {
    if (distance > range) continue;
    const auto found = posterior.find(neighbour);
    if (found == posterior.end()) continue;
    sum += found->second;
    if (centre == nullptr) continue;
    if (found->second > highest || (found->second == highest && neighbour < *centre)) {
      highest = found->second, *centre = neighbour;
    }
  }
  return sum;
}

}  // namespace

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
  const int range = options.neighbour_range;
  if (options.hypothesis_value == "loop_mass") {
    best.value = 1.0 - virtual_place;
  } else if (options.hypothesis_value == "best_neighbours") {
    best.value = -1;
    for (const auto& [id, own] : posterior) {
      LocationId centre = id;
      const double sum = NeighbourSum(id, posterior, neighbourhoods, range, &centre);
      if (sum > best.value) best.value = sum, best.id = centre;  // ties: the older sum
    }
  } else {
    best.value = NeighbourSum(best.id, posterior, neighbourhoods, range);
  }
  best.eligible = static_cast<int>(posterior.size()) >= options.min_hypotheses;
  best.accepted = best.eligible && best.value > options.loop_threshold;
  return best;
}

void RequireLoopRatio(double previous_value, double ratio, Hypothesis& hypothesis) {
  if (ratio <= 0 || hypothesis.id == kNoLocation) return;
  if (previous_value <= 0 || hypothesis.value < ratio * previous_value) hypothesis.Refuse();
}

void CapRepeatedObservation(double previous_value, double loop_threshold, Hypothesis& hypothesis) {
  if (hypothesis.id == kNoLocation || hypothesis.value <= previous_value) return;
  hypothesis.value = previous_value;
  hypothesis.accepted = hypothesis.eligible && hypothesis.value > loop_threshold;
}

void RequireSimilarRoll(const ViewRoll& roll, double max_degrees, Hypothesis& hypothesis) {
  if (max_degrees <= 0 || hypothesis.id == kNoLocation || !roll.known) return;
  if (std::fabs(roll.degrees) > max_degrees) hypothesis.Refuse();
}

bool SharesWords(const Signature& z_t, const Signature& z_i, int min_words) {
  return min_words <= 0 || CountWordPairs(z_t.Histogram(), z_i.Histogram()) >= min_words;
}

bool SupportedByImage(const Signature& image, const Signature& z_i, double min_score,
                      int min_words) {
  const double score = Similarity(image, z_i);
  return score > 0 && score >= min_score && SharesWords(image, z_i, min_words);
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
