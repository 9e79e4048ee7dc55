// The discrete Bayes filter over loop-closure hypotheses (paper III-C, after Angeli et al. 2008):
// S_t = -1 (new location, the "virtual place") or S_t = j for each location j in WM.
// The state space follows WM: a location that enters WM starts with probability 0, one that
// leaves WM leaves the state space.
#pragma once

#include <utility>
#include <vector>

#include "detector/graph.h"
#include "detector/likelihood.h"
#include "memloop/options.h"

namespace memloop {

class BayesFilter {
 public:
  explicit BayesFilter(const FilterOptions& options);

  // Eq. 2: posterior = eta * likelihood * sum_i transition * prior, over the locations of
  // `likelihood.values` (all of WM) and the virtual place.
  void Update(const Likelihood& likelihood, const Neighbourhoods& neighbourhoods);

  // Transition model part 4: p(S_t = i | S_t-1 = j) for the neighbours i of j, a discretized
  // Gaussian over link distance (0..neighbour_range) whose values sum to virtual_place_stay
  // (0.9). Part 3, p(S_t = -1 | S_t-1 = j), is the rest (0.1), so each column sums to 1.
  std::vector<std::pair<LocationId, double>> NeighbourTransition(const Neighbourhood& j) const;

  // p(S_t | L^t) of the WM locations, and of the virtual place.
  const IdMap<double>& posterior() const { return posterior_; }
  double virtual_place() const { return virtual_place_; }
  // A location that entered WM after the update (retrieved) starts with probability 0.
  void Add(LocationId id) { posterior_.emplace(id, 0.0); }
  // Resuming a map: the posterior as it was.
  void Reload(IdMap<double> posterior, double virtual_place) {
    posterior_ = std::move(posterior);
    virtual_place_ = virtual_place;
  }
  // Forget a location that left WM.
  void Remove(LocationId id) { posterior_.erase(id); }
  // A new session (MapMode::kNewSession): nothing is known of where the robot is, so the whole
  // belief goes to the virtual place (as the filter starts), every state kept at 0.
  void Forget();

 private:
  // The Gaussian's unnormalized value at each link distance 0..neighbour_range.
  std::vector<double> TransitionWeights() const;
  // What part 4's weights over j's neighbours are multiplied by to sum to virtual_place_stay.
  double ColumnScale(const Neighbourhood& j, const std::vector<double>& weights) const;

  FilterOptions options_;
  IdMap<double> posterior_;
  double virtual_place_ = 1.0;  // before any image: surely a new location
};

}  // namespace memloop
