#include "detector/word_correspondences.h"

#include <gtest/gtest.h>

namespace memloop {
namespace {

Signature Make(const std::vector<WordId>& words) {
  Signature signature;
  signature.words = words;
  for (size_t k = 0; k < words.size(); ++k) {
    signature.keypoints.emplace_back(static_cast<float>(10 * k), static_cast<float>(words[k]), 5);
  }
  return signature;
}

TEST(WordCorrespondencesTest, OnlyWordsEachSignatureHoldsOnceInWordOrder) {
  // Word 7 is shared once each; 3 is repeated in a; 9 is repeated in b; 4 is in a only.
  const Signature a = Make({9, 3, 7, 4, 3, 2});
  const Signature b = Make({2, 9, 7, 9, 3});
  const WordCorrespondences matched = UniqueWordCorrespondences(a, b);
  ASSERT_EQ(matched.size(), 2);
  // Word 2: a's keypoint 5, b's keypoint 0; word 7: a's 2, b's 2.
  EXPECT_EQ(matched.in_a[0], cv::Point2f(50, 2));
  EXPECT_EQ(matched.in_b[0], cv::Point2f(0, 2));
  EXPECT_EQ(matched.in_a[1], cv::Point2f(20, 7));
  EXPECT_EQ(matched.in_b[1], cv::Point2f(20, 7));
}

TEST(WordCorrespondencesTest, SignaturesWithoutKeypointsHaveNone) {
  Signature a = Make({1, 2});
  a.keypoints.clear();
  EXPECT_EQ(UniqueWordCorrespondences(a, Make({1, 2})).size(), 0);
}

}  // namespace
}  // namespace memloop
