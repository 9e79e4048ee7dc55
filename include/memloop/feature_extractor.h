// The feature plug-in: one pure-virtual work method and the metadata the dictionary needs.
// Backends: features/surf_extractor.cc (memloop's SURF), features/sift_extractor.cc and
// features/orb_extractor.cc (OpenCV).
#pragma once

#include <memory>
#include <opencv2/core.hpp>
#include <vector>

#include "memloop/options.h"

namespace memloop {

// kFloat: CV_32F rows compared by L2 distance; kBinary: CV_8U rows (bit strings) compared by
// Hamming distance.
enum class DescriptorKind { kFloat, kBinary };

struct Features {
  std::vector<cv::KeyPoint> keypoints;
  cv::Mat descriptors;  // one row per keypoint: CV_32F for kFloat, CV_8U for kBinary
  // surf.rolled_view_degrees: the same keypoints described in the frame of the image's roll;
  // empty when the image has no such view.
  cv::Mat rolled_descriptors;
};

class FeatureExtractor {
 public:
  virtual ~FeatureExtractor() = default;
  // Throws ParameterError naming features.type when the backend is unknown.
  static std::unique_ptr<FeatureExtractor> Create(const FeatureOptions& options);

  // `gray` is an 8-bit single-channel image. The result is deterministic: the same image gives
  // the same keypoints and descriptors in the same order. Thread-compatible, not thread-safe.
  virtual Features Extract(const cv::Mat& gray) const = 0;
  virtual int DescriptorDim() const = 0;  // values (kFloat) or bytes (kBinary) per row
  virtual DescriptorKind Kind() const = 0;
  virtual const char* Name() const = 0;
};

}  // namespace memloop
