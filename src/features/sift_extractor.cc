#include "features/sift_extractor.h"

#include "features/opencv_features.h"

namespace memloop {

SiftExtractor::SiftExtractor(const FeatureOptions& options)
    : sift_(cv::SIFT::create(options.max_features)), upright_(options.sift_upright != 0) {}

Features SiftExtractor::Extract(const cv::Mat& gray) const {
  return DetectAndDescribe(*sift_, gray, DescriptorDim(), CV_32F, upright_);
}

}  // namespace memloop
