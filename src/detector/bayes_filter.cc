#include "detector/bayes_filter.h"

#include <cmath>

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

double BayesFilter::ColumnScale(const Neighbourhood& j, const std::vector<double>& weights) const {
  double total = 0;
  for (const auto& [id, distance] : j) {
    if (distance <= options_.neighbour_range) total += weights[distance];
  }
  // The paper's line of 9 locations (j-4..j+4) is one case; in a graph with loop closures the
  // neighbours at each distance vary, so each column is normalized to the same sum.
  return options_.virtual_place_stay / total;
}

std::vector<std::pair<LocationId, double>> BayesFilter::NeighbourTransition(
    const Neighbourhood& j) const {
  const std::vector<double> weights = TransitionWeights();
  const double scale = ColumnScale(j, weights);
  std::vector<std::pair<LocationId, double>> column;
  for (const auto& [id, distance] : j) {
    if (distance <= options_.neighbour_range) column.emplace_back(id, weights[distance] * scale);
  }
  return column;
}

void BayesFilter::Update(const Likelihood& likelihood, const Neighbourhoods& neighbourhoods) {
  const double stay = options_.virtual_place_stay;  // parts 1 and 4: 0.9
  const double leave = 1.0 - stay;                  // parts 2 and 3: 0.1
  const size_t wm_size = likelihood.values.size();

  // Prediction (the "belief" of eq. 2): sum over previous states of transition * prior. The
  // states are WM's, in id order, in an array (docs/benchmarks.md).
  const auto& states = likelihood.values;
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
    // Part 4: NeighbourTransition's column, walked without being built.
    const double scale = ColumnScale(neighbourhood->second, weights);
    for (const auto& [i, distance] : neighbourhood->second) {
      if (distance > options_.neighbour_range) continue;
      const auto state = states.find(i);
      if (state == states.end()) continue;
      belief[states.index_of(state)] += weights[distance] * scale * prior;
    }
  }
  double virtual_belief = stay * virtual_place_ + leave * previous_loop_mass;  // parts 1 and 3

  // Update with the observation, then normalize (eta).
  posterior_.clear();
  posterior_.reserve(wm_size);
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

void BayesFilter::Forget() {
  for (auto& entry : posterior_) entry.second = 0;
  virtual_place_ = 1;
}

}  // namespace memloop
