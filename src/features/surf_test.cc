#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "features/fast_hessian.h"
#include "features/integral_image.h"
#include "features/matching_score.h"
#include "features/surf_extractor.h"
#include "memloop/synthetic_route.h"

namespace memloop {
namespace {

cv::Mat Texture(int width = 512, int height = 384, int frame = 5) {
  SyntheticRouteOptions options;
  options.image_width = width;
  options.image_height = height;
  return SyntheticRoute(options).RenderGray(frame);
}

TEST(IntegralImageTest, BoxSumsAgainstBruteForceAndClamped) {
  cv::Mat gray(7, 9, CV_8U);
  cv::RNG(1).fill(gray, cv::RNG::UNIFORM, 0, 256);
  const IntegralImage image(gray);
  EXPECT_EQ(image.BoxSum(1, 2, 4, 6), static_cast<int>(cv::sum(gray(cv::Rect(2, 1, 5, 4)))[0]));
  EXPECT_EQ(image.BoxSum(-3, -3, 100, 100), static_cast<int>(cv::sum(gray)[0]));
  EXPECT_EQ(image.BoxSum(5, 5, 4, 4), 0);
  // A vertical step edge: dark left, bright right -> positive HaarX, zero HaarY.
  cv::Mat edge(20, 20, CV_8U, cv::Scalar(0));
  edge.colRange(10, 20).setTo(200);
  const IntegralImage edges(edge);
  EXPECT_FLOAT_EQ(edges.HaarX(10, 10, 4), 200.0f);  // mean of the right half - of the left
  EXPECT_FLOAT_EQ(edges.HaarY(10, 10, 4), 0.0f);
}

// A bright 12 Mpx photo: the whole image sums to 3.06e9, past a signed 32-bit int. Box sums stay
// exact everywhere, the far corner included (the UBSan build aborted here with an int table).
TEST(IntegralImageTest, BoxSumsExactOnALargeBrightImage) {
  cv::Mat gray(3000, 4000, CV_8U, cv::Scalar(255));
  gray(cv::Rect(3990, 2990, 5, 10)).setTo(7);
  const IntegralImage image(gray);
  EXPECT_EQ(image.BoxSum(2990, 3990, 2999, 3999), 5 * 10 * 7 + 5 * 10 * 255);
  EXPECT_EQ(image.BoxSum(0, 0, 99, 99), 100 * 100 * 255);
  // Running sums of 2.04e9 above and 3.06e9 below: their difference crosses 2^31.
  EXPECT_EQ(image.BoxSum(2000, 0, 2999, 3999), 1000 * 4000 * 255 - 5 * 10 * 248);
  EXPECT_EQ(image.BoxSumInside(2900, 3900, 2989, 3999), 90 * 100 * 255);
  EXPECT_FLOAT_EQ(image.HaarX(2994, 3995, 4), 255.0f - 7.0f);  // left half dark, right bright
}

TEST(FastHessianTest, FilterSizesOfTheSurfPaper) {
  const int expected[4][4] = {
      {9, 15, 21, 27}, {15, 27, 39, 51}, {27, 51, 75, 99}, {51, 99, 147, 195}};
  for (int octave = 0; octave < 4; ++octave) {
    for (int interval = 0; interval < 4; ++interval) {
      EXPECT_EQ(FilterSize(octave, interval), expected[octave][interval]);
    }
  }
}

// A dark disc on a bright ground: one blob, at its centre, at the scale of the disc. For a disc of
// radius r the determinant of the Hessian peaks near sigma = r / sqrt(2), i.e. a filter side
// L = 9 sigma / 1.2.
TEST(FastHessianTest, FindsABlobAtItsPositionAndScale) {
  for (const int radius : {6, 10, 16}) {
    cv::Mat gray(200, 240, CV_8U, cv::Scalar(200));
    const cv::Point2f centre(121.0f, 97.0f);
    cv::circle(gray, centre, radius, cv::Scalar(40), cv::FILLED, cv::LINE_AA);
    cv::GaussianBlur(gray, gray, cv::Size(), 1.0);
    FastHessianOptions options;
    options.sample_step = 1;
    const auto keypoints = DetectFastHessian(IntegralImage(gray), options);
    ASSERT_FALSE(keypoints.empty()) << "radius " << radius;
    const auto strongest = *std::max_element(
        keypoints.begin(), keypoints.end(),
        [](const cv::KeyPoint& a, const cv::KeyPoint& b) { return a.response < b.response; });
    EXPECT_LT(cv::norm(strongest.pt - centre), 1.5) << "radius " << radius;
    const double expected_size = 9.0 / 1.2 * radius / std::sqrt(2.0);
    EXPECT_GT(strongest.size, expected_size / 1.5) << "radius " << radius;
    EXPECT_LT(strongest.size, expected_size * 1.5) << "radius " << radius;
    EXPECT_EQ(strongest.class_id, 1);  // dark blob: positive Laplacian
  }
}

TEST(SurfExtractorTest, DeterministicUnitDescriptorsStrongestFirst) {
  const SurfExtractor surf{FeatureOptions()};
  const cv::Mat gray = Texture();
  const Features first = surf.Extract(gray);
  const Features second = surf.Extract(gray);
  ASSERT_EQ(first.keypoints.size(), 400u);  // the cap decides
  ASSERT_EQ(first.descriptors.cols, 64);
  EXPECT_EQ(cv::norm(first.descriptors, second.descriptors, cv::NORM_INF), 0.0);
  for (size_t i = 0; i < first.keypoints.size(); ++i) {
    EXPECT_EQ(first.keypoints[i].pt, second.keypoints[i].pt);
    EXPECT_NEAR(cv::norm(first.descriptors.row(static_cast<int>(i))), 1.0, 1e-5);
    if (i > 0) {
      EXPECT_GE(first.keypoints[i - 1].response, first.keypoints[i].response);
    }
    EXPECT_GE(first.keypoints[i].angle, 0.0f);
    EXPECT_LT(first.keypoints[i].angle, 360.0f);
  }
}

TEST(SurfExtractorTest, ExtendedAndUpright) {
  FeatureOptions options;
  options.surf_extended = 1;
  options.surf_upright = 1;
  const SurfExtractor surf(options);
  EXPECT_EQ(surf.DescriptorDim(), 128);
  const Features features = surf.Extract(Texture(320, 240));
  EXPECT_EQ(features.descriptors.cols, 128);
  for (const auto& keypoint : features.keypoints) EXPECT_EQ(keypoint.angle, 0.0f);
}

// A quarter turn is exact for box filters: keypoints turn with the image, their angles by 90
// degrees, and their descriptors stay the same.
TEST(SurfExtractorTest, KeypointsRotateWithTheImage) {
  FeatureOptions options;
  options.surf_upright = 0;  // oriented SURF (the default is U-SURF)
  options.surf_sample_step = 1;
  const SurfExtractor surf(options);
  const cv::Mat gray = Texture();
  cv::Mat turned;
  cv::rotate(gray, turned, cv::ROTATE_90_CLOCKWISE);  // (x, y) -> (rows - 1 - y, x)
  const Features a = surf.Extract(gray);
  const Features b = surf.Extract(turned);
  int found = 0;
  int angle_ok = 0;
  int descriptor_ok = 0;
  for (size_t i = 0; i < a.keypoints.size(); ++i) {
    const cv::Point2f expected(gray.rows - 1 - a.keypoints[i].pt.y, a.keypoints[i].pt.x);
    for (size_t j = 0; j < b.keypoints.size(); ++j) {
      if (cv::norm(b.keypoints[j].pt - expected) > 1.5) continue;
      ++found;
      const double turn = std::fmod(b.keypoints[j].angle - a.keypoints[i].angle + 720.0, 360.0);
      angle_ok += std::fabs(turn - 90) < 15;
      descriptor_ok += cv::norm(a.descriptors.row(static_cast<int>(i)),
                                b.descriptors.row(static_cast<int>(j))) < 0.3;
      break;
    }
  }
  EXPECT_GT(found, 0.7 * a.keypoints.size());
  EXPECT_GT(angle_ok, 0.8 * found);
  EXPECT_GT(descriptor_ok, 0.8 * found);
}

// Matching under the standard transformations, on the shared images when present, generated
// textures otherwise. Floors well below what oriented SURF reaches (docs/surf.md) and far above
// what a broken detector or descriptor gives (a random descriptor scores about 0).
TEST(SurfExtractorTest, MatchingScoreFloors) {
  std::vector<cv::Mat> images;
  const std::string samples =
      std::string(MEMLOOP_SOURCE_DIR) + "/../shared/datasets/rtabmap_samples/images";
  if (std::filesystem::exists(samples)) {
    for (int n : {5, 35, 65}) {
      images.push_back(
          cv::imread(samples + "/" + std::to_string(n) + ".jpg", cv::IMREAD_GRAYSCALE));
    }
  } else {
    images = {Texture(512, 384, 3), Texture(512, 384, 40)};
  }
  const std::map<std::string, double> floors = {
      {"rotation 30 deg", 0.10},       {"scale 0.7", 0.25},
      {"brightness +30%", 0.60},       {"brightness -30%", 0.45},
      {"Gaussian blur sigma 2", 0.25}, {"JPEG quality 40", 0.45}};
  FeatureOptions oriented;
  oriented.surf_upright = 0;  // a 30-degree rotation is beyond U-SURF by design
  const SurfExtractor surf{oriented};
  for (const auto& transformation : StandardTransformations(images[0].size())) {
    double score = 0;
    for (const cv::Mat& image : images) {
      score += EvaluateMatching(surf, image, transformation).matching_score / images.size();
    }
    EXPECT_GE(score, floors.at(transformation.name)) << transformation.name;
  }
}

}  // namespace
}  // namespace memloop
