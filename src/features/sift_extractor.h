#pragma once

#include <opencv2/features2d.hpp>

#include "memloop/feature_extractor.h"

namespace memloop {

// OpenCV's SIFT (Lowe 2004), 128-d float descriptors; upright by default (sift.upright).
class SiftExtractor : public FeatureExtractor {
 public:
  explicit SiftExtractor(const FeatureOptions& options);
  Features Extract(const cv::Mat& gray) const override;
  int DescriptorDim() const override { return 128; }
  DescriptorKind Kind() const override { return DescriptorKind::kFloat; }
  const char* Name() const override { return "sift"; }

 private:
  cv::Ptr<cv::SIFT> sift_;
  bool upright_;
};

}  // namespace memloop
