// The observation model of the Bayes filter (paper III-C): scores of eq. 1 between L_t and every
// WM location, normalized by eq. 3, and the virtual place's likelihood, eq. 4.
#pragma once

#include <map>

#include "memory.h"

namespace memloop {

struct Likelihood {
  std::map<LocationId, double> scores;  // s_j = s(z_t, z_j), eq. 1, every WM location
  std::map<LocationId, double> values;  // p(L_t | S_t = j), eq. 3
  double virtual_place = 1;             // p(L_t | S_t = -1), eq. 4
  double mean = 0;                      // mu of the non-null scores
  double stddev = 0;                    // sigma of the non-null scores
};

// Eq. 1 for every WM location, through the dictionary's references (locations that share no word
// with z_t score 0 without being visited).
std::map<LocationId, double> ScoreWorkingMemory(const Signature& z_t, const Memory& memory);

// Eq. 3 and 4 from the scores. With no non-null score, or sigma = 0, mu/sigma is taken as 1
// (the paper leaves 0/0 open), so the virtual place's likelihood is 2.
Likelihood ComputeLikelihood(const std::map<LocationId, double>& scores);

}  // namespace memloop
