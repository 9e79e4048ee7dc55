#include "features/upsampled_extractor.h"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>

namespace memloop {

int UpsampleFactor(cv::Size size, int min_side) {
  const int smaller = std::min(size.width, size.height);
  if (min_side <= 0 || smaller <= 0 || smaller >= min_side) return 1;
  const int factor = (min_side + smaller - 1) / smaller;
  const double area = static_cast<double>(size.width) * size.height;
  const int within_cap = static_cast<int>(std::sqrt(kMaxEnlargedPixels / area));
  return std::max(1, std::min(factor, within_cap));
}

UpsampledExtractor::UpsampledExtractor(std::unique_ptr<FeatureExtractor> inner, int min_side)
    : inner_(std::move(inner)), min_side_(min_side) {}

Features UpsampledExtractor::Extract(const cv::Mat& gray) const {
  const int factor = UpsampleFactor(gray.size(), min_side_);
  if (factor == 1) return inner_->Extract(gray);
  cv::Mat enlarged;
  cv::resize(gray, enlarged, cv::Size(), factor, factor, cv::INTER_LINEAR);
  Features features = inner_->Extract(enlarged);
  // Pixel centres: enlarged pixel x covers image x' = (x + 0.5) / factor - 0.5.
  const float scale = 1.0f / static_cast<float>(factor);
  const float shift = 0.5f * scale - 0.5f;
  for (cv::KeyPoint& keypoint : features.keypoints) {
    keypoint.pt = keypoint.pt * scale + cv::Point2f(shift, shift);
    keypoint.size *= scale;
  }
  return features;
}

}  // namespace memloop
