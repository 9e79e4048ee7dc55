#include "features/camera_roll.h"

#include <gtest/gtest.h>

#include <cmath>
#include <opencv2/imgproc.hpp>

#include "features/surf_extractor.h"
#include "memloop/synthetic_route.h"

namespace memloop {
namespace {

constexpr double kPi = 3.14159265358979323846;

// A "facade": a grid of dark lines along (cos a, sin a) and across it, in image axes (y down).
cv::Mat Facade(double degrees) {
  cv::Mat image(240, 320, CV_8U, cv::Scalar(200));
  const double a = degrees * kPi / 180;
  const cv::Point2d along(std::cos(a), std::sin(a)), across(-std::sin(a), std::cos(a));
  const cv::Point2d centre(160, 120);
  for (int k = -12; k <= 12; ++k) {
    for (const auto& [direction, offset] : {std::pair{along, across}, std::pair{across, along}}) {
      const cv::Point2d middle = centre + offset * (k * 17.0);
      cv::line(image, middle - direction * 400, middle + direction * 400, cv::Scalar(40), 3,
               cv::LINE_AA);
    }
  }
  return image;
}

TEST(CameraRollTest, FindsTheAngleOfVerticalsAndHorizontals) {
  for (double degrees : {0.0, 7.0, -12.0, 20.0}) {
    const CameraRoll roll = EstimateCameraRoll(Facade(degrees));
    EXPECT_NEAR(roll.radians * 180 / kPi, degrees, 0.5) << degrees;
    EXPECT_GT(roll.strength, 0.5) << degrees;  // every edge on one pair of axes
  }
  // A grid turned by 90 + 7 degrees is the same grid as at 7: the roll is known modulo 90.
  EXPECT_NEAR(EstimateCameraRoll(Facade(97)).radians * 180 / kPi, 7, 0.5);
}

TEST(CameraRollTest, NoPreferredOrientationHasNoStrength) {
  cv::Mat noise(240, 320, CV_8U);
  cv::RNG(3).fill(noise, cv::RNG::UNIFORM, 0, 256);
  cv::GaussianBlur(noise, noise, cv::Size(5, 5), 1.5);
  EXPECT_LT(EstimateCameraRoll(noise).strength, 0.05);
  EXPECT_EQ(EstimateCameraRoll(cv::Mat(50, 50, CV_8U, cv::Scalar(9))).strength, 0.0);
}

// U-SURF with surf.max_roll_degrees describes every keypoint at the image's roll (the angle the
// keypoints keep), when it is within the bound and strong enough; otherwise at 0.
TEST(CameraRollTest, UprightSurfDescribesInTheRolledFrame) {
  FeatureOptions options;
  options.surf_max_roll_degrees = 15;
  const Features rolled = SurfExtractor(options).Extract(Facade(-10));
  ASSERT_FALSE(rolled.keypoints.empty());
  for (const cv::KeyPoint& keypoint : rolled.keypoints) EXPECT_NEAR(keypoint.angle, 350, 0.5);
  const Features beyond = SurfExtractor(options).Extract(Facade(25));  // over 15 degrees
  ASSERT_FALSE(beyond.keypoints.empty());
  for (const cv::KeyPoint& keypoint : beyond.keypoints) EXPECT_EQ(keypoint.angle, 0);
  options.surf_min_roll_degrees = 12;  // a 10-degree roll is left to U-SURF's own tolerance
  for (const cv::KeyPoint& keypoint : SurfExtractor(options).Extract(Facade(-10)).keypoints) {
    EXPECT_EQ(keypoint.angle, 0);
  }
  options.surf_min_roll_degrees = 0;
  options.surf_min_roll_strength = 1.0;  // never that strong
  for (const cv::KeyPoint& keypoint : SurfExtractor(options).Extract(Facade(-10)).keypoints) {
    EXPECT_EQ(keypoint.angle, 0);
  }
  options.surf_max_roll_degrees = 0;  // off: U-SURF as it was
  for (const cv::KeyPoint& keypoint : SurfExtractor(options).Extract(Facade(-10)).keypoints) {
    EXPECT_EQ(keypoint.angle, 0);
  }
}

// surf.rolled_view_degrees: the keypoints and their upright descriptors as without it, and, for
// an image rolled within [surf.min_roll_degrees, the bound], the same keypoints described in the
// rolled frame, as surf.max_roll_degrees would describe them.
TEST(CameraRollTest, RolledViewIsTheCompensatedDescriptionBesideTheUprightOne) {
  FeatureOptions plain;
  plain.surf_rolled_view_degrees = 0;
  FeatureOptions second = plain;
  second.surf_rolled_view_degrees = 20;
  second.surf_min_roll_degrees = 8;
  FeatureOptions compensated = plain;
  compensated.surf_max_roll_degrees = 20;
  compensated.surf_min_roll_degrees = 8;
  const cv::Mat image = Facade(-12);
  const Features upright = SurfExtractor(plain).Extract(image);
  const Features both = SurfExtractor(second).Extract(image);
  const Features turned = SurfExtractor(compensated).Extract(image);
  ASSERT_FALSE(both.keypoints.empty());
  EXPECT_EQ(cv::norm(both.descriptors, upright.descriptors, cv::NORM_INF), 0);
  ASSERT_EQ(both.rolled_descriptors.rows, both.keypoints.size());
  EXPECT_EQ(cv::norm(both.rolled_descriptors, turned.descriptors, cv::NORM_INF), 0);
  for (const cv::KeyPoint& keypoint : both.keypoints) EXPECT_EQ(keypoint.angle, 0);
  // Under the minimum (U-SURF tolerates it), over the bound, or compensated already: none.
  EXPECT_TRUE(SurfExtractor(second).Extract(Facade(5)).rolled_descriptors.empty());
  EXPECT_TRUE(SurfExtractor(second).Extract(Facade(30)).rolled_descriptors.empty());
  FeatureOptions with_compensation = second;
  with_compensation.surf_max_roll_degrees = 20;
  EXPECT_TRUE(SurfExtractor(with_compensation).Extract(image).rolled_descriptors.empty());
  EXPECT_TRUE(upright.rolled_descriptors.empty());
}

// The point of it: a view rolled by 12 degrees gives the same descriptors as the upright view
// once both are described in their own frames, much closer than at angle 0.
TEST(CameraRollTest, CompensationBringsARolledViewsDescriptorsBack) {
  SyntheticRouteOptions route;
  route.image_width = 320;
  route.image_height = 240;
  const cv::Mat upright = Facade(0) / 2 + SyntheticRoute(route).RenderGray(3) / 2;
  cv::Mat rolled;
  const cv::Mat turn = cv::getRotationMatrix2D(cv::Point2f(160, 120), -12, 1.0);  // y down: +12
  cv::warpAffine(upright, rolled, turn, upright.size(), cv::INTER_LINEAR, cv::BORDER_REFLECT);
  const auto nearest_distance = [](const Features& a, const Features& b) {
    // Mean distance of each keypoint of a near b's centre to b's keypoint nearest in position.
    double sum = 0;
    int count = 0;
    for (int i = 0; i < static_cast<int>(a.keypoints.size()); ++i) {
      const cv::Point2f p = a.keypoints[i].pt - cv::Point2f(160, 120);
      if (cv::norm(p) > 80) continue;
      const double c = std::cos(12 * kPi / 180), s = std::sin(12 * kPi / 180);
      const cv::Point2f q(static_cast<float>(c * p.x - s * p.y + 160),
                          static_cast<float>(s * p.x + c * p.y + 120));
      int best = -1;
      for (int j = 0; j < static_cast<int>(b.keypoints.size()); ++j) {
        if (cv::norm(b.keypoints[j].pt - q) < 1.5 &&
            (best < 0 || cv::norm(b.keypoints[j].pt - q) < cv::norm(b.keypoints[best].pt - q))) {
          best = j;
        }
      }
      if (best < 0) continue;
      sum += cv::norm(a.descriptors.row(i), b.descriptors.row(best));
      ++count;
    }
    EXPECT_GT(count, 10);
    return sum / std::max(count, 1);
  };
  FeatureOptions plain;
  FeatureOptions compensated;
  compensated.surf_max_roll_degrees = 20;
  const double at_zero =
      nearest_distance(SurfExtractor(plain).Extract(upright), SurfExtractor(plain).Extract(rolled));
  const double in_frame = nearest_distance(SurfExtractor(compensated).Extract(upright),
                                           SurfExtractor(compensated).Extract(rolled));
  EXPECT_LT(in_frame, 0.6 * at_zero) << in_frame << " vs " << at_zero;
}

}  // namespace
}  // namespace memloop
