#include "detector/bayes_filter.h"

#include <cmath>
#include <unordered_map>

namespace memloop {

BayesFilter::BayesFilter(const FilterOptions& options) : options_(options) {}

std::vector<double> BayesFilter::TransitionWeights() const {
  std::vector<double> weights;
  const double two_sigma_squared = 2 * options_.neighbour_sigma * options_.neighbour_sigma;
  for (int distance = 0; distance <= options_.neighbour_range; ++distance) {
    weights.push_back(std::exp(-distance * distance / two_sigma_squared));
  }
  return weights;
}

std::vector<std::pair<LocationId, double>> BayesFilter::NeighbourTransition(
    const Neighbourhood& j, const std::vector<double>& weights) const {
  std::vector<std::pair<LocationId, double>> column;
  double total = 0;
  for (const auto& [id, distance] : j) {
    if (distance > options_.neighbour_range) continue;
    column.emplace_back(id, weights[distance]);
    total += weights[distance];
  }
  // The paper's line of 9 locations (j-4..j+4) is one case; in a graph with loop closures the
  // neighbours at each distance vary, so each column is normalized to the same sum.
  for (auto& entry : column) entry.second *= options_.virtual_place_stay / total;
  return column;
}

std::vector<std::pair<LocationId, double>> BayesFilter::NeighbourTransition(
    const Neighbourhood& j) const {
  return NeighbourTransition(j, TransitionWeights());
}

void BayesFilter::Update(const Likelihood& likelihood, const Neighbourhoods& neighbourhoods) {
  const double stay = options_.virtual_place_stay;  // parts 1 and 4: 0.9
  const double leave = 1.0 - stay;                  // parts 2 and 3: 0.1
  const size_t wm_size = likelihood.values.size();

  // Prediction (the "belief" of eq. 2): sum over previous states of transition * prior. The
  // states are WM's, in id order, in an array; `index` finds a neighbour's (docs/benchmarks.md).
  std::unordered_map<LocationId, size_t> index;
  index.reserve(wm_size);
  for (const auto& [id, value] : likelihood.values) index.emplace(id, index.size());
  std::vector<double> belief(wm_size, wm_size > 0 ? leave / wm_size * virtual_place_ : 0.0);
  const std::vector<double> weights = TransitionWeights();
  double previous_loop_mass = 0;
  auto neighbourhood = neighbourhoods.begin();  // sorted as posterior_: walked alongside
  for (const auto& [j, prior] : posterior_) {
    while (neighbourhood != neighbourhoods.end() && neighbourhood->first < j) ++neighbourhood;
    if (neighbourhood == neighbourhoods.end() || neighbourhood->first != j || prior == 0) {
      continue;  // j left WM
    }
    previous_loop_mass += prior;
    for (const auto& [i, transition] : NeighbourTransition(neighbourhood->second, weights)) {
      const auto state = index.find(i);
      if (state != index.end()) belief[state->second] += transition * prior;  // part 4
    }
  }
  double virtual_belief = stay * virtual_place_ + leave * previous_loop_mass;  // parts 1 and 3

  // Update with the observation, then normalize (eta).
  posterior_.clear();
  double total = likelihood.virtual_place * virtual_belief;
  size_t state = 0;
  for (const auto& [id, value] : likelihood.values) {
    const double unnormalized = value * belief[state++];
    posterior_.emplace_hint(posterior_.end(), id, unnormalized);
    total += unnormalized;
  }
  virtual_place_ = likelihood.virtual_place * virtual_belief / total;
  for (auto& entry : posterior_) entry.second /= total;
}

}  // namespace memloop
