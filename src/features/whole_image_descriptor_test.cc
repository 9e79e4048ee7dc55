#include "features/whole_image_descriptor.h"

#include <gtest/gtest.h>

#include <cmath>
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

// Cells of 9 orientation bins, each centred on its mean before the cosine.
WholeImageDescriptor Cells(std::initializer_list<std::vector<uint8_t>> cells) {
  WholeImageDescriptor descriptor;
  for (const auto& cell : cells) descriptor.insert(descriptor.end(), cell.begin(), cell.end());
  return descriptor;
}

TEST(WholeImageDescriptorTest, SimilarityIsTheCosineOfTheCellsCentredOnTheirMean) {
  const std::vector<uint8_t> east{9, 0, 0, 0, 0, 0, 0, 0, 0};  // centred: 8, then eight -1
  const std::vector<uint8_t> north{0, 9, 0, 0, 0, 0, 0, 0, 0};
  const std::vector<uint8_t> round(9, 5);  // the same energy in every direction
  EXPECT_DOUBLE_EQ(WholeImageSimilarity(Cells({east}), Cells({east})), 1.0);
  // 8 * -1 + -1 * 8 + 7 * (-1 * -1) = -9, over 8^2 + 8 = 72.
  EXPECT_DOUBLE_EQ(WholeImageSimilarity(Cells({east}), Cells({north})), -9.0 / 72.0);
  // Energy in every direction drops out (noise at night): east plus 10 in each bin is east.
  const std::vector<uint8_t> east_noisy{19, 10, 10, 10, 10, 10, 10, 10, 10};
  EXPECT_DOUBLE_EQ(WholeImageSimilarity(Cells({east}), Cells({east_noisy})), 1.0);
  // A cell without an orientation that stands out weighs nothing: 72 / sqrt(72 * (72 + 72)).
  EXPECT_DOUBLE_EQ(WholeImageSimilarity(Cells({east, round}), Cells({east, north})),
                   1.0 / std::sqrt(2.0));
  EXPECT_EQ(WholeImageSimilarity(Cells({round}), Cells({east})), 0);  // nothing to compare
  // A location made without the channel, or a size that is not whole cells.
  EXPECT_EQ(WholeImageSimilarity(Cells({east}), Cells({east, east})), 0);
  EXPECT_EQ(WholeImageSimilarity({1, 2}, {1, 2}), 0);
  EXPECT_EQ(WholeImageSimilarity({}, {}), 0);
}

// What the channel is for: the same scene by night (darker, less contrast, another gamma, noise)
// keeps its gradients' orientations; another scene's differ. Vertical stripes vote the 0-degree
// bins only, horizontal ones the 90-degree bin: no bin in common (centred, below 0).
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
