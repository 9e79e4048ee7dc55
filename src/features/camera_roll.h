// The camera's roll about its optical axis, estimated from an image of a man-made scene: edges
// cluster at vertical and horizontal, so the gradient orientations, folded by 90 degrees, peak at
// the roll. Used by U-SURF (surf.max_roll_degrees) to describe every keypoint in the frame of the
// image's own vertical: a hand-held camera's views of one place, rolled by a few degrees, give the
// same words, while views rolled further than the bound stay as upright as U-SURF makes them.
#pragma once

#include <opencv2/core.hpp>

namespace memloop {

struct CameraRoll {
  double radians = 0;   // in (-pi/4, pi/4], image axes (y down), as DominantOrientation's
  double strength = 0;  // 0 (no preferred orientation) .. 1 (every edge on one axis pair)
};

// Sobel gradients of the 8-bit grey image; each pixel votes e^{4 i phi} weighted by its gradient
// magnitude: the roll is a quarter of the sum's angle and the strength the sum's length over the
// total magnitude.
CameraRoll EstimateCameraRoll(const cv::Mat& gray);

}  // namespace memloop
