// Loop-closure hypothesis selection (paper III-D).
#pragma once

#include <functional>
#include <vector>

#include "detector/bayes_filter.h"
#include "detector/view_roll.h"
#include "memloop/options.h"
#include "vocabulary/signature.h"

namespace memloop {

struct Hypothesis {
  LocationId id = kNoLocation;  // highest hypothesis, kNoLocation when WM is empty
  double value = 0;             // compared with T_loop (FilterOptions::hypothesis_value)
  bool eligible = false;        // WM holds at least T_minHyp locations: T_loop alone decides
  bool accepted = false;        // eligible and value > T_loop
  // The filter's highest hypothesis, which retrieval (III-E) and the past matches follow; `id`
  // may instead name a WM location linked to it (filter.support_from_image 2).
  LocationId filter_id = kNoLocation;

  // A check beside T_loop refused it: not accepted at any threshold.
  void Refuse() { eligible = accepted = false; }
};

// The highest hypothesis is the WM location of highest posterior (ties: the older); its value is
// the posterior summed over its neighbourhood (the transition model's range), because a loop
// closure's probability spreads to the neighbours of the matched location. The paper's text also
// reads as "the highest of the neighbour sums"; that choice names the centre of the probability
// mass rather than the best match, so matches lag behind along a path (RTAB-Map, by the same
// authors, sums around the highest posterior, as here).
// With hypothesis_value "best_neighbours" (the paper's 2011 code) the neighbour sum of every WM
// location is computed and the highest is the value; the hypothesis is the location of highest
// posterior inside that neighbourhood.
// With hypothesis_value "loop_mass" the value is instead 1 - p(S_t = -1) (`virtual_place`).
Hypothesis SelectHypothesis(const IdMap<double>& posterior, double virtual_place,
                            const Neighbourhoods& neighbourhoods, const FilterOptions& options);

// filter.loop_ratio (the paper's 2011 code, LoopRatio): the hypothesis is refused unless its value
// is at least `ratio` times the previous image's highest hypothesis value, which must not be 0.
void RequireLoopRatio(double previous_value, double ratio, Hypothesis& hypothesis);

// filter.cap_merged_images (memloop): on an image that Rehearsal merged into an older location,
// whose words the filter has observed already, the hypothesis' value is at most
// `previous_value` (the previous image's, as compared with T_loop) and is accepted only when that
// value is over `loop_threshold`: repeated evidence keeps a loop closure, it does not make one.
void CapRepeatedObservation(double previous_value, double loop_threshold, Hypothesis& hypothesis);

// verify.max_roll_degrees (memloop): L_i is refused when the camera's roll between the image and
// L_i, measured from where their shared words are (view_roll.h), is known and over `max_degrees`
// (0: no check). Roll-compensated U-SURF and oriented features make views rolled far apart look
// alike; by what they see, they are other views (a hand-held camera turned about its axis).
// An unknown roll (few shared words: a hypothesis the filter carries) is not refused.
void RequireSimilarRoll(const ViewRoll& roll, double max_degrees, Hypothesis& hypothesis);

// filter.min_shared_words (memloop): true when the image `z_t` shares at least `min_words` words
// with L_i (eq. 1's N_pair, `z_i`; always with `min_words` 0). When an image matches almost
// nothing, mu and sigma of eq. 3 are tiny and a location sharing two words "stands out" as much as
// a true match: the support of eq. 3 is relative, this floor is absolute.
bool SharesWords(const Signature& z_t, const Signature& z_i, int min_words);

// filter.support_from_image (memloop): true when the image's own words (`image`, before Rehearsal
// replaced them with an older image's) share at least `min_words` words with L_i (`z_i`) and
// score at least `min_score` against it in eq. 1 (the mean mu of z_t's non-null WM scores: the
// image still looks more like L_i than an average WM location does).
bool SupportedByImage(const Signature& image, const Signature& z_i, double min_score,
                      int min_words);

// filter.ltm_neighbour_check (memloop): L_i is refused while a location linked to it (`links`) is
// in LTM and looks more like the image than L_i does: the image may have been taken there, where
// the filter could not look (it was transferred, its retrieval was deferred, or comes after this
// selection), so the hypothesis lags behind the robot. `looks_like_image` scores a location against
// the image (retrieval by appearance's descriptions); without it, any linked LTM location refuses.
void CheckLtmNeighbours(const std::vector<LocationId>& links,
                        const std::function<bool(LocationId)>& in_ltm,
                        const std::function<double(LocationId)>& looks_like_image,
                        Hypothesis& hypothesis);

}  // namespace memloop
