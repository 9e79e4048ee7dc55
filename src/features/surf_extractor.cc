#include "features/surf_extractor.h"

#include <algorithm>
#include <cmath>

#include "features/camera_roll.h"

namespace memloop {

SurfExtractor::SurfExtractor(const FeatureOptions& options) : max_features_(options.max_features) {
  detector_.hessian_threshold = options.surf_hessian_threshold;
  detector_.octaves = options.surf_octaves;
  detector_.intervals = options.surf_intervals;
  detector_.sample_step = options.surf_sample_step;
  descriptor_.upright = options.surf_upright != 0;
  descriptor_.extended = options.surf_extended != 0;
  max_roll_radians_ = options.surf_max_roll_degrees * M_PI / 180;
  min_roll_strength_ = options.surf_min_roll_strength;
  min_roll_radians_ = options.surf_min_roll_degrees * M_PI / 180;
  rolled_view_radians_ = options.surf_rolled_view_degrees * M_PI / 180;
}

Features SurfExtractor::Extract(const cv::Mat& gray) const {
  const IntegralImage image(gray);
  Features features;
  features.keypoints = DetectFastHessian(image, detector_);
  // The strongest first (then by position, so the order is total); describe only those kept.
  std::sort(features.keypoints.begin(), features.keypoints.end(),
            [](const cv::KeyPoint& a, const cv::KeyPoint& b) {
              if (a.response != b.response) return a.response > b.response;
              if (a.pt.y != b.pt.y) return a.pt.y < b.pt.y;
              if (a.pt.x != b.pt.x) return a.pt.x < b.pt.x;
              return a.size < b.size;
            });
  if (max_features_ > 0 && static_cast<int>(features.keypoints.size()) > max_features_) {
    features.keypoints.resize(max_features_);
  }
  SurfDescriptorOptions descriptor = descriptor_;
  const bool compensate = descriptor.upright && max_roll_radians_ > 0;
  const bool second_view = descriptor.upright && rolled_view_radians_ > 0;
  CameraRoll roll;
  if (compensate || second_view) roll = EstimateCameraRoll(gray);
  const bool roll_known = roll.strength >= min_roll_strength_ &&
                          std::fabs(roll.radians) >= min_roll_radians_ && roll.radians != 0;
  const bool compensated = compensate && roll_known && std::fabs(roll.radians) <= max_roll_radians_;
  if (compensated) descriptor.upright_angle = roll.radians;
  features.descriptors = DescribeSurf(image, features.keypoints, descriptor);
  if (second_view && roll_known && !compensated &&
      std::fabs(roll.radians) <= rolled_view_radians_) {
    SurfDescriptorOptions rolled = descriptor;
    rolled.upright_angle = roll.radians;
    std::vector<cv::KeyPoint> keypoints = features.keypoints;  // their angles stay upright's
    features.rolled_descriptors = DescribeSurf(image, keypoints, rolled);
  }
  return features;
}

}  // namespace memloop
