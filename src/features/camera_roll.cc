#include "features/camera_roll.h"

#include <cmath>
#include <opencv2/imgproc.hpp>

namespace memloop {

CameraRoll EstimateCameraRoll(const cv::Mat& gray) {
  cv::Mat dx, dy;
  cv::Sobel(gray, dx, CV_32F, 1, 0);
  cv::Sobel(gray, dy, CV_32F, 0, 1);
  // m e^{4 i phi} = (gx + i gy)^4 / m^3: one square root a pixel, no hypot (5.8 -> 2.4
  // ms at 960x540, BM_EstimateCameraRoll; an OpenCV array version took 3.6 ms). Sums in float
  // along a row, in double over rows.
  double sum_cos = 0, sum_sin = 0, total = 0;
  for (int y = 1; y + 1 < gray.rows; ++y) {
    const float* gx = dx.ptr<float>(y);
    const float* gy = dy.ptr<float>(y);
    float row_cos = 0, row_sin = 0, row_total = 0;
    for (int x = 1; x + 1 < gray.cols; ++x) {
      const float squared = gx[x] * gx[x] + gy[x] * gy[x];
      const float magnitude = std::sqrt(squared);
      const float c2 = gx[x] * gx[x] - gy[x] * gy[x], s2 = 2 * gx[x] * gy[x];  // m^2 e^{2 i phi}
      const float weight = squared > 0 ? 1 / (squared * magnitude) : 0.0f;
      row_cos += (c2 * c2 - s2 * s2) * weight;
      row_sin += (2 * s2 * c2) * weight;
      row_total += magnitude;
    }
    sum_cos += row_cos;
    sum_sin += row_sin;
    total += row_total;
  }
  CameraRoll roll;
  if (total == 0) return roll;
  roll.radians = std::atan2(sum_sin, sum_cos) / 4;
  roll.strength = std::hypot(sum_cos, sum_sin) / total;
  return roll;
}

}  // namespace memloop
