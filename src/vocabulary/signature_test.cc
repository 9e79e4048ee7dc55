#include "vocabulary/signature.h"

#include <gtest/gtest.h>

#include "memloop/feature_extractor.h"
#include "small_memory.h"
#include "vocabulary/dictionary.h"

namespace memloop {
namespace {

using testing::MakeSignature;

TEST(SignatureTest, HistogramCountsRepeatedWords) {
  const auto histogram = MakeSignature({3, 1, 3, 2, 3}).Histogram();
  const std::vector<std::pair<WordId, int>> expected = {{1, 1}, {2, 1}, {3, 3}};
  EXPECT_EQ(histogram, expected);
}

TEST(SignatureTest, WordPairsTakeTheSmallerCount) {
  // t: {1:1, 2:2, 3:1}; c: {2:1, 3:2, 4:1, 5:1} -> min(2,1) + min(1,2) = 2 pairs.
  EXPECT_EQ(CountWordPairs(MakeSignature({1, 2, 2, 3}).Histogram(),
                           MakeSignature({2, 3, 3, 4, 5}).Histogram()),
            2);
}

TEST(SignatureTest, Equation1DividesByTheLargerSignature) {
  // N_zt = 4 < N_zc = 5: s = N_pair / N_zc = 2 / 5.
  EXPECT_DOUBLE_EQ(Similarity(MakeSignature({1, 2, 2, 3}), MakeSignature({2, 3, 3, 4, 5})), 0.4);
  // N_zt = 6 >= N_zc = 2: s = N_pair / N_zt = 2 / 6.
  EXPECT_DOUBLE_EQ(Similarity(MakeSignature({1, 2, 3, 4, 5, 6}), MakeSignature({1, 2})), 2.0 / 6);
  EXPECT_DOUBLE_EQ(Similarity(MakeSignature({7, 8}), MakeSignature({8, 7})), 1.0);
  EXPECT_DOUBLE_EQ(Similarity(MakeSignature({}), MakeSignature({})), 0.0);
  EXPECT_DOUBLE_EQ(Similarity(MakeSignature({1}), MakeSignature({2})), 0.0);
}

TEST(SignatureTest, LocalizationMatchesWithoutCreatingWords) {
  Dictionary dictionary(DescriptorKind::kFloat, 2, testing::SmallDictionaryOptions());
  dictionary.Add({1, 2}, (cv::Mat_<float>(2, 2) << 0, 0, 10, 0));
  Features features;
  // (1,0) -> word 1; (5,0) is as far from both (ratio test fails) -> dropped; (9,0) -> word 2.
  features.descriptors = (cv::Mat_<float>(3, 2) << 1, 0, 5, 0, 9, 0);
  features.keypoints = {cv::KeyPoint(10, 10, 1), cv::KeyPoint(20, 20, 1), cv::KeyPoint(30, 30, 1)};
  const Signature signature = MatchSignature(features, dictionary);
  EXPECT_EQ(signature.words, (std::vector<WordId>{1, 2}));
  ASSERT_EQ(signature.keypoints.size(), 2u);
  EXPECT_EQ(signature.keypoints[1].pt, cv::Point2f(30, 30));  // each word keeps its own keypoint
  EXPECT_EQ(dictionary.size(), 2u);
}

// A gated quantization keeps the features it reached (the first, strongest ones) and their
// keypoints; KeepFirstFeatures cuts the image's features, rolled view included, to match.
TEST(SignatureTest, GatedSignatureHoldsTheFirstFeatures) {
  Dictionary dictionary(DescriptorKind::kFloat, 2, testing::SmallDictionaryOptions());
  testing::AddWords(dictionary, {1});
  Features features;
  features.descriptors.create(40, 2, CV_32F);
  features.rolled_descriptors.create(40, 2, CV_32F);
  for (int row = 0; row < 40; ++row) {
    features.keypoints.emplace_back(static_cast<float>(row), 0.0f, 3.0f);
    features.descriptors.at<float>(row, 0) = 1000.0f + 50 * row;
    features.descriptors.at<float>(row, 1) = 0;
    features.rolled_descriptors.at<float>(row, 0) = static_cast<float>(row);
    features.rolled_descriptors.at<float>(row, 1) = 0;
  }
  int created = 0;
  const Signature signature =
      CreateSignature(features, dictionary, &created, {[](size_t) { return false; }});
  ASSERT_EQ(signature.size(), 16);
  EXPECT_EQ(signature.keypoints.size(), 16u);
  EXPECT_EQ(signature.keypoints.back().pt.x, 15.0f);
  KeepFirstFeatures(features, 16);
  EXPECT_EQ(features.keypoints.size(), 16u);
  EXPECT_EQ(features.descriptors.rows, 16);
  EXPECT_EQ(features.rolled_descriptors.rows, 16);
  EXPECT_EQ(features.rolled_descriptors.at<float>(15, 0), 15.0f);
  KeepFirstFeatures(features, 100);  // more than there are: nothing changes
  EXPECT_EQ(features.descriptors.rows, 16);
}

}  // namespace
}  // namespace memloop
