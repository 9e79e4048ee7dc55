// What the generated sequences (synthetic_route.h, place_sequence.h) are drawn with: textured
// worlds, and a camera's view of them with a small change of viewpoint and exposure.
#pragma once

#include <functional>
#include <opencv2/core.hpp>
#include <string>
#include <utility>
#include <vector>

#include "memloop/generated_layout.h"

namespace memloop {

// A gray texture of random shapes of random gray levels over smooth noise: corners and blobs
// everywhere, and no two places alike. With `facades`, the shapes lie over a street front:
// blocks 40-140 pixels wide, each of its own gray and height under a skyline, the structure at a
// scale of the image that a change of light leaves (the day-night route).
cv::Mat MakeTexture(int width, int height, cv::RNG& rng, bool facades = false);

// A frame's deviation from its nominal view.
struct ViewJitter {
  double dx = 0, dy = 0, scale = 1, angle_degrees = 0, gain = 1, bias = 0;
  static ViewJitter Random(cv::RNG& rng);  // the ranges every generated frame draws from
};

// The view of `world` whose top-left corner is at (x, y) (before jitter), `width` x `height`,
// 8-bit BGR, with sensor noise seeded by `noise_seed`.
cv::Mat RenderView(const cv::Mat& world, double x, double y, const ViewJitter& jitter, int width,
                   int height, uint64_t noise_seed);

// The time stamp of generated frame `index`, in seconds: 10 Hz from 1000 s.
double GeneratedStamp(int index);

// The name a run gives generated frame `index` in `layout` ("12.png" in an image folder).
std::string FrameName(GeneratedLayout layout, int index);

// Writes frame i from `render(i)` into `folder` in `layout` (generated_layout.h), and
// `folder`/ground_truth_pairs.csv ("query,match" by the names a run gives the frames). Throws
// InputError naming the file that cannot be written. `written(n)` after each image, if given.
void WriteSequence(const std::string& folder, int size, const std::function<cv::Mat(int)>& render,
                   const std::vector<std::pair<int, int>>& pairs,
                   const std::function<void(int)>& written = {},
                   GeneratedLayout layout = GeneratedLayout::kImages);

}  // namespace memloop
