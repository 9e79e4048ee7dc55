#include "features/whole_image_descriptor.h"

#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

namespace memloop {
namespace {

// Stripes 12 pixels wide, dark on light: vertical ones have horizontal gradients only.
cv::Mat Stripes(bool vertical, double dark = 40, double light = 200) {
  cv::Mat image(192, 256, CV_8U, cv::Scalar(light));
  for (int k = 0; k < 256; k += 24) {
    if (vertical) {
      image.colRange(k, std::min(k + 12, 256)).setTo(dark);
    } else if (k < 192) {
      image.rowRange(k, std::min(k + 12, 192)).setTo(dark);
    }
  }
  return image;
}

TEST(WholeImageDescriptorTest, SizeAndEmptyImage) {
  EXPECT_TRUE(DescribeWholeImage(cv::Mat()).empty());
  EXPECT_EQ(DescribeWholeImage(Stripes(true)).size(), size_t{kWholeImageDescriptorSize});
  // No gradient anywhere: every bin 0, and nothing to compare.
  const WholeImageDescriptor flat = DescribeWholeImage(cv::Mat(120, 160, CV_8U, cv::Scalar(90)));
  EXPECT_EQ(flat, WholeImageDescriptor(kWholeImageDescriptorSize, 0));
  EXPECT_EQ(WholeImageSimilarity(flat, flat), 0);
}

TEST(WholeImageDescriptorTest, SimilarityIsTheCosineOfTheQuantizedValues) {
  EXPECT_DOUBLE_EQ(WholeImageSimilarity({3, 4}, {3, 4}), 1.0);
  EXPECT_DOUBLE_EQ(WholeImageSimilarity({3, 4}, {4, 3}), 24.0 / 25.0);
  EXPECT_DOUBLE_EQ(WholeImageSimilarity({1, 0}, {0, 1}), 0.0);
  EXPECT_EQ(WholeImageSimilarity({1, 2}, {1, 2, 3}), 0);  // a location made without the channel
  EXPECT_EQ(WholeImageSimilarity({}, {}), 0);
}

// What the channel is for: the same scene by night (darker, less contrast, another gamma, noise)
// keeps its gradients' orientations; another scene's differ. Vertical stripes vote the 0-degree
// bins only, horizontal ones the 90-degree bin: no bin in common.
TEST(WholeImageDescriptorTest, LightChangesLittleAndStructureEverything) {
  const WholeImageDescriptor day = DescribeWholeImage(Stripes(true));
  cv::Mat night = Stripes(true, 10, 60);
  cv::Mat noise(night.size(), CV_8U);
  cv::randn(noise, 0, 4);
  night += noise;
  EXPECT_GT(WholeImageSimilarity(day, DescribeWholeImage(night)), 0.95);
  EXPECT_LT(WholeImageSimilarity(day, DescribeWholeImage(Stripes(false))), 0.01);
  // The thumbnail ignores the size: a half-size copy is described alike.
  cv::Mat half;
  cv::resize(Stripes(true), half, cv::Size(128, 96), 0, 0, cv::INTER_AREA);
  EXPECT_GT(WholeImageSimilarity(day, DescribeWholeImage(half)), 0.95);
}

}  // namespace
}  // namespace memloop
