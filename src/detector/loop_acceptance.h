// From the filter's highest hypothesis to a loop closure (III-D): T_loop, and the checks memloop
// adds before it (hypothesis.h has each rule; docs/design.md says why and what each measured).
// A check that fails refuses the hypothesis: it keeps its value, so precision-recall curves
// still sweep T_loop over what the checks let through.
#pragma once

#include "detector/descriptor_correspondences.h"
#include "detector/hypothesis.h"
#include "detector/likelihood.h"
#include "detector/memory.h"
#include "detector/whole_image_agreement.h"
#include "memloop/options.h"
#include "storage/long_term_memory.h"
#include "vocabulary/appearance_index.h"
#include "vocabulary/signature.h"

namespace memloop {

// Epipolar verification needs the image's own keypoints and descriptors (image_view.h).
inline bool VerifiesByDescriptors(const VerificationOptions& verification) {
  return verification.min_inliers > 0 && verification.correspondences == "descriptors";
}

class LoopAcceptance {
 public:
  // `appearance`: retrieval by appearance's index, or null. All are read, never changed.
  LoopAcceptance(const Options& options, const Memory& memory, const LongTermMemory& ltm,
                 const AppearanceIndex* appearance);

  // What the image brings to the checks.
  struct Image {
    const Signature& z_t;            // its location's words (an older image's after Rehearsal)
    const Signature& view;           // what matched L_i: z_t, or the image's rolled view
    bool merged;                     // Rehearsal merged the image into an older location
    const Signature* own_words;      // its own words then (with filter.support_from_image), or null
    const Likelihood& likelihood;    // eq. 3, with the whole-image channel's factor
    const Appearance* appearance;    // retrieval by appearance's description, or null
    const DescribedView& keypoints;  // its own keypoints and descriptors (image_view.h)
  };

  // Before Check, at every image: the whole-image channel's best WM location.
  void Observe(const Likelihood& likelihood);

  // The checks, in order: filter.cap_merged_images, support (filter.require_support,
  // min_shared_words, support_from_image, which may name a WM location linked to L_i instead of
  // L_i, the whole-image channel's agreement),
  // verify.max_roll_degrees, filter.loop_ratio, filter.ltm_neighbour_check, epipolar
  // verification (with T_verified, verify.previous_agrees). `previous_value`: the previous image's
  // value as compared with T_loop, updated to this image's. `inliers` receives the epipolar inliers
  // when verification ran.
  void Check(const Image& image, double& previous_value, Hypothesis& hypothesis, int* inliers);

 private:
  void RequireSupport(const Image& image, Hypothesis& hypothesis) const;
  bool SupportedByWords(const Signature& view, const Likelihood& likelihood, LocationId id) const;
  LocationId PlaceOfOwnWords(const Image& image, LocationId id) const;
  void RequireSimilarRoll(const Signature& view, Hypothesis& hypothesis) const;
  void CheckLtmNeighbours(const Appearance* appearance, Hypothesis& hypothesis) const;
  // True when verification ran and passed.
  bool Verify(const Image& image, Hypothesis& hypothesis, int* inliers) const;
  bool PreviousAgrees(const Hypothesis& hypothesis) const;

  const Options& options_;
  const Memory& memory_;
  const LongTermMemory& ltm_;
  const AppearanceIndex* appearance_;
  WholeImageAgreement agreement_;
  // The previous image's hypothesis when it can agree with this image's (verify.previous_agrees:
  // eligible and over T_verified, or with 2 a loop closure or verified). Not in the checkpoint:
  // after a resume, a loop closure under T_loop waits one image.
  LocationId previous_agreeing_ = kNoLocation;
};

}  // namespace memloop
