// The observation model of the Bayes filter (paper III-C): scores of eq. 1 between L_t and every
// WM location, normalized by eq. 3, and the virtual place's likelihood, eq. 4.
#pragma once

#include "detector/id_map.h"
#include "detector/memory.h"

namespace memloop {

struct Likelihood {
  IdMap<double> scores;      // s_j = s(z_t, z_j), eq. 1, every WM location
  IdMap<double> values;      // p(L_t | S_t = j), eq. 3
  double virtual_place = 1;  // p(L_t | S_t = -1), eq. 4
  double mean = 0;           // mu of the non-null scores
  double stddev = 0;         // sigma of the non-null scores
  // With the whole-image channel (whole_image_likelihood.h): each WM location's z there, and the
  // channel's factor in `values` (the words' eq. 3 is values / factor).
  IdMap<double> whole_image_z;
  IdMap<double> whole_image_values;
};

// Eq. 1 for every WM location, through the dictionary's references (locations that share no word
// with z_t score 0 without being visited). `image_words` > 0 stands for z_t's size in eq. 1: a
// second view of the image (rolled_view.h) holds only the words it matched, and is scored as the
// image it describes.
IdMap<double> ScoreWorkingMemory(const Signature& z_t, const Memory& memory,
                                 size_t image_words = 0);

// tf-idf scores for every WM location j: the sum over the words w of z_t of
// n_wj / n_j * log10(N / n_w), with n_wj the occurrences of w in z_j, n_j the size of z_j, N the
// locations in STM and WM and n_w those among them that hold w (Sivic & Zisserman 2003; RTAB-Map's
// likelihood since 2013). Frequent words weigh less, so a few distinctive shared words stand out
// above many common ones, which eq. 1 counts alike.
IdMap<double> ScoreWorkingMemoryTfIdf(const Signature& z_t, const Memory& memory);

// Eq. 3 and 4 from the scores. Eq. 4, mu/sigma + 1, grows without bound as sigma -> 0 and is
// undefined at 0. With `min_sigma_ratio` > 0 and at least 2 non-null scores, sigma is taken as
// at least min_sigma_ratio * mu in eq. 3 and 4, so the virtual place's likelihood is continuous
// in the scores and at most 1/min_sigma_ratio + 1 (all scores tied: no location stands out).
// With fewer than 2 non-null scores sigma cannot be estimated and mu/sigma is taken as 1 (the
// virtual place's likelihood is 2). With ratio 0 (the paper as written, RTAB-Map's convention),
// sigma = 0 gives 2 and near ties give anything up to infinity.
// With `no_signal_virtual_place` > 0, the virtual place's likelihood is that value whenever no
// score stands out (no s_j >= mu + sigma) or sigma is under 1e-4 (the paper's 2011 code: 2), so
// that an image that matches nothing in particular does not push the filter toward a new place
// by mu/sigma, which is then the spread of noise.
Likelihood ComputeLikelihood(const IdMap<double>& scores, double min_sigma_ratio = 0,
                             double no_signal_virtual_place = 0);

}  // namespace memloop
