// Loop-closure hypothesis selection (paper III-D).
#pragma once

#include <map>

#include "bayes_filter.h"
#include "memloop/options.h"

namespace memloop {

struct Hypothesis {
  LocationId id = kNoLocation;  // highest hypothesis, kNoLocation when WM is empty
  double value = 0;             // its neighbour-summed posterior
  bool accepted = false;        // value > T_loop and WM holds at least T_minHyp locations
};

// The highest hypothesis is the WM location of highest posterior (ties: the older); its value is
// the posterior summed over its neighbourhood (the transition model's range), because a loop
// closure's probability spreads to the neighbours of the matched location. The paper's text also
// reads as "the highest of the neighbour sums"; that choice names the centre of the probability
// mass rather than the best match, so matches lag behind along a path (RTAB-Map, by the same
// authors, sums around the highest posterior, as here).
Hypothesis SelectHypothesis(const std::map<LocationId, double>& posterior,
                            const Neighbourhoods& neighbourhoods, const FilterOptions& options);

}  // namespace memloop
