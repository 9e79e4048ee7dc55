#pragma once

#include <opencv2/features2d.hpp>

#include "memloop/feature_extractor.h"

namespace memloop {

// OpenCV's ORB (Rublee et al. 2011): 256-bit binary descriptors (32 bytes), compared by Hamming
// distance; the dictionary indexes them by LSH. Upright by default (orb.upright).
class OrbExtractor : public FeatureExtractor {
 public:
  explicit OrbExtractor(const FeatureOptions& options);
  Features Extract(const cv::Mat& gray) const override;
  int DescriptorDim() const override { return 32; }
  DescriptorKind Kind() const override { return DescriptorKind::kBinary; }
  const char* Name() const override { return "orb"; }

 private:
  cv::Ptr<cv::ORB> orb_;
  bool upright_;
};

}  // namespace memloop
