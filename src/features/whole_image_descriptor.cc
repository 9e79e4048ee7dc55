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
  if (a.empty() || a.size() != b.size() || a.size() % kBins != 0) return 0;
  // Each cell centred on its mean over the orientations: that mean is gradient energy in every
  // direction (sensor noise, what blur leaves), which a night raises everywhere and which says
  // nothing of the place; what is left is which orientations stand out in the cell.
  double dot = 0, norm_a = 0, norm_b = 0;
  for (size_t cell = 0; cell < a.size(); cell += kBins) {
    int sum_a = 0, sum_b = 0;
    for (size_t k = cell; k < cell + kBins; ++k) {
      sum_a += a[k];
      sum_b += b[k];
    }
    const double mean_a = static_cast<double>(sum_a) / kBins;
    const double mean_b = static_cast<double>(sum_b) / kBins;
    for (size_t k = cell; k < cell + kBins; ++k) {
      const double x = a[k] - mean_a, y = b[k] - mean_b;
      dot += x * y;
      norm_a += x * x;
      norm_b += y * y;
    }
  }
  if (norm_a == 0 || norm_b == 0) return 0;
  return dot / std::sqrt(norm_a * norm_b);
}

}  // namespace memloop
