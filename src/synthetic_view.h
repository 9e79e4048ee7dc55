// What the generated sequences (synthetic_route.h, place_sequence.h) are drawn with: textured
// worlds, and a camera's view of them with a small change of viewpoint and exposure.
#pragma once

#include <opencv2/core.hpp>

namespace memloop {

// A gray texture of random shapes of random gray levels over smooth noise: corners and blobs
// everywhere, and no two places alike.
cv::Mat MakeTexture(int width, int height, cv::RNG& rng);

// A frame's deviation from its nominal view.
struct ViewJitter {
  double dx = 0, dy = 0, scale = 1, angle_degrees = 0, gain = 1, bias = 0;
  static ViewJitter Random(cv::RNG& rng);  // the ranges every generated frame draws from
};

// The view of `world` whose top-left corner is at (x, y) (before jitter), `width` x `height`,
// 8-bit BGR, with sensor noise seeded by `noise_seed`.
cv::Mat RenderView(const cv::Mat& world, double x, double y, const ViewJitter& jitter, int width,
                   int height, uint64_t noise_seed);

}  // namespace memloop
