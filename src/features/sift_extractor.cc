#include "features/sift_extractor.h"

#include <algorithm>
#include <numeric>

namespace memloop {

SiftExtractor::SiftExtractor(const FeatureOptions& options)
    : sift_(cv::SIFT::create(options.max_features)) {}

Features SiftExtractor::Extract(const cv::Mat& gray) const {
  Features raw;
  sift_->detectAndCompute(gray, cv::noArray(), raw.keypoints, raw.descriptors);
  // OpenCV gathers keypoints from parallel workers, so their order can vary between runs.
  // A total order (strongest first, then position) makes the signature repeatable.
  std::vector<int> order(raw.keypoints.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](int a, int b) {
    const cv::KeyPoint& ka = raw.keypoints[a];
    const cv::KeyPoint& kb = raw.keypoints[b];
    if (ka.response != kb.response) return ka.response > kb.response;
    if (ka.pt.y != kb.pt.y) return ka.pt.y < kb.pt.y;
    if (ka.pt.x != kb.pt.x) return ka.pt.x < kb.pt.x;
    if (ka.size != kb.size) return ka.size < kb.size;
    return ka.angle < kb.angle;
  });
  Features sorted;
  sorted.keypoints.reserve(order.size());
  sorted.descriptors.create(static_cast<int>(order.size()), DescriptorDim(), CV_32F);
  for (size_t row = 0; row < order.size(); ++row) {
    sorted.keypoints.push_back(raw.keypoints[order[row]]);
    raw.descriptors.row(order[row]).copyTo(sorted.descriptors.row(static_cast<int>(row)));
  }
  return sorted;
}

}  // namespace memloop
