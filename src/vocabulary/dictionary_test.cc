#include "vocabulary/dictionary.h"

#include <gtest/gtest.h>

#include "memloop/errors.h"
#include "small_memory.h"

namespace memloop {
namespace {

TEST(DictionaryTest, RatioTestOnTrueDistances) {
  Dictionary dictionary(DescriptorKind::kFloat, 2, testing::SmallDictionaryOptions());
  dictionary.Add({1, 2}, (cv::Mat_<float>(2, 2) << 0, 0, 10, 0));
  // (1,0): d1 = 1 < 0.8 * d2 = 7.2 -> word 1. (4,0): d1 = 4 < 0.8 * 6 = 4.8 -> word 1.
  // (4.5,0): d1 = 4.5 > 0.8 * 5.5 = 4.4 -> none (squared distances would have passed:
  // 20.25 < 0.8 * 30.25). (9,0): d1 = 1 -> word 2.
  const cv::Mat queries = (cv::Mat_<float>(4, 2) << 1, 0, 4, 0, 4.5, 0, 9, 0);
  EXPECT_EQ(dictionary.Match(queries), (std::vector<WordId>{1, 1, kNoWord, 2}));
}

TEST(DictionaryTest, QuantizeCreatesWordsForUnmatchedDescriptors) {
  Dictionary dictionary(DescriptorKind::kFloat, 2, testing::SmallDictionaryOptions());
  dictionary.Add({1, 2}, (cv::Mat_<float>(2, 2) << 0, 0, 10, 0));
  // Rows 2 and 3 are close to each other but belong to one image: both become new words.
  const cv::Mat descriptors = (cv::Mat_<float>(3, 2) << 1, 0, 5, 0, 5.1f, 0);
  int created = 0;
  EXPECT_EQ(dictionary.Quantize(descriptors, &created), (std::vector<WordId>{1, 3, 4}));
  EXPECT_EQ(created, 2);
  EXPECT_EQ(dictionary.size(), 4u);
  EXPECT_EQ(dictionary.Descriptor(4).at<float>(0, 0), 5.1f);
  // The next image's (5.05, 0) now matches... neither: 3 and 4 are equally close.
  EXPECT_EQ(dictionary.Match((cv::Mat_<float>(1, 2) << 5.05f, 0))[0], kNoWord);
}

TEST(DictionaryTest, ReferencesAreTheInvertedIndex) {
  Dictionary dictionary(DescriptorKind::kFloat, 2, testing::SmallDictionaryOptions());
  testing::AddWords(dictionary, {1});
  dictionary.AddReference(1, 10);
  dictionary.AddReference(1, 10);
  dictionary.AddReference(1, 11);
  EXPECT_EQ(dictionary.References(1), (std::map<LocationId, int>{{10, 2}, {11, 1}}));
  EXPECT_FALSE(dictionary.RemoveReferences(1, 10));
  EXPECT_TRUE(dictionary.RemoveReferences(1, 11));  // none left
  dictionary.Remove(1);
  EXPECT_FALSE(dictionary.Contains(1));
  EXPECT_TRUE(dictionary.References(1).empty());
  EXPECT_EQ(dictionary.next_word_id(), 2);  // ids are never reused
}

TEST(DictionaryTest, OneMapOneDescriptorKind) {
  Dictionary dictionary(DescriptorKind::kFloat, 64, DictionaryOptions());
  const cv::Mat binary(3, 32, CV_8U, cv::Scalar(7));
  try {
    dictionary.Quantize(binary, nullptr);
    FAIL() << "binary descriptors accepted by a float dictionary";
  } catch (const Error& error) {
    EXPECT_NE(std::string(error.what()).find("64-d float"), std::string::npos) << error.what();
    EXPECT_NE(std::string(error.what()).find("32-byte binary"), std::string::npos);
  }
  EXPECT_THROW(dictionary.Match(cv::Mat(2, 128, CV_32F, cv::Scalar(0))), Error);
  EXPECT_EQ(dictionary.size(), 0u);  // nothing was added
}

}  // namespace
}  // namespace memloop
