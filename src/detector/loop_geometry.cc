#include "detector/loop_geometry.h"

#include <cmath>
#include <cstdlib>
#include <opencv2/calib3d.hpp>
#include <sstream>

#include "detector/word_correspondences.h"
#include "memloop/errors.h"

namespace memloop {
namespace {

std::array<double, 4> QuaternionOf(const cv::Matx33d& r) {
  // Shepperd's method: the largest of the four candidates divides.
  const double trace = r(0, 0) + r(1, 1) + r(2, 2);
  std::array<double, 4> q{};  // x, y, z, w
  if (trace > 0) {
    const double s = 2 * std::sqrt(1 + trace);
    q = {(r(2, 1) - r(1, 2)) / s, (r(0, 2) - r(2, 0)) / s, (r(1, 0) - r(0, 1)) / s, s / 4};
  } else if (r(0, 0) > r(1, 1) && r(0, 0) > r(2, 2)) {
    const double s = 2 * std::sqrt(1 + r(0, 0) - r(1, 1) - r(2, 2));
    q = {s / 4, (r(0, 1) + r(1, 0)) / s, (r(0, 2) + r(2, 0)) / s, (r(2, 1) - r(1, 2)) / s};
  } else if (r(1, 1) > r(2, 2)) {
    const double s = 2 * std::sqrt(1 + r(1, 1) - r(0, 0) - r(2, 2));
    q = {(r(0, 1) + r(1, 0)) / s, s / 4, (r(1, 2) + r(2, 1)) / s, (r(0, 2) - r(2, 0)) / s};
  } else {
    const double s = 2 * std::sqrt(1 + r(2, 2) - r(0, 0) - r(1, 1));
    q = {(r(0, 2) + r(2, 0)) / s, (r(1, 2) + r(2, 1)) / s, s / 4, (r(1, 0) - r(0, 1)) / s};
  }
  if (q[3] < 0) {
    for (double& value : q) value = -value;
  }
  return q;
}

// The pose between the two views from the inliers, through the essential matrix. recoverPose
// gives x_match = R x_query + t for points1 = query.
void EstimatePose(const std::vector<cv::Point2f>& query, const std::vector<cv::Point2f>& match,
                  const CameraIntrinsics& k, double ransac_pixels, LoopGeometry& geometry) {
  if (query.size() < 5) return;  // the five-point algorithm's minimum
  const cv::Matx33d camera(k.fx, 0, k.cx, 0, k.fy, k.cy, 0, 0, 1);
  cv::Mat mask;
  const cv::Mat essential =
      cv::findEssentialMat(query, match, camera, cv::RANSAC, 0.999, ransac_pixels, mask);
  if (essential.rows != 3 || essential.cols != 3) return;  // none, or several solutions
  cv::Mat rotation, translation;
  const int inliers = cv::recoverPose(essential, query, match, camera, rotation, translation, mask);
  if (inliers < 5) return;
  const cv::Matx33d r(rotation);
  const cv::Vec3d t(translation);
  geometry.has_pose = true;
  geometry.pose_inliers = inliers;
  for (int i = 0; i < 9; ++i) geometry.rotation[i] = r(i / 3, i % 3);
  geometry.quaternion = QuaternionOf(r);
  const double norm = cv::norm(t);
  for (int i = 0; i < 3; ++i) geometry.translation[i] = norm > 0 ? t[i] / norm : 0;
}

double ParseNumber(const std::string& text, const std::string& option, const std::string& whole) {
  char* end = nullptr;
  const double value = std::strtod(text.c_str(), &end);
  if (text.empty() || *end != '\0' || !std::isfinite(value)) {
    throw ParameterError(option, option + ": '" + whole + "' is not four numbers fx,fy,cx,cy");
  }
  return value;
}

}  // namespace

LoopGeometry EstimateLoopGeometry(const Signature& query, const Signature& match,
                                  const CameraIntrinsics& intrinsics,
                                  const VerificationOptions& verification) {
  LoopGeometry geometry;
  const WordCorrespondences matched = UniqueWordCorrespondences(query, match);
  geometry.correspondences = matched.size();
  if (matched.size() < 8) return geometry;  // the eight-point algorithm's minimum
  std::vector<unsigned char> mask;
  cv::setRNGSeed(0);  // RANSAC's samples repeat: the same map exports the same file
  const cv::Mat fundamental =
      cv::findFundamentalMat(matched.in_a, matched.in_b, cv::FM_RANSAC, verification.ransac_pixels,
                             verification.ransac_confidence, mask);
  if (fundamental.empty()) return geometry;
  std::vector<cv::Point2f> in_query, in_match;
  for (int i = 0; i < matched.size(); ++i) {
    if (!mask[i]) continue;
    const cv::Point2f& q = matched.in_a[i];
    const cv::Point2f& m = matched.in_b[i];
    geometry.inliers.push_back({q.x, q.y, m.x, m.y});
    in_query.push_back(q);
    in_match.push_back(m);
  }
  if (intrinsics.known()) {
    cv::setRNGSeed(0);
    EstimatePose(in_query, in_match, intrinsics, verification.ransac_pixels, geometry);
  }
  return geometry;
}

CameraIntrinsics ParseIntrinsics(const std::string& text) {
  std::vector<double> values;
  std::stringstream fields(text);
  for (std::string field; std::getline(fields, field, ',');) {
    values.push_back(ParseNumber(field, "--intrinsics", text));
  }
  if (values.size() != 4) {
    throw ParameterError("--intrinsics",
                         "--intrinsics: '" + text + "' is not four numbers fx,fy,cx,cy");
  }
  CameraIntrinsics intrinsics{values[0], values[1], values[2], values[3]};
  if (!intrinsics.known()) {
    throw ParameterError("--intrinsics",
                         "--intrinsics: the focal lengths fx and fy must be over 0");
  }
  return intrinsics;
}

}  // namespace memloop
