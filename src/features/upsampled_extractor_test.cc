#include "features/upsampled_extractor.h"

#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>
#include <string>

#include "noise_texture.h"

namespace memloop {
namespace {

TEST(UpsampledExtractorTest, FactorIsTheSmallestIntegerThatReachesTheSide) {
  EXPECT_EQ(UpsampleFactor(cv::Size(160, 120), 240), 2);
  EXPECT_EQ(UpsampleFactor(cv::Size(120, 160), 240), 2);  // the smaller side, either way round
  EXPECT_EQ(UpsampleFactor(cv::Size(121, 119), 240), 3);  // 2 x 119 = 238 < 240
  EXPECT_EQ(UpsampleFactor(cv::Size(100, 50), 240), 5);
  EXPECT_EQ(UpsampleFactor(cv::Size(320, 240), 240), 1);  // already there
  EXPECT_EQ(UpsampleFactor(cv::Size(160, 120), 0), 1);    // off
  // 24x would make 720000x240; sqrt(4e6 / 300000) = 3.65: 3x, 2.7 million pixels.
  EXPECT_EQ(UpsampleFactor(cv::Size(30000, 10), 240), 3);
  EXPECT_EQ(UpsampleFactor(cv::Size(1000000, 10), 240), 1);  // over the cap already: as it is
}

// Records the image it was given and returns one keypoint at a known place.
class FixedKeypoint : public FeatureExtractor {
 public:
  explicit FixedKeypoint(cv::Size* seen) : seen_(seen) {}
  Features Extract(const cv::Mat& gray) const override {
    *seen_ = gray.size();
    Features features;
    features.keypoints.emplace_back(cv::Point2f(1.5f, 3.5f), 10.0f);
    features.descriptors = cv::Mat::ones(1, 4, CV_32F);
    return features;
  }
  int DescriptorDim() const override { return 4; }
  DescriptorKind Kind() const override { return DescriptorKind::kFloat; }
  const char* Name() const override { return "fixed"; }

 private:
  cv::Size* seen_;
};

TEST(UpsampledExtractorTest, KeypointsComeBackInTheImagesPixels) {
  cv::Size seen;
  const UpsampledExtractor extractor(std::make_unique<FixedKeypoint>(&seen), 240);
  const Features features = extractor.Extract(cv::Mat::zeros(120, 160, CV_8U));
  EXPECT_EQ(seen, cv::Size(320, 240));
  ASSERT_EQ(features.keypoints.size(), 1u);
  // Enlarged pixel x is image x' = (x + 0.5) / 2 - 0.5: 1.5 -> 0.5, 3.5 -> 1.5.
  EXPECT_FLOAT_EQ(features.keypoints[0].pt.x, 0.5f);
  EXPECT_FLOAT_EQ(features.keypoints[0].pt.y, 1.5f);
  EXPECT_FLOAT_EQ(features.keypoints[0].size, 5.0f);
  EXPECT_EQ(features.descriptors.rows, 1);

  extractor.Extract(cv::Mat::zeros(240, 320, CV_8U));
  EXPECT_EQ(seen, cv::Size(320, 240));  // large enough: given as it is
}

cv::Mat SmallTexture() { return testing::NoiseTexture(cv::Size(160, 120), 11, 1.5); }

// Through FeatureExtractor::Create, as the detector makes it: at 160x120 SURF and ORB find more
// keypoints enlarged (OpenCV's SIFT already doubles its input: on this fine noise its count does
// not rise), all inside the image; at the threshold nothing changes.
TEST(UpsampledExtractorTest, SmallImagesGiveMoreKeypointsInsideTheImage) {
  for (const char* type : {"surf", "sift", "orb"}) {
    SCOPED_TRACE(type);
    FeatureOptions options;
    options.type = type;
    options.max_features = 0;
    options.min_image_side = 0;
    const Features as_is = FeatureExtractor::Create(options)->Extract(SmallTexture());
    options.min_image_side = 240;
    const Features enlarged = FeatureExtractor::Create(options)->Extract(SmallTexture());
    if (std::string(type) != "sift") {
      EXPECT_GT(enlarged.keypoints.size(), as_is.keypoints.size());
    }
    ASSERT_GT(enlarged.keypoints.size(), 0u);
    EXPECT_EQ(enlarged.descriptors.rows, static_cast<int>(enlarged.keypoints.size()));
    for (const cv::KeyPoint& keypoint : enlarged.keypoints) {
      EXPECT_GE(keypoint.pt.x, -0.5f);
      EXPECT_LT(keypoint.pt.x, 160.0f);
      EXPECT_GE(keypoint.pt.y, -0.5f);
      EXPECT_LT(keypoint.pt.y, 120.0f);
    }
    cv::Mat large;
    cv::resize(SmallTexture(), large, cv::Size(320, 240));
    const Features large_on = FeatureExtractor::Create(options)->Extract(large);
    options.min_image_side = 0;
    const Features large_off = FeatureExtractor::Create(options)->Extract(large);
    ASSERT_EQ(large_on.keypoints.size(), large_off.keypoints.size());
    EXPECT_EQ(cv::norm(large_on.descriptors, large_off.descriptors, cv::NORM_L1), 0.0);
  }
}

}  // namespace
}  // namespace memloop
