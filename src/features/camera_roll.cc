#include "features/camera_roll.h"

#include <cmath>
#include <opencv2/imgproc.hpp>

namespace memloop {

CameraRoll EstimateCameraRoll(const cv::Mat& gray) {
  cv::Mat dx, dy;
  cv::Sobel(gray, dx, CV_32F, 1, 0);
  cv::Sobel(gray, dy, CV_32F, 0, 1);
  double sum_cos = 0, sum_sin = 0, total = 0;
  for (int y = 1; y + 1 < gray.rows; ++y) {
    const float* gx = dx.ptr<float>(y);
    const float* gy = dy.ptr<float>(y);
    for (int x = 1; x + 1 < gray.cols; ++x) {
      const double magnitude = std::hypot(gx[x], gy[x]);
      if (magnitude == 0) continue;
      // cos 4phi and sin 4phi from cos phi = gx / m, sin phi = gy / m, without atan2.
      const double c = gx[x] / magnitude, s = gy[x] / magnitude;
      const double c2 = c * c - s * s, s2 = 2 * s * c;
      sum_cos += magnitude * (c2 * c2 - s2 * s2);
      sum_sin += magnitude * (2 * s2 * c2);
      total += magnitude;
    }
  }
  CameraRoll roll;
  if (total == 0) return roll;
  roll.radians = std::atan2(sum_sin, sum_cos) / 4;
  roll.strength = std::hypot(sum_cos, sum_sin) / total;
  return roll;
}

}  // namespace memloop
