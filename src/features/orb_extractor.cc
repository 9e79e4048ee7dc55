#include "features/orb_extractor.h"

#include "features/opencv_features.h"

namespace memloop {

OrbExtractor::OrbExtractor(const FeatureOptions& options)
    : orb_(cv::ORB::create(options.max_features > 0 ? options.max_features : 100000)),
      upright_(options.orb_upright != 0) {}

Features OrbExtractor::Extract(const cv::Mat& gray) const {
  return DetectAndDescribe(*orb_, gray, DescriptorDim(), CV_8U, upright_);
}

}  // namespace memloop
