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

// Nearest gives the search's two neighbours and their true distances; MatchOf is Match's ratio test
// on them. A gate that stops after the first chunk (16 rows) leaves the other rows out.
TEST(DictionaryTest, NearestAndMatchOfAreMatchInTwoSteps) {
  Dictionary dictionary(DescriptorKind::kFloat, 2, testing::SmallDictionaryOptions());
  dictionary.Add({1, 2}, (cv::Mat_<float>(2, 2) << 0, 0, 10, 0));
  const cv::Mat queries = (cv::Mat_<float>(2, 2) << 4, 0, 4.5, 0);
  const auto nearest = dictionary.Nearest(queries);
  ASSERT_EQ(nearest.size(), 2u);
  EXPECT_EQ(nearest[0][0].word, 1);
  EXPECT_FLOAT_EQ(nearest[0][0].distance, 4);
  EXPECT_EQ(nearest[0][1].word, 2);
  EXPECT_FLOAT_EQ(nearest[0][1].distance, 6);
  EXPECT_EQ(dictionary.MatchOf(nearest[0]), 1);        // 4 < 0.8 x 6
  EXPECT_EQ(dictionary.MatchOf(nearest[1]), kNoWord);  // 4.5 > 0.8 x 5.5
  const cv::Mat many(40, 2, CV_32F, cv::Scalar(1));
  SearchOptions first_chunk;
  first_chunk.gate = [](size_t) { return false; };
  EXPECT_EQ(dictionary.Match(many, first_chunk).size(), WordIndex::kSearchChunk);
  EXPECT_EQ(dictionary.Match(many).size(), 40u);
}

// A gated quantization makes words of the rows it reached only.
TEST(DictionaryTest, GatedQuantizationStopsAtAChunk) {
  Dictionary dictionary(DescriptorKind::kFloat, 2, testing::SmallDictionaryOptions());
  testing::AddWords(dictionary, {1, 2});  // at 100 and 200: the rows (1000 + 50 k) match neither
  cv::Mat rows(40, 2, CV_32F);
  for (int row = 0; row < rows.rows; ++row) rows.at<float>(row, 0) = 1000.0f + 50 * row;
  rows.col(1).setTo(0);
  int created = 0;
  double search_ms = -1;
  const std::vector<WordId> words =
      dictionary.Quantize(rows, &created, {[](size_t taken) { return taken < 20; }}, &search_ms);
  EXPECT_EQ(words.size(), 2 * WordIndex::kSearchChunk);  // taken 0, 16 (< 20), then 32: stop
  EXPECT_EQ(created, static_cast<int>(words.size()));
  EXPECT_EQ(dictionary.size(), 2 + words.size());
  EXPECT_GE(search_ms, 0);
}

// MatchSince: a row searched at a mark, with the nearest and second distances found then, is
// matched again against the words that joined since, as one search of all of them would.
TEST(DictionaryTest, MatchSinceCountsTheWordsThatJoinedAfterTheSearch) {
  Dictionary dictionary(DescriptorKind::kFloat, 2, testing::SmallDictionaryOptions());
  dictionary.Add({1, 2}, (cv::Mat_<float>(2, 2) << 0, 0, 10, 0));
  EXPECT_EQ(dictionary.JoinMark(), 2);
  // Searched now: (5,0) is 5 from both words (no match); (1,0) matches word 1 (1 < 0.8 x 9).
  const cv::Mat rows = (cv::Mat_<float>(2, 2) << 5, 0, 1, 0);
  const auto nearest = dictionary.Nearest(rows);
  const long long mark = dictionary.JoinMark();
  const std::vector<std::pair<float, float>> found = {
      {nearest[0][0].distance, nearest[0][1].distance},
      {nearest[1][0].distance, nearest[1][1].distance}};
  // Nothing joined: the answers stand (a row that matched stays matched: MatchSince only says
  // whether a joined word takes it).
  EXPECT_EQ(*dictionary.MatchSince(rows, found, mark), (std::vector<WordId>{kNoWord, kNoWord}));
  // A twin of (5,0) joins at (5,0.5): 0.5 < 0.8 x min(5, its second among the joined: none) = 4.
  dictionary.Add({3}, (cv::Mat_<float>(1, 2) << 5, 0.5f));
  EXPECT_EQ(*dictionary.MatchSince(rows, found, mark), (std::vector<WordId>{3, kNoWord}));
  // Another joins beside it at (5,-0.5): 0.5 vs 0.5, the ratio test fails for both.
  dictionary.Add({4}, (cv::Mat_<float>(1, 2) << 5, -0.5f));
  EXPECT_EQ(*dictionary.MatchSince(rows, found, mark), (std::vector<WordId>{kNoWord, kNoWord}));
  // A joined word that left again does not count.
  dictionary.Remove(4);
  EXPECT_EQ(*dictionary.MatchSince(rows, found, mark), (std::vector<WordId>{3, kNoWord}));
  // Not nearer than what the search found: (1,0)'s nearest is still word 1, no change.
  dictionary.Add({5}, (cv::Mat_<float>(1, 2) << 1, 3));
  EXPECT_EQ(*dictionary.MatchSince(rows, found, mark), (std::vector<WordId>{3, kNoWord}));
}

TEST(DictionaryTest, MatchSinceForgetsWhatJoinedLongAgo) {
  Dictionary dictionary(DescriptorKind::kFloat, 2, testing::SmallDictionaryOptions());
  const cv::Mat row = (cv::Mat_<float>(1, 2) << 0, 0);
  const long long mark = dictionary.JoinMark();
  std::vector<WordId> ids(Dictionary::kJoinedRemembered);
  cv::Mat points(static_cast<int>(ids.size()), 2, CV_32F);
  for (size_t i = 0; i < ids.size(); ++i) {
    ids[i] = static_cast<WordId>(i + 1);
    points.at<float>(static_cast<int>(i), 0) = 100.0f + i;
    points.at<float>(static_cast<int>(i), 1) = 0;
  }
  dictionary.Add(ids, points);
  EXPECT_TRUE(dictionary.MatchSince(row, {{1e9f, 1e9f}}, mark).has_value());
  testing::AddWords(dictionary,
                    {static_cast<WordId>(ids.size() + 1000)});  // one more: the first goes
  EXPECT_FALSE(dictionary.MatchSince(row, {{1e9f, 1e9f}}, mark).has_value());
  EXPECT_TRUE(dictionary.MatchSince(row, {{1e9f, 1e9f}}, mark + 1).has_value());
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
