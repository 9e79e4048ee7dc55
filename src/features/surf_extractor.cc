#include "features/surf_extractor.h"

#include <algorithm>

namespace memloop {

SurfExtractor::SurfExtractor(const FeatureOptions& options) : max_features_(options.max_features) {
  detector_.hessian_threshold = options.surf_hessian_threshold;
  detector_.octaves = options.surf_octaves;
  detector_.intervals = options.surf_intervals;
  detector_.sample_step = options.surf_sample_step;
  descriptor_.upright = options.surf_upright != 0;
  descriptor_.extended = options.surf_extended != 0;
}

Features SurfExtractor::Extract(const cv::Mat& gray) const {
  const IntegralImage image(gray);
  Features features;
  features.keypoints = DetectFastHessian(image, detector_);
  // The strongest first (then by position, so the order is total); describe only those kept.
  std::sort(features.keypoints.begin(), features.keypoints.end(),
            [](const cv::KeyPoint& a, const cv::KeyPoint& b) {
              if (a.response != b.response) return a.response > b.response;
              if (a.pt.y != b.pt.y) return a.pt.y < b.pt.y;
              if (a.pt.x != b.pt.x) return a.pt.x < b.pt.x;
              return a.size < b.size;
            });
  if (max_features_ > 0 && static_cast<int>(features.keypoints.size()) > max_features_) {
    features.keypoints.resize(max_features_);
  }
  features.descriptors = DescribeSurf(image, features.keypoints, descriptor_);
  return features;
}

}  // namespace memloop
