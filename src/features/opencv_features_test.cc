#include "features/opencv_features.h"

#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>
#include <set>
#include <tuple>

#include "memloop/feature_extractor.h"
#include "memloop/options.h"
#include "noise_texture.h"

namespace memloop {
namespace {

cv::Mat Texture() { return testing::NoiseTexture(cv::Size(320, 240), 5, 2.0); }

// sift.upright / orb.upright: every keypoint at angle 0, each once (SIFT makes one per dominant
// orientation), described at that angle; oriented, the detector's angles stay.
TEST(OpenCvFeaturesTest, UprightDescribesAtAngleZeroOnce) {
  FeatureOptions options;
  for (const char* type : {"sift", "orb"}) {
    SCOPED_TRACE(type);
    options.type = type;
    options.sift_upright = options.orb_upright = 1;
    const Features upright = FeatureExtractor::Create(options)->Extract(Texture());
    options.sift_upright = options.orb_upright = 0;
    const Features oriented = FeatureExtractor::Create(options)->Extract(Texture());
    ASSERT_GT(upright.keypoints.size(), 50u);
    ASSERT_EQ(upright.descriptors.rows, static_cast<int>(upright.keypoints.size()));
    std::set<std::tuple<float, float, float>> places;
    for (const cv::KeyPoint& keypoint : upright.keypoints) {
      EXPECT_EQ(keypoint.angle, 0.0f);
      places.emplace(keypoint.pt.x, keypoint.pt.y, keypoint.size);
    }
    EXPECT_EQ(places.size(), upright.keypoints.size());
    int angled = 0;
    for (const cv::KeyPoint& keypoint : oriented.keypoints) angled += keypoint.angle != 0.0f;
    EXPECT_GT(angled, static_cast<int>(oriented.keypoints.size()) / 2);
    // The same image, the same upright features: repeatable.
    options.sift_upright = options.orb_upright = 1;
    const Features again = FeatureExtractor::Create(options)->Extract(Texture());
    ASSERT_EQ(again.descriptors.size(), upright.descriptors.size());
    EXPECT_EQ(cv::norm(again.descriptors, upright.descriptors, cv::NORM_L1), 0.0);
  }
}

}  // namespace
}  // namespace memloop
