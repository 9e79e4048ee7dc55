#include "detector/loop_geometry.h"

#include <gtest/gtest.h>

#include <cmath>
#include <opencv2/calib3d.hpp>
#include <random>

#include "detector/word_correspondences.h"
#include "memloop/errors.h"
#include "memloop/map_export.h"

namespace memloop {
namespace {

// Two signatures of the same 3-D points seen by two cameras: the match camera at the origin,
// the query camera where x_match = R x_query + t. Word i is point i in both.
struct TwoViews {
  Signature query, match;
};

TwoViews Project(const cv::Matx33d& r, const cv::Vec3d& t, const CameraIntrinsics& k, int points) {
  std::mt19937 random(3);
  std::uniform_real_distribution<double> lateral(-3, 3), depth(6, 12);
  TwoViews views;
  for (int i = 0; i < points; ++i) {
    const cv::Vec3d in_match(lateral(random), lateral(random), depth(random));
    const cv::Vec3d in_query = r.t() * (in_match - t);  // x_match = R x_query + t
    const auto pixel = [&](const cv::Vec3d& x) {
      return cv::KeyPoint(static_cast<float>(k.fx * x[0] / x[2] + k.cx),
                          static_cast<float>(k.fy * x[1] / x[2] + k.cy), 10);
    };
    views.match.words.push_back(i + 1);
    views.match.keypoints.push_back(pixel(in_match));
    views.query.words.push_back(i + 1);
    views.query.keypoints.push_back(pixel(in_query));
  }
  return views;
}

TEST(LoopGeometryTest, RecoversTheRelativePoseOfTwoKnownCameras) {
  const CameraIntrinsics k{500, 500, 320, 240};
  // 10 degrees about y, then 1 m along x (and a little forward): the direction (0.98, 0, 0.196).
  cv::Matx33d r;
  cv::Rodrigues(cv::Vec3d(0, 10 * CV_PI / 180, 0), r);
  const cv::Vec3d t(1, 0, 0.2);
  TwoViews views = Project(r, t, k, 60);
  // Two wrong pairings: RANSAC leaves them out.
  std::swap(views.query.keypoints[0], views.query.keypoints[1]);
  VerificationOptions verification;
  verification.ransac_pixels = 1;
  const LoopGeometry geometry = EstimateLoopGeometry(views.query, views.match, k, verification);
  EXPECT_EQ(geometry.correspondences, 60);
  EXPECT_GE(geometry.inliers.size(), 56u);
  EXPECT_LE(geometry.inliers.size(), 58u);
  ASSERT_TRUE(geometry.has_pose);
  EXPECT_TRUE(geometry.translation_known);  // 1 m at 6-12 m: parallax a rotation cannot explain
  for (int i = 0; i < 9; ++i) EXPECT_NEAR(geometry.rotation[i], r(i / 3, i % 3), 1e-3) << i;
  const double norm = std::sqrt(1 + 0.04);
  EXPECT_NEAR(geometry.translation[0], 1 / norm, 1e-3);
  EXPECT_NEAR(geometry.translation[1], 0, 1e-3);
  EXPECT_NEAR(geometry.translation[2], 0.2 / norm, 1e-3);
  // 10 degrees about y: q = (0, sin 5 deg, 0, cos 5 deg).
  EXPECT_NEAR(geometry.quaternion[0], 0, 1e-4);
  EXPECT_NEAR(geometry.quaternion[1], std::sin(5 * CV_PI / 180), 1e-4);
  EXPECT_NEAR(geometry.quaternion[2], 0, 1e-4);
  EXPECT_NEAR(geometry.quaternion[3], std::cos(5 * CV_PI / 180), 1e-4);

  // The same views give the same answer (RANSAC seeded).
  const LoopGeometry again = EstimateLoopGeometry(views.query, views.match, k, verification);
  EXPECT_EQ(again.inliers.size(), geometry.inliers.size());
  EXPECT_EQ(again.rotation, geometry.rotation);

  // Without intrinsics: the inliers, no pose.
  const LoopGeometry unposed = EstimateLoopGeometry(views.query, views.match, {}, verification);
  EXPECT_EQ(unposed.inliers.size(), geometry.inliers.size());
  EXPECT_FALSE(unposed.has_pose);
}

TEST(LoopGeometryTest, ACameraTurnedWhereItStandsGivesItsRotationAndNoDirection) {
  const CameraIntrinsics k{500, 500, 320, 240};
  cv::Matx33d r;
  cv::Rodrigues(cv::Vec3d(3 * CV_PI / 180, -4 * CV_PI / 180, 8 * CV_PI / 180), r);
  const TwoViews views = Project(r, cv::Vec3d(0, 0, 0), k, 60);  // no baseline
  VerificationOptions verification;
  verification.ransac_pixels = 1;
  const LoopGeometry geometry = EstimateLoopGeometry(views.query, views.match, k, verification);
  ASSERT_TRUE(geometry.has_pose);
  EXPECT_FALSE(geometry.translation_known);
  EXPECT_EQ(geometry.translation, (std::array<double, 3>{0, 0, 0}));
  EXPECT_GE(geometry.pose_inliers, 58);
  for (int i = 0; i < 9; ++i) EXPECT_NEAR(geometry.rotation[i], r(i / 3, i % 3), 1e-3) << i;
}

// The query view's keypoints with their 3-D points (an RGB-D image) and the match's pixels.
WordCorrespondences WithDepth(const cv::Matx33d& r, const cv::Vec3d& t, const CameraIntrinsics& k,
                              int points, int without_depth) {
  std::mt19937 random(5);
  std::uniform_real_distribution<double> lateral(-1.5, 1.5), depth(1.5, 4);
  WordCorrespondences matched;
  for (int i = 0; i < points; ++i) {
    const cv::Vec3d in_match(lateral(random), lateral(random), depth(random));
    const cv::Vec3d in_query = r.t() * (in_match - t);
    const auto pixel = [&](const cv::Vec3d& x) {
      return cv::Point2f(static_cast<float>(k.fx * x[0] / x[2] + k.cx),
                         static_cast<float>(k.fy * x[1] / x[2] + k.cy));
    };
    matched.in_a.push_back(pixel(in_query));
    matched.in_b.push_back(pixel(in_match));
    matched.points_a.emplace_back(in_query);
    if (i < without_depth) matched.points_a.back() = {0, 0, 0};  // a hole in the depth map
  }
  return matched;
}

TEST(LoopGeometryTest, WithDepthTheTranslationIsInMetres) {
  const CameraIntrinsics k{525, 525, 319.5, 239.5};
  cv::Matx33d r;
  cv::Rodrigues(cv::Vec3d(0.05, -0.2, 0.1), r);
  const cv::Vec3d t(0.12, -0.03, 0.25);  // metres
  WordCorrespondences matched = WithDepth(r, t, k, 80, 10);
  // Three wrong pairings: PnP's RANSAC leaves them out.
  std::swap(matched.in_b[20], matched.in_b[21]);
  std::swap(matched.in_b[30], matched.in_b[31]);
  matched.in_b[40].x += 40;
  VerificationOptions verification;
  verification.ransac_pixels = 1;
  const LoopGeometry geometry = EstimateLoopGeometry(matched, k, verification);
  ASSERT_TRUE(geometry.has_pose);
  EXPECT_TRUE(geometry.translation_metric);
  EXPECT_TRUE(geometry.translation_known);
  // 70 points with depth, 5 of them misplaced: 65 fit.
  EXPECT_EQ(geometry.pose_inliers, 65);
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(geometry.translation[i], t[i], 1e-4) << i;
  for (int i = 0; i < 9; ++i) EXPECT_NEAR(geometry.rotation[i], r(i / 3, i % 3), 1e-4) << i;

  // Depth at too few keypoints (11 of 12 needed): the epipolar pose, a direction of length 1.
  const WordCorrespondences sparse = WithDepth(r, t, k, 80, 69);
  const LoopGeometry direction = EstimateLoopGeometry(sparse, k, verification);
  ASSERT_TRUE(direction.has_pose);
  EXPECT_FALSE(direction.translation_metric);
  const double norm = cv::norm(t);
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(direction.translation[i], t[i] / norm, 1e-2) << i;
}

TEST(LoopGeometryTest, FewerThanEightSharedWordsGiveNoGeometry) {
  cv::Matx33d r = cv::Matx33d::eye();
  const TwoViews views = Project(r, cv::Vec3d(1, 0, 0), {500, 500, 320, 240}, 7);
  const LoopGeometry geometry =
      EstimateLoopGeometry(views.query, views.match, {500, 500, 320, 240}, {});
  EXPECT_EQ(geometry.correspondences, 7);
  EXPECT_TRUE(geometry.inliers.empty());
  EXPECT_FALSE(geometry.has_pose);
}

TEST(LoopGeometryTest, IntrinsicsAndFormatsAreParsedOrRefused) {
  const CameraIntrinsics k = ParseIntrinsics("517.3,516.5,318.6,255.3");
  EXPECT_DOUBLE_EQ(k.fx, 517.3);
  EXPECT_DOUBLE_EQ(k.cy, 255.3);
  for (const char* bad : {"517,516,318", "517,516,318,255,1", "a,b,c,d", "0,516,318,255", ""}) {
    EXPECT_THROW(ParseIntrinsics(bad), ParameterError) << bad;
  }
  EXPECT_EQ(ParseExportFormat("g2o"), ExportFormat::kG2o);
  EXPECT_THROW(ParseExportFormat("csv"), ParameterError);
}

}  // namespace
}  // namespace memloop
