// The whole-image channel's check before acceptance (memloop, issue 34; docs/design.md,
// "Whole-image channel"): one image's whole-image match is often a look-alike place (corridors,
// a stretch of facades), so a loop closure is accepted with the channel on only when the
// channel's best WM location agreed with it over the last few images, moving along the map as
// the robot moves along its route.
#pragma once

#include <deque>

#include "detector/hypothesis.h"
#include "detector/likelihood.h"
#include "detector/memory.h"

namespace memloop {

class WholeImageAgreement {
 public:
  // `images`: how many images, the current one included, must agree (0: no check).
  explicit WholeImageAgreement(int images) : images_(images) {}

  // The image's best WM location in the channel, when its z reaches `min_z` (else none).
  void Observe(const Likelihood& likelihood, double min_z);

  // Refuses `hypothesis` unless each of the last `images` images' best lies within `range` links
  // of it in WM, and they are not all one location (the views moved along the map). Not in the
  // checkpoint: after a resume, loop closures wait for `images` images.
  void Require(const Memory& memory, int range, Hypothesis& hypothesis) const;

 private:
  int images_;
  std::deque<LocationId> bests_;  // newest last
};

}  // namespace memloop
