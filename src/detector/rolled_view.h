// A second view of a rolled image (surf.rolled_view_degrees; memloop, issue 33). U-SURF describes
// every keypoint at angle 0: views of a place rolled apart by more than ~10 degrees share few
// words. A hand-held camera rolls: lip6_outdoor's last 60 images are rolled 9-25 degrees against
// the first pass. Describing the image in the frame of its roll instead (surf.max_roll_degrees)
// matches them, but then every location's words are roll-compensated, and a camera turning about
// one spot (tum_fr1_rpy) sees its views at every roll look alike. Here the location keeps its
// upright words; only the image's observation gains a second view, its keypoints described in
// the frame of its roll and matched to the dictionary (no word created), and each WM location
// scores the better of the two views in eq. 1. The rolled view finds the places seen upright,
// the upright view those seen at the same roll.
#pragma once

#include "detector/id_map.h"
#include "detector/memory.h"
#include "memloop/feature_extractor.h"
#include "vocabulary/signature.h"

namespace memloop {

class RolledView {
 public:
  // This image's rolled view, from its features (Features::rolled_descriptors): none when the
  // extractor gave none.
  void Observe(const Features& features, const Dictionary& dictionary);

  // Eq. 1 of the rolled view against WM, scored as an image of `image_words` words (z_t's size):
  // each score it beats is raised to its own, and the location is then matched by this view.
  void Raise(const Memory& memory, size_t image_words, IdMap<double>& scores);

  // The view that gave location `id` its score in the last Raise: the rolled one, or z_t. What
  // is checked on a hypothesis (shared words, the view roll, epipolar geometry) is checked on it.
  const Signature& ViewOf(LocationId id, const Signature& z_t) const;

  bool present() const { return present_; }
  int raised() const { return static_cast<int>(raised_.size()); }

 private:
  Signature view_;
  bool present_ = false;
  IdSet raised_;
};

}  // namespace memloop
