// Keypoint correspondences between two signatures through their shared visual words: the
// geometry behind eq. 1's word pairs, for the checks that look at where the words are.
#pragma once

#include <opencv2/core.hpp>
#include <vector>

#include "vocabulary/signature.h"

namespace memloop {

struct WordCorrespondences {
  std::vector<cv::Point2f> in_a, in_b;  // the same word's keypoint in each signature
  // a's keypoints in 3-D (its camera's frame, metres; z = 0: no depth), when a's view has depth.
  std::vector<cv::Point3f> points_a;
  int size() const { return static_cast<int>(in_a.size()); }
};

// The words each signature holds exactly once (a repeated word's pairing is ambiguous), in
// increasing word order, so that what is computed from them repeats exactly.
WordCorrespondences UniqueWordCorrespondences(const Signature& a, const Signature& b);

}  // namespace memloop
