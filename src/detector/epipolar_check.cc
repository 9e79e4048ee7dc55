#include "detector/epipolar_check.h"

#include <algorithm>
#include <cmath>
#include <opencv2/calib3d.hpp>

#include "detector/epipolar_significance.h"
#include "detector/word_correspondences.h"

namespace memloop {

EpipolarCheck CheckEpipolarGeometry(const Signature& a, const Signature& b,
                                    const VerificationOptions& options,
                                    const cv::Size& image_size) {
  // In a fixed order: RANSAC's samples repeat.
  return CheckEpipolarGeometry(UniqueWordCorrespondences(a, b), options, image_size);
}

EpipolarCheck CheckEpipolarGeometry(const WordCorrespondences& matched,
                                    const VerificationOptions& options,
                                    const cv::Size& image_size) {
  EpipolarCheck check;
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
  if (options.max_false_alarms > 0 && !image_size.empty() && !fundamental.empty()) {
    check.log10_false_alarms = LowestLog10FalseAlarms(
        EpipolarResiduals(fundamental.rowRange(0, 3), matched.in_a, matched.in_b), image_size);
    check.passed &= check.log10_false_alarms <= std::log10(options.max_false_alarms);
  }
  return check;
}

}  // namespace memloop
