// Frames cut from one panorama, for tests whose ground truth is exact: two images show the same
// place as far as their crops overlap.
#pragma once

#include <algorithm>
#include <opencv2/core.hpp>
#include <vector>

#include "memloop/result.h"
#include "route_frames_run.h"

namespace memloop::testing {

// The share of `a`'s area that `b` covers.
inline double Overlap(const cv::Rect& a, const cv::Rect& b) {
  return static_cast<double>((a & b).area()) / a.area();
}

// Runs the detector over the crops of `panorama`, in order (T_time off).
inline FramesRun RunCrops(const Options& options, const cv::Mat& panorama,
                          const std::vector<cv::Rect>& crops) {
  return RunFrames(options, static_cast<int>(crops.size()),
                   [&](int index) { return cv::Mat(panorama(crops[index])).clone(); });
}

// How much of a loop closure's image the best of its matched images' crops covers: at least a
// quarter is a true loop closure in these tests, 0 a false one.
inline double BestOverlap(const std::vector<cv::Rect>& crops, const Result& loop_closure) {
  const cv::Rect& image = crops[static_cast<size_t>(loop_closure.image_index)];
  double best = 0;
  for (ImageIndex match : loop_closure.loop_closure_images) {
    best = std::max(best, Overlap(image, crops[static_cast<size_t>(match)]));
  }
  return best;
}

}  // namespace memloop::testing
