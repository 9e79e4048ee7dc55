// The whole-image descriptor of the day-night channel (memloop, issue 34; docs/design.md,
// "Whole-image channel"): a histogram of oriented gradients (Dalal & Triggs 2005) over a
// 128x64 thumbnail of the image, as CoHOG (Zaffar et al. 2020) describes places without training.
// Gradients' orientations survive a change of light that local features do not (by night SURF
// finds streetlights and noise), and each block is normalised, so the overall brightness and
// contrast drop out. One descriptor per location, 756 bytes.
#pragma once

#include <cstdint>
#include <opencv2/core.hpp>
#include <vector>

namespace memloop {

using WholeImageDescriptor = std::vector<uint8_t>;

// 16-pixel cells, blocks of 2x2 cells every 16 pixels: 7 x 3 blocks of 4 cells of 9 orientation
// bins, each value quantized to 0..255.
constexpr int kWholeImageDescriptorSize = 7 * 3 * 4 * 9;

// The descriptor of an 8-bit grey image of any size (resized to the thumbnail, which ignores
// its aspect ratio: a camera's images all have the same). Empty for an empty image.
WholeImageDescriptor DescribeWholeImage(const cv::Mat& gray);

// Cosine similarity of two descriptors with each cell's 9 bins centred on their mean, in [-1, 1]:
// gradient energy spread over every orientation (sensor noise, what blur leaves, raised at night
// everywhere) says nothing of the place, which orientations stand out in a cell does. On the
// day-night route of tests/day_night_route_test.cc a night image's best match is its day place
// for 49 of 50 images, 24 with the plain cosine. 0 when either is empty or they differ in size
// (a location made without the channel).
double WholeImageSimilarity(const WholeImageDescriptor& a, const WholeImageDescriptor& b);

}  // namespace memloop
