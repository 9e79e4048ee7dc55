// The roll between two views of one place, from where their shared words are: a rotation of the
// camera about its optical axis turns every segment between two keypoints by the same angle,
// while translation and perspective change it little. Each pair of correspondences votes the
// angle by which its segment turned; the densest window of votes is the roll. Unlike each image's
// roll from its edges (camera_roll.h), this measures the two views against each other, so a view
// rolled far from the other is known as such even when both images' edges look upright.
#pragma once

#include "detector/word_correspondences.h"

namespace memloop {

struct ViewRoll {
  bool known = false;  // enough correspondences, and enough of their votes agree
  double degrees = 0;  // b against a, in (-180, 180]
  int correspondences = 0;
  double agreement = 0;  // the share of votes in the window around `degrees` (0..1)
};

// Pairs whose segment is under 8 pixels in either view, or whose length changes by more than 3x
// (a wrong word), do not vote. Known when there are at least 8 correspondences and a quarter of
// the votes fall within 7.5 degrees of the estimate. O(n^2): of more than 100 correspondences,
// the first 100 vote (0.2 ms; once per image, for the highest hypothesis).
ViewRoll EstimateViewRoll(const WordCorrespondences& matched);

}  // namespace memloop
