// Geometric verification of a loop-closure hypothesis: the words L_t shares with the matched
// location must be seen from two poses of one rigid scene, that is, satisfy one epipolar
// geometry (a fundamental matrix found by RANSAC). Appearance alone confuses places that look
// alike (perceptual aliasing); their shared words rarely agree on one geometry.
#pragma once

#include <limits>
#include <opencv2/core.hpp>

#include "detector/word_correspondences.h"
#include "memloop/options.h"
#include "vocabulary/signature.h"

namespace memloop {

struct EpipolarCheck {
  int correspondences = 0;  // e.g. words held exactly once by each signature
  int inliers = 0;          // correspondences within ransac_pixels of their epipolar line
  // log10 of the geometry's number of false alarms (epipolar_significance.h): +infinity when
  // not computed (no image size, or under 8 correspondences).
  double log10_false_alarms = std::numeric_limits<double>::infinity();
  bool passed = false;  // inliers >= min_inliers, false alarms <= max_false_alarms when checked
};

// Correspondences are the words each signature holds once (a repeated word's pairing is
// ambiguous). Fewer than 8 (the 8-point algorithm's minimum) or than min_inliers fail at once.
// OpenCV's RANSAC is seeded per call, so the verdict repeats exactly.
EpipolarCheck CheckEpipolarGeometry(const Signature& a, const Signature& b,
                                    const VerificationOptions& options,
                                    const cv::Size& image_size = {});

// The same on given correspondences (in a fixed order, e.g. MatchDescriptors'), in images of
// `image_size` (empty: unknown, false alarms not checked).
EpipolarCheck CheckEpipolarGeometry(const WordCorrespondences& matched,
                                    const VerificationOptions& options,
                                    const cv::Size& image_size = {});

}  // namespace memloop
