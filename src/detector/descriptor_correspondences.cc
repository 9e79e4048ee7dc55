#include "detector/descriptor_correspondences.h"

#include <opencv2/features2d.hpp>

#include "vocabulary/dictionary.h"
#include "vocabulary/signature.h"

namespace memloop {
namespace {

// For each query row: its nearest train row when it passes the ratio test, else -1.
std::vector<int> NearestPassingRatio(const cv::Mat& query, const cv::Mat& train, double ratio) {
  std::vector<int> nearest(query.rows, -1);
  if (query.empty() || train.rows < 2) return nearest;
  cv::BFMatcher matcher(query.type() == CV_8U ? cv::NORM_HAMMING : cv::NORM_L2);
  std::vector<std::vector<cv::DMatch>> matches;
  matcher.knnMatch(query, train, matches, 2);
  for (const auto& pair : matches) {
    if (pair.size() == 2 && pair[0].distance < ratio * pair[1].distance) {
      nearest[pair[0].queryIdx] = pair[0].trainIdx;
    }
  }
  return nearest;
}

}  // namespace

DescribedView WordDescribedView(const Signature& signature, const Dictionary& dictionary) {
  DescribedView view;
  if (signature.keypoints.size() != signature.words.size()) return view;
  view.keypoints = signature.keypoints;
  for (WordId word : signature.words) view.descriptors.push_back(dictionary.Descriptor(word));
  return view;
}

WordCorrespondences MatchDescriptors(const DescribedView& a, const DescribedView& b, double ratio) {
  WordCorrespondences matched;
  if (a.descriptors.rows != a.size() || b.descriptors.rows != b.size() ||
      a.descriptors.type() != b.descriptors.type() || a.descriptors.cols != b.descriptors.cols) {
    return matched;
  }
  const std::vector<int> a_to_b = NearestPassingRatio(a.descriptors, b.descriptors, ratio);
  const std::vector<int> b_to_a = NearestPassingRatio(b.descriptors, a.descriptors, ratio);
  for (int k = 0; k < a.size(); ++k) {
    if (a_to_b[k] < 0 || b_to_a[a_to_b[k]] != k) continue;
    matched.in_a.push_back(a.keypoints[k].pt);
    matched.in_b.push_back(b.keypoints[a_to_b[k]].pt);
    if (a.points.size() == a.keypoints.size()) matched.points_a.push_back(a.points[k]);
  }
  return matched;
}

}  // namespace memloop
