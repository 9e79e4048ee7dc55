#include "features/whole_image_descriptor.h"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <opencv2/objdetect.hpp>

namespace memloop {

namespace {

constexpr int kWidth = 128, kHeight = 64, kCell = 16, kBins = 9;

const cv::HOGDescriptor& Hog() {
  static const cv::HOGDescriptor hog(cv::Size(kWidth, kHeight), cv::Size(2 * kCell, 2 * kCell),
                                     cv::Size(kCell, kCell), cv::Size(kCell, kCell), kBins);
  return hog;
}

}  // namespace

WholeImageDescriptor DescribeWholeImage(const cv::Mat& gray) {
  if (gray.empty()) return {};
  cv::Mat thumbnail;
  cv::resize(gray, thumbnail, cv::Size(kWidth, kHeight), 0, 0, cv::INTER_AREA);
  std::vector<float> values;
  Hog().compute(thumbnail, values);
  // L2-Hys leaves every value of a block in [0, 1] (clipped at 0.2, then normalised again).
  WholeImageDescriptor descriptor(values.size());
  std::transform(values.begin(), values.end(), descriptor.begin(), [](float value) {
    return static_cast<uint8_t>(std::lround(255.0f * std::clamp(value, 0.0f, 1.0f)));
  });
  return descriptor;
}

double WholeImageSimilarity(const WholeImageDescriptor& a, const WholeImageDescriptor& b) {
  if (a.empty() || a.size() != b.size()) return 0;
  int64_t dot = 0, norm_a = 0, norm_b = 0;
  for (size_t k = 0; k < a.size(); ++k) {
    dot += int64_t{a[k]} * b[k];
    norm_a += int64_t{a[k]} * a[k];
    norm_b += int64_t{b[k]} * b[k];
  }
  if (norm_a == 0 || norm_b == 0) return 0;
  return static_cast<double>(dot) /
         std::sqrt(static_cast<double>(norm_a) * static_cast<double>(norm_b));
}

}  // namespace memloop
