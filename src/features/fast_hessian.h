// The Fast-Hessian detector of SURF (Bay et al., "Speeded-Up Robust Features", CVIU 2008,
// Sec. 3): the determinant of the Hessian approximated with box filters on an integral image,
// over octaves and intervals of filter sizes, 3x3x3 non-maximum suppression and sub-pixel /
// sub-scale interpolation of the maxima (Brown & Lowe 2002).
#pragma once

#include <opencv2/core.hpp>
#include <vector>

#include "features/integral_image.h"

namespace memloop {

struct FastHessianOptions {
  double hessian_threshold = 400;  // on det(H) of intensities (0-255), as OpenCV's SURF
  int octaves = 4;
  int intervals = 4;    // filter sizes per octave; maxima are searched in the inner ones
  int sample_step = 2;  // sampling step of the first octave, doubled at each octave
};

// Filter side L of octave o, interval i (0-based): 3 * (2^(o+1) * (i+1) + 1), i.e. 9, 15, 21,
// 27 for the first octave, 15, 27, 39, 51 for the second (SURF Sec. 3.3).
int FilterSize(int octave, int interval);

// Keypoints with pt (pixels), size = interpolated filter side L (scale s = 1.2 L / 9),
// response = det(H), octave, class_id = sign of the Laplacian (+1 or -1), angle = -1.
// Order: as found (octave, interval, row, column).
std::vector<cv::KeyPoint> DetectFastHessian(const IntegralImage& image,
                                            const FastHessianOptions& options);

}  // namespace memloop
