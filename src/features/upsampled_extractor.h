// Small images enlarged before feature extraction (features.min_image_side). Detectors find few
// features at low resolution: on the 160x120 corridor sequence memloop's SURF keeps a median of
// 50 keypoints and finds no loop; enlarged 2x, recall at 100% precision is 11.7% with SURF, 24.3%
// with SIFT and 20.7% with ORB (0%, 3.6% and 16.2% before; docs/real-data.md). Lowe's SIFT
// doubles its input for the same reason.
#pragma once

#include <memory>

#include "memloop/feature_extractor.h"

namespace memloop {

// At most this many pixels once enlarged (twice a 1080p frame): a strip such as 30000x10 would
// otherwise be enlarged 24x, to 720000x240 (22 s and 1.8 GB for one image; issue 35).
constexpr double kMaxEnlargedPixels = 4e6;

// The smallest integer factor that brings the smaller side of `size` to at least `min_side`
// pixels, lowered so that the enlarged image has at most kMaxEnlargedPixels; 1 when the side
// already is, or when `min_side` is 0.
int UpsampleFactor(cv::Size size, int min_side);

// Wraps another extractor: images whose smaller side is under `min_side` are enlarged by
// UpsampleFactor (bilinear) and the keypoints (position and size) are given back in the
// image's own pixels. Other images go through unchanged.
class UpsampledExtractor : public FeatureExtractor {
 public:
  UpsampledExtractor(std::unique_ptr<FeatureExtractor> inner, int min_side);
  Features Extract(const cv::Mat& gray) const override;
  int DescriptorDim() const override { return inner_->DescriptorDim(); }
  DescriptorKind Kind() const override { return inner_->Kind(); }
  const char* Name() const override { return inner_->Name(); }

 private:
  std::unique_ptr<FeatureExtractor> inner_;
  int min_side_;
};

}  // namespace memloop
