// The whole-image channel of the observation model (memloop, issue 34; docs/design.md,
// "Whole-image channel"): the image's whole-image descriptor scored against every WM location,
// like eq. 1, and made a likelihood multiplied into eq. 3 and 4. The channels are taken as
// independent given the place, so their likelihoods multiply.
#pragma once

#include "detector/id_map.h"
#include "detector/likelihood.h"
#include "detector/memory.h"
#include "memloop/options.h"

namespace memloop {

struct WholeImageLikelihood {
  IdMap<double> z;           // (s_j - mean) / stddev, 0 with nothing to weigh
  IdMap<double> values;      // the channel's p(L_t | S_t = j)
  double virtual_place = 1;  // the channel's p(L_t | S_t = -1)
  double mean = 0;           // of the scores over WM
  double stddev = 0;
};

// Whether `location` was first seen before image `before` (kNoImage: every location was).
bool SeenBefore(const Location& location, ImageIndex before);

// The score of every WM location first seen before image `before` (0 for one without a
// descriptor). The others are not weighed by the channel.
IdMap<double> ScoreWholeImage(const std::vector<uint8_t>& descriptor, const Memory& memory,
                              ImageIndex before);

// Whether the words' eq. 3 value (before the channel's factor) reaches `min_value` for a WM
// location first seen before image `before`: the words recognize the place, and the channel
// stays out of the image (filter.whole_image_words_first; false with min_value 0).
bool WordsRecognize(const Likelihood& likelihood, const Memory& memory, ImageIndex before,
                    double min_value);

// z_j = (s_j - mean) / stddev over WM. A location is likelier the further its z passes min_z:
// exp(gain * (z_j - min_z)), else 1. Whole-image scores are dense (every image shares gradients
// with every other), so eq. 3's (s - sigma) / mu would barely leave 1; z measures how far the
// place stands out of WM as eq. 3 means to. The virtual place gets the mean of the values over
// WM: what an image of a new place, whose scores are all noise, earns on average; an image's
// weak peak thus moves little mass, while the same place standing out image after image (the
// transition model carries it) builds a hypothesis. All 1 with fewer than 2 locations or no
// spread.
WholeImageLikelihood ComputeWholeImageLikelihood(const IdMap<double>& scores, double gain,
                                                 double min_z);

// Eq. 3 and 4 times the channel's values (a location absent from the channel keeps its value);
// the channel's z go to likelihood.whole_image_z.
void MultiplyLikelihood(WholeImageLikelihood channel, Likelihood& likelihood);

// Location `id`'s eq. 3 from its words alone: likelihood.values without the channel's factor (0
// when it has no value).
double WordLikelihood(const Likelihood& likelihood, LocationId id);

// The three above with filter.whole_image_gain and whole_image_min_z, over the WM locations first
// seen before image `before` (kNoImage: all), unless the words recognize one of them
// (WordsRecognize with filter.whole_image_words_first): then `likelihood` is left as it was.
void WeighWholeImage(const std::vector<uint8_t>& descriptor, const Memory& memory,
                     const FilterOptions& options, ImageIndex before, Likelihood& likelihood);

// filter.whole_image_support_z: a hypothesis whose image stands out of WM by at least `min_z`
// in the channel is supported by the image even when it shares few words with it (by night,
// SURF's words are streetlights and noise). False without the channel or with min_z 0.
bool SupportedByWholeImage(const Likelihood& likelihood, LocationId id, double min_z);

}  // namespace memloop
