// A repeatable texture for feature tests: uniform noise blurred to `blur_sigma` pixels and
// stretched to 0-255, so every detector finds keypoints at known places run after run.
#pragma once

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

namespace memloop {
namespace testing {

inline cv::Mat NoiseTexture(cv::Size size, uint64_t seed, double blur_sigma) {
  cv::Mat noise(size, CV_8U);
  cv::RNG rng(seed);
  rng.fill(noise, cv::RNG::UNIFORM, 0, 256);
  cv::GaussianBlur(noise, noise, cv::Size(0, 0), blur_sigma);
  cv::normalize(noise, noise, 0, 255, cv::NORM_MINMAX);
  return noise;
}

}  // namespace testing
}  // namespace memloop
