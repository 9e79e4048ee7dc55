#include "detector/loop_geometry.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <opencv2/calib3d.hpp>
#include <sstream>

#include "memloop/errors.h"

namespace memloop {
namespace {

cv::Vec3d Bearing(const cv::Point2f& pixel, const CameraIntrinsics& k) {
  const cv::Vec3d ray((pixel.x - k.cx) / k.fx, (pixel.y - k.cy) / k.fy, 1);
  return ray / cv::norm(ray);
}

// The rotation that best takes `from` onto `to` (Kabsch, by SVD), with det = +1.
cv::Matx33d Kabsch(const std::vector<cv::Vec3d>& from, const std::vector<cv::Vec3d>& to) {
  cv::Matx33d covariance = cv::Matx33d::zeros();
  for (size_t i = 0; i < from.size(); ++i) covariance += to[i] * from[i].t();
  cv::Mat w, u, vt;
  cv::SVD::compute(cv::Mat(covariance), w, u, vt);
  cv::Matx33d r = cv::Matx33d(cv::Mat(u * vt));
  if (cv::determinant(r) < 0) {
    cv::Mat flip = cv::Mat::eye(3, 3, CV_64F);
    flip.at<double>(2, 2) = -1;
    r = cv::Matx33d(cv::Mat(u * flip * vt));
  }
  return r;
}

// A rotation alone, b_match = R b_query for the bearing vectors: RANSAC over pairs (seeded),
// then a fit to every inlier. What a small baseline (a camera turned where it stands) leaves
// the essential matrix unable to say.
struct RotationOnly {
  cv::Matx33d rotation = cv::Matx33d::eye();
  int inliers = 0;
};
RotationOnly EstimateRotationOnly(const std::vector<cv::Point2f>& query,
                                  const std::vector<cv::Point2f>& match, const CameraIntrinsics& k,
                                  double ransac_pixels) {
  std::vector<cv::Vec3d> from, to;
  for (size_t i = 0; i < query.size(); ++i) {
    from.push_back(Bearing(query[i], k));
    to.push_back(Bearing(match[i], k));
  }
  const double max_angle = ransac_pixels / (0.5 * (k.fx + k.fy));
  const auto inliers_of = [&](const cv::Matx33d& r, std::vector<int>* which) {
    int count = 0;
    for (size_t i = 0; i < from.size(); ++i) {
      const double angle = std::acos(std::min(1.0, (r * from[i]).dot(to[i])));
      if (angle > max_angle) continue;
      ++count;
      if (which) which->push_back(static_cast<int>(i));
    }
    return count;
  };
  RotationOnly best;
  cv::RNG random(0);
  const int n = static_cast<int>(from.size());
  for (int iteration = 0; iteration < 200 && n >= 2; ++iteration) {
    const int a = random.uniform(0, n);
    const int b = random.uniform(0, n);
    if (a == b) continue;
    const cv::Matx33d r = Kabsch({from[a], from[b]}, {to[a], to[b]});
    const int count = inliers_of(r, nullptr);
    if (count > best.inliers) best = {r, count};
  }
  std::vector<int> which;
  inliers_of(best.rotation, &which);
  if (which.size() >= 2) {
    std::vector<cv::Vec3d> fit_from, fit_to;
    for (int i : which) fit_from.push_back(from[i]), fit_to.push_back(to[i]);
    const cv::Matx33d refined = Kabsch(fit_from, fit_to);
    const int count = inliers_of(refined, nullptr);
    if (count >= best.inliers) best = {refined, count};
  }
  return best;
}

// `t` is normalized unless `metric`.
void SetPose(const cv::Matx33d& r, const cv::Vec3d* t, int inliers, LoopGeometry& geometry,
             bool metric = false) {
  geometry.has_pose = true;
  geometry.pose_inliers = inliers;
  for (int i = 0; i < 9; ++i) geometry.rotation[i] = r(i / 3, i % 3);
  geometry.quaternion = QuaternionOf(r);
  geometry.translation_known = t != nullptr;
  geometry.translation_metric = metric;
  const double norm = t ? (metric ? 1.0 : cv::norm(*t)) : 0;
  for (int i = 0; i < 3; ++i) geometry.translation[i] = norm > 0 ? (*t)[i] / norm : 0;
}

// With the query view's depth: x_match = R X_query + t from the query's 3-D points and the
// match's pixels (PnP in RANSAC, then Levenberg-Marquardt on the inliers), in metres. False when
// fewer than kMinimum correspondences have depth or fit: the caller falls back to the epipolar
// pose.
bool EstimateMetricPose(const WordCorrespondences& matched, const CameraIntrinsics& k,
                        double ransac_pixels, LoopGeometry& geometry) {
  constexpr int kMinimum = 12;
  std::vector<cv::Point3f> points;
  std::vector<cv::Point2f> pixels;
  for (size_t i = 0; i < matched.points_a.size(); ++i) {
    if (matched.points_a[i].z <= 0) continue;
    points.push_back(matched.points_a[i]);
    pixels.push_back(matched.in_b[i]);
  }
  if (static_cast<int>(points.size()) < kMinimum) return false;
  const cv::Matx33d camera(k.fx, 0, k.cx, 0, k.fy, k.cy, 0, 0, 1);
  cv::Mat rvec, tvec;
  std::vector<int> inliers;
  if (!cv::solvePnPRansac(points, pixels, camera, cv::noArray(), rvec, tvec, false, 500,
                          static_cast<float>(ransac_pixels), 0.999, inliers, cv::SOLVEPNP_EPNP) ||
      static_cast<int>(inliers.size()) < kMinimum) {
    return false;
  }
  std::vector<cv::Point3f> fit_points;
  std::vector<cv::Point2f> fit_pixels;
  for (int i : inliers) fit_points.push_back(points[i]), fit_pixels.push_back(pixels[i]);
  cv::solvePnPRefineLM(fit_points, fit_pixels, camera, cv::noArray(), rvec, tvec);
  cv::Mat rotation;
  cv::Rodrigues(rvec, rotation);
  const cv::Vec3d t(tvec);
  SetPose(cv::Matx33d(rotation), &t, static_cast<int>(inliers.size()), geometry, true);
  return true;
}

// The pose between the two views from the inliers, through the essential matrix (recoverPose
// gives x_match = R x_query + t for points1 = query), unless a rotation alone explains the
// matches as well (kRotationShare of the essential matrix's inliers, or more): then the baseline
// is too short for a translation, and the essential matrix's rotation is noise-driven (on
// tum_fr1_rpy, baselines of 1-6 cm: median error 9 degrees with it, docs/export.md).
void EstimatePose(const std::vector<cv::Point2f>& query, const std::vector<cv::Point2f>& match,
                  const CameraIntrinsics& k, double ransac_pixels, LoopGeometry& geometry) {
  constexpr double kRotationShare = 0.9;
  if (query.size() < 5) return;  // the five-point algorithm's minimum
  const RotationOnly rotation_only = EstimateRotationOnly(query, match, k, ransac_pixels);
  const cv::Matx33d camera(k.fx, 0, k.cx, 0, k.fy, k.cy, 0, 0, 1);
  cv::Mat mask;
  const cv::Mat essential =
      cv::findEssentialMat(query, match, camera, cv::RANSAC, 0.999, ransac_pixels, mask);
  int inliers = 0;
  cv::Mat rotation, translation;
  if (essential.rows == 3 && essential.cols == 3) {  // else none, or several solutions
    inliers = cv::recoverPose(essential, query, match, camera, rotation, translation, mask);
  }
  if (rotation_only.inliers >= 5 && rotation_only.inliers >= kRotationShare * inliers) {
    SetPose(rotation_only.rotation, nullptr, rotation_only.inliers, geometry);
    return;
  }
  if (inliers < 5) return;
  const cv::Vec3d t(translation);
  SetPose(cv::Matx33d(rotation), &t, inliers, geometry);
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
  return EstimateLoopGeometry(UniqueWordCorrespondences(query, match), intrinsics, verification);
}

LoopGeometry DescribeLoopClosure(const DescribedView& image, ImageIndex image_index,
                                 const Location& match, const Dictionary& dictionary,
                                 const CameraIntrinsics& intrinsics,
                                 const VerificationOptions& options) {
  LoopGeometry geometry;
  if (!intrinsics.known()) {
    geometry.pose_problem = "the camera's intrinsics are not set (camera.fx..cy)";
  } else {
    geometry = EstimateLoopGeometry(
        MatchDescriptors(image, WordDescribedView(match.signature, dictionary)), intrinsics,
        options);
  }
  geometry.query_view = image_index;
  geometry.match_view = ViewOf(match);
  return geometry;
}

LoopGeometry EstimateLoopGeometry(const WordCorrespondences& matched,
                                  const CameraIntrinsics& intrinsics,
                                  const VerificationOptions& verification) {
  LoopGeometry geometry;
  geometry.correspondences = matched.size();
  if (matched.size() < 8) {  // the eight-point algorithm's minimum
    geometry.pose_problem = std::to_string(matched.size()) +
                            " correspondences between the views (the epipolar fit needs 8)";
    return geometry;
  }
  std::vector<unsigned char> mask;
  cv::setRNGSeed(0);  // RANSAC's samples repeat: the same map exports the same file
  const cv::Mat fundamental =
      cv::findFundamentalMat(matched.in_a, matched.in_b, cv::FM_RANSAC, verification.ransac_pixels,
                             verification.ransac_confidence, mask);
  if (fundamental.empty()) {
    geometry.pose_problem =
        "no epipolar geometry fits the " + std::to_string(matched.size()) + " correspondences";
    return geometry;
  }
  std::vector<cv::Point2f> in_query, in_match;
  for (int i = 0; i < matched.size(); ++i) {
    if (!mask[i]) continue;
    const cv::Point2f& q = matched.in_a[i];
    const cv::Point2f& m = matched.in_b[i];
    geometry.inliers.push_back({q.x, q.y, m.x, m.y});
    in_query.push_back(q);
    in_match.push_back(m);
  }
  if (!intrinsics.known()) {
    geometry.pose_problem = "the camera's intrinsics are unknown (camera.fx..cy)";
    return geometry;
  }
  cv::setRNGSeed(0);
  if (EstimateMetricPose(matched, intrinsics, verification.ransac_pixels, geometry)) {
    return geometry;
  }
  EstimatePose(in_query, in_match, intrinsics, verification.ransac_pixels, geometry);
  if (!geometry.has_pose) {
    geometry.pose_problem = "no pose fits the " + std::to_string(in_query.size()) +
                            " epipolar inliers (the five-point algorithm needs 5 in front of "
                            "both cameras)";
  }
  return geometry;
}

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

cv::Matx33d RotationOf(const std::array<double, 4>& quaternion) {
  const auto [x, y, z, w] = quaternion;
  const double norm = std::sqrt(x * x + y * y + z * z + w * w);
  const double a = x / norm, b = y / norm, c = z / norm, d = w / norm;
  return {1 - 2 * (b * b + c * c), 2 * (a * b - c * d),     2 * (a * c + b * d),
          2 * (a * b + c * d),     1 - 2 * (a * a + c * c), 2 * (b * c - a * d),
          2 * (a * c - b * d),     2 * (b * c + a * d),     1 - 2 * (a * a + b * b)};
}

LoopClosurePose KeptPose(const LoopGeometry& geometry, bool intrinsics_known) {
  LoopClosurePose pose;
  if (!intrinsics_known) {
    pose.reason = "the camera's intrinsics were not set (camera.fx..cy)";
    return pose;
  }
  pose.estimated = true;
  pose.inliers = static_cast<int>(geometry.inliers.size());
  pose.has_pose = geometry.has_pose;
  pose.metric = geometry.translation_metric;
  if (geometry.has_pose) {
    pose.translation = geometry.translation;
    pose.quaternion = geometry.quaternion;
  }
  pose.reason = geometry.pose_problem;
  return pose;
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
