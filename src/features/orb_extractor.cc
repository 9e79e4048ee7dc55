#include "features/orb_extractor.h"

#include "features/keypoint_order.h"

namespace memloop {

OrbExtractor::OrbExtractor(const FeatureOptions& options)
    : orb_(cv::ORB::create(options.max_features > 0 ? options.max_features : 100000)) {}

Features OrbExtractor::Extract(const cv::Mat& gray) const {
  Features features;
  orb_->detectAndCompute(gray, cv::noArray(), features.keypoints, features.descriptors);
  if (features.descriptors.empty()) features.descriptors = cv::Mat(0, DescriptorDim(), CV_8U);
  return SortStrongestFirst(std::move(features));
}

}  // namespace memloop
