// SURF orientation and descriptor (Bay et al., CVIU 2008, Sec. 4), from Haar wavelet responses
// on the integral image at the keypoint's scale s = 1.2 L / 9.
#pragma once

#include <opencv2/core.hpp>
#include <vector>

#include "features/integral_image.h"

namespace memloop {

struct SurfDescriptorOptions {
  bool upright = false;      // U-SURF: no orientation (angle `upright_angle`)
  double upright_angle = 0;  // radians: U-SURF's frame (the camera's roll, camera_roll.h)
  bool extended = false;     // 128 values instead of 64
};

// Sec. 4.1: Haar responses of side 4s at the samples within 6s of the keypoint, weighted by a
// Gaussian (sigma = 2s); the orientation is that of the largest sum of responses within a
// sliding window of 60 degrees. Radians, image axes (y down).
double DominantOrientation(const IntegralImage& image, const cv::KeyPoint& keypoint);

// Sec. 4.2: a 20s square window, oriented, split into 4 x 4 subregions of 5 x 5 samples; Haar
// responses of side 2s, turned into the window's frame and weighted by a Gaussian
// (sigma = 3.3s), summed per subregion as (sum du, sum |du|, sum dv, sum |dv|) (the extended
// descriptor splits the sums of du by the sign of dv and those of dv by the sign of du), then
// normalized to unit length. Sets each keypoint's angle in degrees ([0, 360), 0 when upright).
cv::Mat DescribeSurf(const IntegralImage& image, std::vector<cv::KeyPoint>& keypoints,
                     const SurfDescriptorOptions& options);

}  // namespace memloop
