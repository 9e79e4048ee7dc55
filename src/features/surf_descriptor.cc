#include "features/surf_descriptor.h"

#include <array>
#include <cmath>

namespace memloop {
namespace {

constexpr double kPi = 3.14159265358979323846;

double KeypointScale(const cv::KeyPoint& keypoint) { return 1.2 * keypoint.size / 9.0; }

// Even Haar side closest to `side`, at least 2.
int HaarSide(double side) { return std::max(2, 2 * static_cast<int>(std::lround(side / 2))); }

// The window is resampled in its own frame: a 21 x 21 grid of samples s apart, each the mean of
// the s x s box around its rotated position. Haar responses of side 2s are then differences of
// neighbouring samples along the window's axes, so they turn with the keypoint exactly instead
// of being axis-aligned boxes turned afterwards (as OpenCV's SURF resamples the window too).
void DescribeOne(const IntegralImage& image, const cv::KeyPoint& keypoint, double angle,
                 bool extended, float* out) {
  constexpr int kGrid = 21;
  const double scale = KeypointScale(keypoint);
  const double c = std::cos(angle);
  const double s = std::sin(angle);
  const int half_box =
      std::max(0, static_cast<int>(std::lround(scale / 2)) - (scale < 1.5 ? 1 : 0));
  std::array<float, kGrid * kGrid> patch;
  for (int k = 0; k < kGrid; ++k) {
    const double v = k - 10.0;
    for (int l = 0; l < kGrid; ++l) {
      const double u = l - 10.0;
      const int x = static_cast<int>(std::lround(keypoint.pt.x + scale * (c * u - s * v)));
      const int y = static_cast<int>(std::lround(keypoint.pt.y + scale * (s * u + c * v)));
      const int side = 2 * half_box + 1;
      patch[k * kGrid + l] =
          static_cast<float>(image.BoxSum(y - half_box, x - half_box, y + half_box, x + half_box)) /
          (side * side);
    }
  }
  // The Gaussian (sigma = 3.3s) at each of the 20x20 samples, the same for every keypoint.
  static const std::array<double, 400> kWeights = [] {
    std::array<double, 400> weights{};
    for (int k = 0; k < 20; ++k) {
      const double v = k - 9.5;
      for (int l = 0; l < 20; ++l) {
        const double u = l - 9.5;
        weights[k * 20 + l] = std::exp(-(u * u + v * v) / (2 * 3.3 * 3.3));
      }
    }
    return weights;
  }();
  const int values_per_region = extended ? 8 : 4;
  std::fill(out, out + 16 * values_per_region, 0.0f);
  for (int k = 0; k < 20; ++k) {
    for (int l = 0; l < 20; ++l) {
      const float* top = &patch[k * kGrid + l];
      const float* bottom = top + kGrid;
      const double weight = kWeights[k * 20 + l];
      const float du = static_cast<float>(weight * (top[1] + bottom[1] - top[0] - bottom[0]) / 2);
      const float dv = static_cast<float>(weight * (bottom[0] + bottom[1] - top[0] - top[1]) / 2);
      float* region = out + ((k / 5) * 4 + l / 5) * values_per_region;
      if (!extended) {
        region[0] += du;
        region[1] += std::fabs(du);
        region[2] += dv;
        region[3] += std::fabs(dv);
      } else {
        float* by_dv = region + (dv >= 0 ? 0 : 2);
        by_dv[0] += du;
        by_dv[1] += std::fabs(du);
        float* by_du = region + (du >= 0 ? 4 : 6);
        by_du[0] += dv;
        by_du[1] += std::fabs(dv);
      }
    }
  }
  double norm = 0;
  for (int i = 0; i < 16 * values_per_region; ++i) norm += double{out[i]} * out[i];
  if (norm > 0) {
    const float inverse = static_cast<float>(1.0 / std::sqrt(norm));
    for (int i = 0; i < 16 * values_per_region; ++i) out[i] *= inverse;
  }
}

}  // namespace

double DominantOrientation(const IntegralImage& image, const cv::KeyPoint& keypoint) {
  const double scale = KeypointScale(keypoint);
  const int haar = HaarSide(4 * scale);
  struct Response {
    double angle, dx, dy;
  };
  std::vector<Response> responses;
  responses.reserve(113);
  for (int j = -6; j <= 6; ++j) {
    for (int i = -6; i <= 6; ++i) {
      if (i * i + j * j >= 36) continue;
      const int x = static_cast<int>(std::lround(keypoint.pt.x + i * scale));
      const int y = static_cast<int>(std::lround(keypoint.pt.y + j * scale));
      const double weight = std::exp(-(i * i + j * j) / (2 * 2.0 * 2.0));  // sigma = 2s
      const double dx = weight * image.HaarX(y, x, haar);
      const double dy = weight * image.HaarY(y, x, haar);
      if (dx == 0 && dy == 0) continue;
      responses.push_back({std::atan2(dy, dx), dx, dy});
    }
  }
  double best_norm = -1;
  double best_angle = 0;
  for (int start_degrees = 0; start_degrees < 360; start_degrees += 5) {
    const double start = start_degrees * kPi / 180 - kPi;
    double sum_x = 0;
    double sum_y = 0;
    for (const Response& response : responses) {
      double difference = response.angle - start;
      if (difference < 0) difference += 2 * kPi;
      if (difference < kPi / 3) {
        sum_x += response.dx;
        sum_y += response.dy;
      }
    }
    const double norm = sum_x * sum_x + sum_y * sum_y;
    if (norm > best_norm) {
      best_norm = norm;
      best_angle = std::atan2(sum_y, sum_x);
    }
  }
  return best_angle;
}

cv::Mat DescribeSurf(const IntegralImage& image, std::vector<cv::KeyPoint>& keypoints,
                     const SurfDescriptorOptions& options) {
  const int dim = options.extended ? 128 : 64;
  cv::Mat descriptors(static_cast<int>(keypoints.size()), dim, CV_32F);
  for (size_t n = 0; n < keypoints.size(); ++n) {
    cv::KeyPoint& keypoint = keypoints[n];
    const double angle =
        options.upright ? options.upright_angle : DominantOrientation(image, keypoint);
    double degrees = angle * 180 / kPi;
    if (degrees < 0) degrees += 360;
    keypoint.angle = static_cast<float>(degrees >= 360 ? 0 : degrees);
    DescribeOne(image, keypoint, angle, options.extended,
                descriptors.ptr<float>(static_cast<int>(n)));
  }
  return descriptors;
}

}  // namespace memloop
