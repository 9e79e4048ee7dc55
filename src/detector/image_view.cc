#include "detector/image_view.h"

#include <cmath>
#include <limits>

#include "memloop/errors.h"

namespace memloop {
namespace {

// The reading at (x, y), else the one of its 8 neighbours nearest the camera; 0 when none.
float DepthNear(const cv::Mat& depth, int x, int y) {
  if (x < 0 || y < 0 || x >= depth.cols || y >= depth.rows) return 0;
  const float centre = depth.at<float>(y, x);
  if (centre > 0) return centre;
  float nearest = std::numeric_limits<float>::infinity();
  for (int dy = -1; dy <= 1; ++dy) {
    for (int dx = -1; dx <= 1; ++dx) {
      const int u = x + dx, v = y + dy;
      if (u < 0 || v < 0 || u >= depth.cols || v >= depth.rows) continue;
      const float reading = depth.at<float>(v, u);
      if (reading > 0 && reading < nearest) nearest = reading;
    }
  }
  return std::isfinite(nearest) ? nearest : 0;
}

}  // namespace

cv::Mat DepthInMetres(const cv::Mat& depth, const cv::Size& image_size) {
  if (depth.empty()) return {};
  if (depth.size() != image_size) {
    throw InputError("depth", "the depth map is " + std::to_string(depth.cols) + "x" +
                                  std::to_string(depth.rows) + ", the image " +
                                  std::to_string(image_size.width) + "x" +
                                  std::to_string(image_size.height) +
                                  ": give one registered to the image, of its size");
  }
  cv::Mat metres;
  if (depth.type() == CV_16UC1) {
    depth.convertTo(metres, CV_32F, 1e-3);
  } else if (depth.type() == CV_32FC1) {
    metres = depth.clone();
    cv::patchNaNs(metres, 0);
    metres.setTo(0, metres > std::numeric_limits<float>::max());  // +infinity
  } else {
    throw InputError("depth",
                     "the depth map is neither 16-bit unsigned (millimetres) nor 32-bit float "
                     "(metres), one channel");
  }
  metres.setTo(0, metres < 0);
  return metres;
}

DescribedView ImageView(Features features, const cv::Mat& depth_metres, const CameraIntrinsics& k) {
  DescribedView view;
  view.keypoints = std::move(features.keypoints);
  view.descriptors = features.descriptors;
  if (depth_metres.empty() || !k.known()) return view;
  for (const cv::KeyPoint& keypoint : view.keypoints) {
    const float z = DepthNear(depth_metres, static_cast<int>(std::lround(keypoint.pt.x)),
                              static_cast<int>(std::lround(keypoint.pt.y)));
    view.points.emplace_back(z * (keypoint.pt.x - k.cx) / k.fx, z * (keypoint.pt.y - k.cy) / k.fy,
                             z);
  }
  return view;
}

}  // namespace memloop
