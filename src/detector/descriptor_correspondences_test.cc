#include "detector/descriptor_correspondences.h"

#include <gtest/gtest.h>

namespace memloop {
namespace {

// A view of 2-D descriptors (rows), keypoint i at (i, 100 + i).
DescribedView ViewOf(const std::vector<cv::Vec2f>& descriptors) {
  DescribedView view;
  for (size_t i = 0; i < descriptors.size(); ++i) {
    view.keypoints.emplace_back(static_cast<float>(i), 100.0f + i, 5);
    view.descriptors.push_back(cv::Mat(1, 2, CV_32F, const_cast<float*>(descriptors[i].val)));
  }
  return view;
}

TEST(DescriptorCorrespondencesTest, MutualNearestNeighboursThatPassTheRatioTest) {
  DescribedView a = ViewOf({{0, 0}, {10, 0}, {0, 10}, {5, 5}, {20, 20}, {29, 29}});
  const DescribedView b =
      ViewOf({{0.1f, 0}, {10, 0.5f}, {0, 10.2f}, {5.45f, 5}, {4.5f, 5}, {30, 30}});
  for (int i = 0; i < a.size(); ++i) a.points.emplace_back(i, 0, i == 2 ? 0 : 1.5f);
  const WordCorrespondences matched = MatchDescriptors(a, b);
  // a3's two nearest (0.45 and 0.5 away) fail the ratio test (0.45 > 0.8 * 0.5); a4's nearest,
  // b5 (14.1 away), has a5 (1.4 away) as its own nearest: not mutual.
  ASSERT_EQ(matched.size(), 4);
  const std::vector<int> from_a = {0, 1, 2, 5}, to_b = {0, 1, 2, 5};
  for (int k = 0; k < 4; ++k) {
    EXPECT_EQ(matched.in_a[k], a.keypoints[from_a[k]].pt) << k;
    EXPECT_EQ(matched.in_b[k], b.keypoints[to_b[k]].pt) << k;
    EXPECT_EQ(matched.points_a[k], a.points[from_a[k]]) << k;  // z = 0 stays: no depth there
  }
  // A ratio of 0.95 lets a3 through (0.45 < 0.475).
  EXPECT_EQ(MatchDescriptors(a, b, 0.95).size(), 5);
}

TEST(DescriptorCorrespondencesTest, ViewsThatCannotBeComparedGiveNoPairs) {
  const DescribedView a = ViewOf({{0, 0}, {10, 0}, {0, 10}});
  DescribedView binary;
  for (int i = 0; i < 3; ++i) binary.keypoints.emplace_back(static_cast<float>(i), 0.0f, 5);
  binary.descriptors = cv::Mat::zeros(3, 2, CV_8U);
  EXPECT_EQ(MatchDescriptors(a, binary).size(), 0);  // another descriptor type
  EXPECT_EQ(MatchDescriptors(a, DescribedView{}).size(), 0);
  DescribedView one = ViewOf({{0, 0}});  // no second nearest: no ratio test can pass
  EXPECT_EQ(MatchDescriptors(a, one).size(), 0);
  EXPECT_TRUE(MatchDescriptors(a, a).points_a.empty());  // a view without depth
  EXPECT_EQ(MatchDescriptors(a, a).size(), 3);
}

}  // namespace
}  // namespace memloop
