#include "detector/loop_acceptance.h"

#include <functional>

#include "detector/epipolar_check.h"
#include "detector/view_roll.h"
#include "detector/whole_image_likelihood.h"
#include "detector/word_correspondences.h"

namespace memloop {

LoopAcceptance::LoopAcceptance(const Options& options, const Memory& memory,
                               const LongTermMemory& ltm, const AppearanceIndex* appearance)
    : options_(options),
      memory_(memory),
      ltm_(ltm),
      appearance_(appearance),
      agreement_(options.features.whole_image ? options.filter.whole_image_agreement : 0) {}

void LoopAcceptance::Observe(const Likelihood& likelihood) {
  if (options_.features.whole_image) {
    agreement_.Observe(likelihood, options_.filter.whole_image_support_z);
  }
}

void LoopAcceptance::Check(const Image& image, double& previous_value, Hypothesis& hypothesis,
                           int* inliers) const {
  if (options_.filter.cap_merged_images && image.merged) {
    CapRepeatedObservation(previous_value, options_.filter.loop_threshold, hypothesis);
  }
  RequireSupport(image, hypothesis);
  RequireSimilarRoll(image.view, hypothesis);
  RequireLoopRatio(previous_value, options_.filter.loop_ratio, hypothesis);
  if (hypothesis.id != kNoLocation) previous_value = hypothesis.value;
  CheckLtmNeighbours(image.appearance, hypothesis);
  Verify(image.view, hypothesis, inliers);
}

// A loop closure says that the image matches L_i: with filter.require_support, the image's own
// likelihood for L_i must stand out (eq. 3 above 1, s_i >= mu + sigma); a hypothesis carried
// only by the prior (just after leaving a revisited stretch) is not eligible. Standing out is
// relative, so filter.min_shared_words also asks for a few shared words (hypothesis.h).
void LoopAcceptance::RequireSupport(const Image& image, Hypothesis& hypothesis) const {
  if (hypothesis.id == kNoLocation) return;
  // Supported by the whole image instead of words only if the channel agreed over images.
  if (SupportedByWholeImage(image.likelihood, hypothesis.id,
                            options_.filter.whole_image_support_z)) {
    return agreement_.Require(memory_, options_.filter.neighbour_range, hypothesis);
  }
  if (!SupportedByWords(image.view, image.likelihood, hypothesis.id)) return hypothesis.Refuse();
  const LocationId place = PlaceOfOwnWords(image, hypothesis.id);
  if (place == kNoLocation) return hypothesis.Refuse();
  hypothesis.id = place;
}

// The words' own eq. 3, without the whole-image channel's factor: a channel's look-alike with a
// few chance words is not supported by words.
bool LoopAcceptance::SupportedByWords(const Signature& view, const Likelihood& likelihood,
                                      LocationId id) const {
  if (!SharesWords(view, memory_.at(id).signature, options_.filter.min_shared_words)) {
    return false;
  }
  return !options_.filter.require_support || WordLikelihood(likelihood, id) > 1.0;
}

// filter.support_from_image: after a Rehearsal merge z_t holds an older image's words; the
// image's own must support the place the loop closure names: L_i, or with 2 the WM location
// linked to L_i they support best. kNoLocation when none is (a rolled view is the image's own).
LocationId LoopAcceptance::PlaceOfOwnWords(const Image& image, LocationId id) const {
  const FilterOptions& filter = options_.filter;
  if (!filter.require_support || !filter.support_from_image || image.own_words == nullptr ||
      &image.view != &image.z_t) {
    return id;
  }
  const auto supports = [&](LocationId j) {
    return SupportedByImage(*image.own_words, memory_.at(j).signature, image.likelihood.mean,
                            filter.min_shared_words);
  };
  if (supports(id)) return id;
  if (filter.support_from_image < 2) return kNoLocation;
  LocationId best = kNoLocation;
  double best_score = 0;
  for (LocationId j : memory_.LinksOf(id)) {
    if (!memory_.InWorkingMemory(j) || !supports(j)) continue;
    const double score = Similarity(*image.own_words, memory_.at(j).signature);
    if (score > best_score) best = j, best_score = score;
  }
  return best;
}

// verify.max_roll_degrees: the roll between the two views, from their shared words' positions.
void LoopAcceptance::RequireSimilarRoll(const Signature& view, Hypothesis& hypothesis) const {
  const double max_degrees = options_.verification.max_roll_degrees;
  if (max_degrees <= 0 || hypothesis.id == kNoLocation || !hypothesis.eligible) return;
  const Signature& z_i = memory_.at(hypothesis.id).signature;
  memloop::RequireSimilarRoll(EstimateViewRoll(UniqueWordCorrespondences(view, z_i)), max_degrees,
                              hypothesis);
}

// filter.ltm_neighbour_check (hypothesis.h), at every image: the filter weighs WM alone, and a
// location linked to L_i that left for LTM (deferred for T_time, or transferred under a small
// WM) may be where the image was taken. The three false positives of a 50,000-image run under
// T_time, and the five of tum_fr1_rpy (ORB, SIFT) at a quarter of the unbounded WM, were such
// hypotheses (docs/design.md, "LTM-neighbour check").
void LoopAcceptance::CheckLtmNeighbours(const Appearance* appearance,
                                        Hypothesis& hypothesis) const {
  if (!options_.filter.ltm_neighbour_check || hypothesis.id == kNoLocation) return;
  std::function<double(LocationId)> looks_like_image;
  if (appearance_ != nullptr && appearance != nullptr) {
    looks_like_image = [&](LocationId id) { return appearance_->Score(*appearance, id); };
  }
  memloop::CheckLtmNeighbours(
      memory_.LinksOf(hypothesis.id), [&](LocationId id) { return ltm_.Contains(id); },
      looks_like_image, hypothesis);
}

// Every eligible hypothesis is checked, accepted or not, so that precision-recall curves sweep
// T_loop over what verification lets through.
void LoopAcceptance::Verify(const Signature& view, Hypothesis& hypothesis, int* inliers) const {
  if (options_.verification.min_inliers == 0 || !hypothesis.eligible) return;
  const EpipolarCheck check =
      CheckEpipolarGeometry(view, memory_.at(hypothesis.id).signature, options_.verification);
  *inliers = check.inliers;
  if (!check.passed) hypothesis.Refuse();
}

}  // namespace memloop
