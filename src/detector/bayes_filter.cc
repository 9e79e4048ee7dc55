#include "detector/bayes_filter.h"

#include <cmath>

namespace memloop {

BayesFilter::BayesFilter(const FilterOptions& options) : options_(options) {}

std::vector<std::pair<LocationId, double>> BayesFilter::NeighbourTransition(
    const Neighbourhood& j) const {
  std::vector<std::pair<LocationId, double>> column;
  double total = 0;
  const double two_sigma_squared = 2 * options_.neighbour_sigma * options_.neighbour_sigma;
  for (const auto& [id, distance] : j) {
    if (distance > options_.neighbour_range) continue;
    const double weight = std::exp(-distance * distance / two_sigma_squared);
    column.emplace_back(id, weight);
    total += weight;
  }
  // The paper's line of 9 locations (j-4..j+4) is one case; in a graph with loop closures the
  // neighbours at each distance vary, so each column is normalized to the same sum.
  for (auto& entry : column) entry.second *= options_.virtual_place_stay / total;
  return column;
}

void BayesFilter::Update(const Likelihood& likelihood, const Neighbourhoods& neighbourhoods) {
  const double stay = options_.virtual_place_stay;  // parts 1 and 4: 0.9
  const double leave = 1.0 - stay;                  // parts 2 and 3: 0.1
  const size_t wm_size = likelihood.values.size();

  // Prediction (the "belief" of eq. 2): sum over previous states of transition * prior.
  std::map<LocationId, double> belief;
  double previous_loop_mass = 0;
  for (const auto& [id, value] : likelihood.values) {
    belief[id] = wm_size > 0 ? leave / wm_size * virtual_place_ : 0.0;  // part 2
  }
  for (const auto& [j, prior] : posterior_) {
    const auto neighbourhood = neighbourhoods.find(j);
    if (neighbourhood == neighbourhoods.end() || prior == 0) continue;  // j left WM
    previous_loop_mass += prior;
    for (const auto& [i, transition] : NeighbourTransition(neighbourhood->second)) {
      belief[i] += transition * prior;  // part 4
    }
  }
  double virtual_belief = stay * virtual_place_ + leave * previous_loop_mass;  // parts 1 and 3

  // Update with the observation, then normalize (eta).
  posterior_.clear();
  double total = likelihood.virtual_place * virtual_belief;
  for (const auto& [id, value] : likelihood.values) {
    const double unnormalized = value * belief[id];
    posterior_[id] = unnormalized;
    total += unnormalized;
  }
  virtual_place_ = likelihood.virtual_place * virtual_belief / total;
  for (auto& entry : posterior_) entry.second /= total;
}

}  // namespace memloop
