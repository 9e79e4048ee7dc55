#include "detector/epipolar_check.h"

#include <algorithm>
#include <opencv2/calib3d.hpp>

#include "detector/word_correspondences.h"

namespace memloop {

EpipolarCheck CheckEpipolarGeometry(const Signature& a, const Signature& b,
                                    const VerificationOptions& options) {
  EpipolarCheck check;
  // In a fixed order: RANSAC's samples repeat.
  const WordCorrespondences matched = UniqueWordCorrespondences(a, b);
  check.correspondences = matched.size();
  constexpr int kEightPoints = 8;
  if (check.correspondences < std::max(kEightPoints, options.min_inliers)) return check;
  std::vector<unsigned char> mask;
  const cv::Mat fundamental =
      cv::findFundamentalMat(matched.in_a, matched.in_b, cv::FM_RANSAC, options.ransac_pixels,
                             options.ransac_confidence, mask);
  if (!fundamental.empty()) {
    check.inliers = static_cast<int>(std::count(mask.begin(), mask.end(), 1));
  }
  check.passed = check.inliers >= options.min_inliers;
  return check;
}

}  // namespace memloop
