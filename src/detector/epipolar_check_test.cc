#include "detector/epipolar_check.h"

#include <gtest/gtest.h>

#include <opencv2/core.hpp>

namespace memloop {
namespace {

// Points of a rigid 3-D scene seen by two cameras (a sideways step): their images satisfy one
// epipolar geometry. Word k is at point k in both views.
void TwoViews(int points, Signature* a, Signature* b) {
  cv::RNG rng(3);
  for (int k = 0; k < points; ++k) {
    const cv::Point3d p(rng.uniform(-2.0, 2.0), rng.uniform(-1.5, 1.5), rng.uniform(4.0, 9.0));
    const auto project = [&](double shift) {
      return cv::Point2f(static_cast<float>(320 + 500 * (p.x - shift) / p.z),
                         static_cast<float>(240 + 500 * p.y / p.z));
    };
    a->words.push_back(k + 1);
    a->keypoints.emplace_back(project(0.0), 10.f);
    b->words.push_back(k + 1);
    b->keypoints.emplace_back(project(0.5), 10.f);
  }
}

VerificationOptions Needing(int inliers) {
  VerificationOptions options;
  options.min_inliers = inliers;
  return options;
}

TEST(EpipolarCheckTest, OneRigidSceneHasEveryCorrespondenceAnInlier) {
  Signature a, b;
  TwoViews(40, &a, &b);
  const EpipolarCheck check = CheckEpipolarGeometry(a, b, Needing(20));
  EXPECT_EQ(check.correspondences, 40);
  EXPECT_GE(check.inliers, 38);  // noiseless: all, up to RANSAC's last refit
  EXPECT_TRUE(check.passed);
}

TEST(EpipolarCheckTest, ShuffledCorrespondencesFail) {
  Signature a, b;
  TwoViews(40, &a, &b);
  cv::RNG rng(5);
  for (auto& keypoint : b.keypoints) {
    keypoint.pt = cv::Point2f(rng.uniform(0.f, 640.f), rng.uniform(0.f, 480.f));
  }
  const EpipolarCheck check = CheckEpipolarGeometry(a, b, Needing(20));
  EXPECT_EQ(check.correspondences, 40);
  EXPECT_LT(check.inliers, 20);
  EXPECT_FALSE(check.passed);
}

// Repeated words are ambiguous and left out; fewer than 8 correspondences fail without RANSAC.
TEST(EpipolarCheckTest, RepeatedWordsAreLeftOutAndTooFewFail) {
  Signature a, b;
  TwoViews(9, &a, &b);
  a.words[1] = a.words[0];  // word 1 twice in a: both left out
  const EpipolarCheck check = CheckEpipolarGeometry(a, b, Needing(1));
  EXPECT_EQ(check.correspondences, 7);  // words 3..9
  EXPECT_EQ(check.inliers, 0);
  EXPECT_FALSE(check.passed);
}

TEST(EpipolarCheckTest, SameInputSameVerdict) {
  Signature a, b;
  TwoViews(60, &a, &b);
  cv::RNG rng(9);
  for (int k = 0; k < 20; ++k) {
    b.keypoints[k].pt = cv::Point2f(rng.uniform(0.f, 640.f), rng.uniform(0.f, 480.f));
  }
  const EpipolarCheck first = CheckEpipolarGeometry(a, b, Needing(30));
  const EpipolarCheck second = CheckEpipolarGeometry(a, b, Needing(30));
  EXPECT_EQ(first.inliers, second.inliers);
  EXPECT_GE(first.inliers, 40);
  EXPECT_TRUE(first.passed);
}

}  // namespace
}  // namespace memloop
