#include "features/opencv_features.h"

#include <algorithm>
#include <numeric>
#include <tuple>

namespace memloop {

Features SortStrongestFirst(Features features) {
  std::vector<int> order(features.keypoints.size());
  std::iota(order.begin(), order.end(), 0);
  const auto& keypoints = features.keypoints;
  std::sort(order.begin(), order.end(), [&](int a, int b) {
    const cv::KeyPoint& ka = keypoints[a];
    const cv::KeyPoint& kb = keypoints[b];
    if (ka.response != kb.response) return ka.response > kb.response;
    if (ka.pt.y != kb.pt.y) return ka.pt.y < kb.pt.y;
    if (ka.pt.x != kb.pt.x) return ka.pt.x < kb.pt.x;
    if (ka.size != kb.size) return ka.size < kb.size;
    return ka.angle < kb.angle;
  });
  Features sorted;
  sorted.keypoints.reserve(order.size());
  sorted.descriptors.create(static_cast<int>(order.size()), features.descriptors.cols,
                            features.descriptors.type());
  for (size_t row = 0; row < order.size(); ++row) {
    sorted.keypoints.push_back(keypoints[order[row]]);
    features.descriptors.row(order[row]).copyTo(sorted.descriptors.row(static_cast<int>(row)));
  }
  return sorted;
}

namespace {

// The keypoints at angle 0, each position, size and scale once, in a total order.
std::vector<cv::KeyPoint> Upright(std::vector<cv::KeyPoint> keypoints) {
  for (cv::KeyPoint& keypoint : keypoints) keypoint.angle = 0;
  const auto key = [](const cv::KeyPoint& k) {
    return std::make_tuple(-k.response, k.pt.y, k.pt.x, k.size, k.octave);
  };
  std::sort(keypoints.begin(), keypoints.end(),
            [&](const cv::KeyPoint& a, const cv::KeyPoint& b) { return key(a) < key(b); });
  keypoints.erase(
      std::unique(keypoints.begin(), keypoints.end(),
                  [&](const cv::KeyPoint& a, const cv::KeyPoint& b) { return key(a) == key(b); }),
      keypoints.end());
  return keypoints;
}

}  // namespace

Features DetectAndDescribe(cv::Feature2D& detector, const cv::Mat& gray, int dim, int cv_type,
                           bool upright) {
  Features features;
  if (upright) {
    detector.detect(gray, features.keypoints);
    features.keypoints = Upright(std::move(features.keypoints));
    detector.compute(gray, features.keypoints, features.descriptors);  // at the given angles
  } else {
    detector.detectAndCompute(gray, cv::noArray(), features.keypoints, features.descriptors);
  }
  if (features.descriptors.empty()) features.descriptors = cv::Mat(0, dim, cv_type);
  return SortStrongestFirst(std::move(features));
}

}  // namespace memloop
