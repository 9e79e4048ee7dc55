#pragma once

#include "features/fast_hessian.h"
#include "features/surf_descriptor.h"
#include "memloop/feature_extractor.h"

namespace memloop {

// SURF (Bay et al., CVIU 2008), written here: Debian's OpenCV has no xfeatures2d. 64-d (or
// 128-d extended) float descriptors; the keypoint's class_id holds the sign of the Laplacian.
// Single-threaded and deterministic. docs/surf.md says where it departs from the paper.
class SurfExtractor : public FeatureExtractor {
 public:
  explicit SurfExtractor(const FeatureOptions& options);
  Features Extract(const cv::Mat& gray) const override;
  int DescriptorDim() const override { return descriptor_.extended ? 128 : 64; }
  DescriptorKind Kind() const override { return DescriptorKind::kFloat; }
  const char* Name() const override { return "surf"; }

 private:
  FastHessianOptions detector_;
  SurfDescriptorOptions descriptor_;
  int max_features_;
  double max_roll_radians_ = 0;  // surf.max_roll_degrees
  double min_roll_strength_ = 0;
  double min_roll_radians_ = 0;
  double rolled_view_radians_ = 0;  // surf.rolled_view_degrees
};

}  // namespace memloop
