#include "input/depth_map.h"

#include <opencv2/imgcodecs.hpp>

namespace memloop {

cv::Mat ReadDepth(const std::string& path, double units_per_metre, std::string* error) {
  cv::Mat depth;
  try {
    depth = cv::imread(path, cv::IMREAD_UNCHANGED);
  } catch (const cv::Exception& exception) {
    *error = "depth map " + path + ": " + exception.what();
    return {};
  }
  if (depth.empty()) {
    *error = "depth map " + path + ": not a readable image";
    return {};
  }
  cv::Mat metres;
  if (depth.type() == CV_16UC1) {
    depth.convertTo(metres, CV_32F, 1.0 / units_per_metre);
  } else if (depth.type() == CV_32FC1) {
    metres = depth;
    cv::patchNaNs(metres, 0);
  } else {
    *error = "depth map " + path + ": not one channel of 16-bit unsigned or 32-bit float";
  }
  return metres;
}

void CheckDepthMatchesImage(const std::string& source, Frame* frame) {
  if (frame->depth.empty() || frame->image.empty() || frame->depth.size() == frame->image.size()) {
    return;
  }
  frame->error = "depth map " + source + " is " + std::to_string(frame->depth.cols) + "x" +
                 std::to_string(frame->depth.rows) + ", its image " +
                 std::to_string(frame->image.cols) + "x" + std::to_string(frame->image.rows) +
                 " (a depth map registered to the image has its size)";
  frame->image.release();
  frame->depth.release();
}

}  // namespace memloop
