#include "features/sift_extractor.h"

#include "features/keypoint_order.h"

namespace memloop {

SiftExtractor::SiftExtractor(const FeatureOptions& options)
    : sift_(cv::SIFT::create(options.max_features)) {}

Features SiftExtractor::Extract(const cv::Mat& gray) const {
  Features features;
  sift_->detectAndCompute(gray, cv::noArray(), features.keypoints, features.descriptors);
  if (features.descriptors.empty()) features.descriptors = cv::Mat(0, DescriptorDim(), CV_32F);
  return SortStrongestFirst(std::move(features));
}

}  // namespace memloop
