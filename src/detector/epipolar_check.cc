#include "detector/epipolar_check.h"

#include <algorithm>
#include <opencv2/calib3d.hpp>
#include <unordered_map>

namespace memloop {
namespace {

// Word -> keypoint index for the words a signature holds exactly once.
std::unordered_map<WordId, int> UniqueWords(const Signature& signature) {
  std::unordered_map<WordId, int> unique;
  std::unordered_map<WordId, int> count;
  for (int k = 0; k < signature.size(); ++k) {
    if (++count[signature.words[k]] == 1) unique[signature.words[k]] = k;
  }
  for (const auto& [word, n] : count) {
    if (n > 1) unique.erase(word);
  }
  return unique;
}

}  // namespace

EpipolarCheck CheckEpipolarGeometry(const Signature& a, const Signature& b,
                                    const VerificationOptions& options) {
  EpipolarCheck check;
  if (a.keypoints.size() != a.words.size() || b.keypoints.size() != b.words.size()) return check;
  const std::unordered_map<WordId, int> in_b = UniqueWords(b);
  std::vector<std::pair<WordId, int>> in_a_sorted;
  for (const auto& entry : UniqueWords(a)) in_a_sorted.push_back(entry);
  std::sort(in_a_sorted.begin(), in_a_sorted.end());  // a fixed order: RANSAC's samples repeat
  std::vector<cv::Point2f> points_a, points_b;
  for (const auto& [word, k] : in_a_sorted) {
    const auto found = in_b.find(word);
    if (found == in_b.end()) continue;
    points_a.push_back(a.keypoints[k].pt);
    points_b.push_back(b.keypoints[found->second].pt);
  }
  check.correspondences = static_cast<int>(points_a.size());
  constexpr int kEightPoints = 8;
  if (check.correspondences < std::max(kEightPoints, options.min_inliers)) return check;
  std::vector<unsigned char> mask;
  const cv::Mat fundamental = cv::findFundamentalMat(
      points_a, points_b, cv::FM_RANSAC, options.ransac_pixels, options.ransac_confidence, mask);
  if (!fundamental.empty()) {
    check.inliers = static_cast<int>(std::count(mask.begin(), mask.end(), 1));
  }
  check.passed = check.inliers >= options.min_inliers;
  return check;
}

}  // namespace memloop
