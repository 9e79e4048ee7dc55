#include "detector/epipolar_significance.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace memloop {
namespace {

constexpr int kSample = 7;  // the 7-point algorithm's
constexpr double kSolutions = 3;

double Log10Binomial(int n, int k) {
  return (std::lgamma(n + 1.0) - std::lgamma(k + 1.0) - std::lgamma(n - k + 1.0)) / std::log(10.0);
}

// Sub-pixel residuals are at the keypoints' own precision: no line is thinner than this.
constexpr double kFinestPixels = 0.05;

}  // namespace

double Log10FalseAlarms(int n, int k, double pixels, const cv::Size& size) {
  if (k <= kSample || n < k || size.area() <= 0) return std::numeric_limits<double>::infinity();
  const double diagonal = std::hypot(size.width, size.height);
  const double alpha =
      std::min(1.0, 2.0 * std::max(pixels, kFinestPixels) * diagonal / size.area());
  return std::log10(kSolutions * (n - kSample)) + Log10Binomial(n, k) + Log10Binomial(k, kSample) +
         (k - kSample) * std::log10(alpha);
}

std::vector<double> EpipolarResiduals(const cv::Mat& fundamental,
                                      const std::vector<cv::Point2f>& in_a,
                                      const std::vector<cv::Point2f>& in_b) {
  std::vector<double> residuals;
  if (fundamental.rows != 3 || fundamental.cols != 3) return residuals;
  cv::Matx33d f;
  fundamental.convertTo(cv::Mat(f, false), CV_64F);
  const auto distance = [](const cv::Vec3d& line, const cv::Point2f& p) {
    const double norm = std::hypot(line[0], line[1]);
    return norm > 0 ? std::abs(line[0] * p.x + line[1] * p.y + line[2]) / norm
                    : std::numeric_limits<double>::infinity();
  };
  for (size_t k = 0; k < in_a.size() && k < in_b.size(); ++k) {
    const cv::Vec3d a(in_a[k].x, in_a[k].y, 1), b(in_b[k].x, in_b[k].y, 1);
    residuals.push_back(std::max(distance(f * a, in_b[k]), distance(f.t() * b, in_a[k])));
  }
  return residuals;
}

double LowestLog10FalseAlarms(std::vector<double> residuals, const cv::Size& size) {
  std::sort(residuals.begin(), residuals.end());
  const int n = static_cast<int>(residuals.size());
  double lowest = std::numeric_limits<double>::infinity();
  for (int k = kSample + 1; k <= n; ++k) {
    lowest = std::min(lowest, Log10FalseAlarms(n, k, residuals[k - 1], size));
  }
  return lowest;
}

}  // namespace memloop
