#include "detector/loop_acceptance.h"

#include <algorithm>
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
                           int* inliers) {
  if (options_.filter.cap_merged_images && image.merged) {
    CapRepeatedObservation(previous_value, options_.filter.loop_threshold, hypothesis);
  }
  RequireSupport(image, hypothesis);
  RequireSimilarRoll(image.view, hypothesis);
  RequireLoopRatio(previous_value, options_.filter.loop_ratio, hypothesis);
  if (hypothesis.id != kNoLocation) previous_value = hypothesis.value;
  CheckLtmNeighbours(image.appearance, hypothesis);
  const bool over_verified =
      hypothesis.eligible && hypothesis.value > options_.verification.loop_threshold;
  const bool verified = Verify(image, hypothesis, inliers);
  const bool agrees_next =
      options_.verification.previous_agrees >= 2 ? hypothesis.accepted || verified : over_verified;
  previous_agreeing_ = agrees_next ? hypothesis.id : kNoLocation;
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

// With verify.loop_threshold 0, every eligible hypothesis is checked, accepted or not, so that
// precision-recall curves sweep T_loop over what verification lets through; with T_verified,
// those between it and T_loop, which verification accepts. With verify.correspondences=descriptors
// the image's own keypoints (not an older image's after Rehearsal, nor a rolled view) are matched
// to L_i's by descriptor: on a changed viewpoint they find the correspondences shared word ids
// miss.
bool LoopAcceptance::Verify(const Image& image, Hypothesis& hypothesis, int* inliers) const {
  const VerificationOptions& verification = options_.verification;
  if (verification.min_inliers == 0 || !hypothesis.eligible) return false;
  const bool two_thresholds = verification.loop_threshold > 0;
  if (two_thresholds && (hypothesis.value <= verification.loop_threshold ||
                         hypothesis.value > options_.filter.loop_threshold)) {
    return false;  // below T_verified, nothing to accept; over T_loop, appearance alone accepts
  }
  const Signature& z_i = memory_.at(hypothesis.id).signature;
  const EpipolarCheck check =
      verification.correspondences == "descriptors"
          ? CheckEpipolarGeometry(
                MatchDescriptors(image.keypoints, WordDescribedView(z_i, memory_.dictionary())),
                verification, image.keypoints.image_size)
          : CheckEpipolarGeometry(image.view, z_i, verification, image.keypoints.image_size);
  *inliers = check.inliers;
  if (two_thresholds) {
    // The value stays eligible: the precision-recall sweep is T_loop's, as in the paper.
    hypothesis.accepted = check.passed && PreviousAgrees(hypothesis);
  } else if (!check.passed) {
    hypothesis.Refuse();
  }
  return check.passed;
}

// verify.previous_agrees: the previous image's hypothesis lay near L_i (and was over T_verified,
// or with 2 a loop closure or verified). A corridor seen again further on satisfies one epipolar
// geometry (its doors repeat along the epipole's lines), as does one sign on two buildings; the
// robot's previous image rarely confirmed the same look-alike.
bool LoopAcceptance::PreviousAgrees(const Hypothesis& hypothesis) const {
  if (!options_.verification.previous_agrees) return true;
  if (previous_agreeing_ == kNoLocation || !memory_.Contains(previous_agreeing_)) {
    return false;
  }
  const Neighbourhood near =
      memory_.WmNeighbourhood(hypothesis.id, options_.filter.neighbour_range);
  return std::any_of(near.begin(), near.end(),
                     [&](const auto& entry) { return entry.first == previous_agreeing_; });
}

}  // namespace memloop
