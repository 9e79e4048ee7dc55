#include "detector/whole_image_likelihood.h"

#include <gtest/gtest.h>

#include <cmath>

#include "features/whole_image_descriptor.h"
#include "small_memory.h"

namespace memloop {
namespace {

IdMap<double> Scores(std::initializer_list<std::pair<LocationId, double>> values) {
  IdMap<double> scores;
  for (const auto& [id, value] : values) scores.emplace(id, value);
  return scores;
}

TEST(WholeImageLikelihoodTest, OnlyAPlaceThatStandsOutOfWmIsLikelier) {
  // Scores 0.5, 0.6, 0.7, 0.9: mean 0.675, standard deviation sqrt(0.0875 / 4) = 0.147902, so
  // z = -1.1832, -0.5071, 0.1690, 1.5213. Only location 4 passes min_z = 1:
  // exp(2 * 0.5213) = 2.836456; the virtual place gets the mean, (3 + 2.836456) / 4 = 1.459114.
  const WholeImageLikelihood channel =
      ComputeWholeImageLikelihood(Scores({{1, 0.5}, {2, 0.6}, {3, 0.7}, {4, 0.9}}), 2.0, 1.0);
  EXPECT_NEAR(channel.mean, 0.675, 1e-12);
  EXPECT_NEAR(channel.stddev, 0.1479020, 1e-7);
  EXPECT_EQ(channel.values.at(1), 1.0);
  EXPECT_EQ(channel.values.at(2), 1.0);
  EXPECT_EQ(channel.values.at(3), 1.0);
  EXPECT_NEAR(channel.values.at(4), 2.836456, 1e-6);
  EXPECT_NEAR(channel.virtual_place, 1.459114, 1e-6);
}

TEST(WholeImageLikelihoodTest, NothingToWeighGivesOnes) {
  for (const IdMap<double>& scores :
       {Scores({}), Scores({{1, 0.9}}), Scores({{1, 0.4}, {2, 0.4}, {3, 0.4}})}) {
    const WholeImageLikelihood channel = ComputeWholeImageLikelihood(scores, 2.0, 1.0);
    for (const auto& [id, value] : channel.values) EXPECT_EQ(value, 1.0) << id;
    EXPECT_EQ(channel.virtual_place, 1.0);
  }
  // gain 0: the channel is kept but not weighed.
  const WholeImageLikelihood off =
      ComputeWholeImageLikelihood(Scores({{1, 0.5}, {2, 0.6}, {3, 0.7}, {4, 0.9}}), 0.0, 1.0);
  EXPECT_EQ(off.values.at(4), 1.0);
  EXPECT_EQ(off.virtual_place, 1.0);
}

TEST(WholeImageLikelihoodTest, MultipliesIntoEquations3And4) {
  Likelihood words;
  words.values = Scores({{1, 2.0}, {2, 1.0}, {3, 1.0}});
  words.virtual_place = 3.0;
  WholeImageLikelihood channel;
  channel.values = Scores({{1, 1.5}, {2, 4.0}});  // 3 absent: kept
  channel.virtual_place = 1.25;
  MultiplyLikelihood(channel, words);
  EXPECT_EQ(words.values.at(1), 3.0);
  EXPECT_EQ(words.values.at(2), 4.0);
  EXPECT_EQ(words.values.at(3), 1.0);
  EXPECT_EQ(words.virtual_place, 3.75);
}

TEST(WholeImageLikelihoodTest, ALocationIsSeenBeforeAnImageByItsFirstImage) {
  Location merged;
  merged.images = {5, 1};  // rehearsal merged image 1 into the location of image 5
  EXPECT_TRUE(SeenBefore(merged, 2));
  EXPECT_FALSE(SeenBefore(merged, 1));
  Location recent;
  recent.images = {5};
  EXPECT_FALSE(SeenBefore(recent, 2));
  EXPECT_TRUE(SeenBefore(recent, kNoImage));  // no session bound: every location
  EXPECT_FALSE(SeenBefore(Location(), 2));
}

// Locations of images 0-3 in WM, each with a descriptor; the image's session starts at image 2.
class WholeImageScopeTest : public ::testing::Test {
 protected:
  void SetUp() override {
    ids_ = testing::AddChain(memory_, {{1, 2}, {3, 4}, {5, 6}, {7, 8}});
    memory_.MoveStmOverflowToWm(0);
    for (size_t i = 0; i < ids_.size(); ++i) {
      memory_.at(ids_[i]).signature.whole_image = Descriptor(static_cast<int>(i));
    }
  }

  // Cell c has 1 in bin (c + shift) % 9, 0 elsewhere: centred, each cell is 8/9 at that bin and
  // -1/9 at the 8 others. Two descriptors of the same shift score 1; of shifts one apart, each
  // cell's product is -1/9 against a squared norm of 8/9: cosine -1/8.
  static WholeImageDescriptor Descriptor(int shift) {
    WholeImageDescriptor descriptor(kWholeImageDescriptorSize, 0);
    for (int cell = 0; cell < kWholeImageDescriptorSize / 9; ++cell) {
      descriptor[cell * 9 + (cell + shift) % 9] = 255;
    }
    return descriptor;
  }

  Memory memory_{DescriptorKind::kFloat, 2, testing::SmallDictionaryOptions()};
  std::vector<LocationId> ids_;
};

TEST_F(WholeImageScopeTest, OnlyLocationsOfEarlierSessionsAreScored) {
  const IdMap<double> earlier = ScoreWholeImage(Descriptor(1), memory_, 2);
  ASSERT_EQ(earlier.size(), 2u);
  EXPECT_NEAR(earlier.at(ids_[0]), -1.0 / 8, 1e-9);
  EXPECT_NEAR(earlier.at(ids_[1]), 1.0, 1e-9);
  EXPECT_EQ(ScoreWholeImage(Descriptor(1), memory_, kNoImage).size(), 4u);
  EXPECT_TRUE(ScoreWholeImage(Descriptor(1), memory_, 0).empty());  // the map's first session
}

TEST_F(WholeImageScopeTest, WordsThatRecognizeAnEarlierPlaceKeepTheChannelOut) {
  Likelihood likelihood;
  likelihood.values = Scores({{ids_[0], 1.0}, {ids_[1], 2.5}, {ids_[2], 4.0}, {ids_[3], 1.0}});
  // Location 2 (image 2) is this session's: its 4.0 says nothing of an earlier place.
  EXPECT_FALSE(WordsRecognize(likelihood, memory_, 2, 3.0));
  EXPECT_TRUE(WordsRecognize(likelihood, memory_, 2, 2.5));  // location 1's 2.5 reaches 2.5
  EXPECT_TRUE(WordsRecognize(likelihood, memory_, kNoImage, 3.0));
  EXPECT_FALSE(WordsRecognize(likelihood, memory_, kNoImage, 0.0));  // 0: off
  // The words' own value: 5.0 with a channel factor of 2 is 2.5 from the words.
  likelihood.values[ids_[1]] = 5.0;
  likelihood.whole_image_values = Scores({{ids_[1], 2.0}});
  EXPECT_FALSE(WordsRecognize(likelihood, memory_, 2, 3.0));
}

TEST_F(WholeImageScopeTest, WeighsEarlierSessionsUnlessTheWordsRecognizeOne) {
  FilterOptions options;
  options.whole_image_gain = 1.0;
  options.whole_image_min_z = 0.5;
  options.whole_image_words_first = 3.0;
  Likelihood words;
  words.values = Scores({{ids_[0], 1.0}, {ids_[1], 1.0}, {ids_[2], 1.0}, {ids_[3], 1.0}});
  words.virtual_place = 2.0;
  // Scored against images 0 and 1 only: -1/8 and 1, mean 7/16, standard deviation 9/16, so
  // z = -1 and 1. Location 1: exp(1 * (1 - 0.5)) = 1.648721; the virtual place gets the mean of
  // 1 and 1.648721, 1.324361, times 2.
  Likelihood weighed = words;
  WeighWholeImage(Descriptor(1), memory_, options, 2, weighed);
  EXPECT_EQ(weighed.values.at(ids_[0]), 1.0);
  EXPECT_NEAR(weighed.values.at(ids_[1]), 1.648721, 1e-6);
  EXPECT_EQ(weighed.values.at(ids_[2]), 1.0);  // this session's: not weighed
  EXPECT_EQ(weighed.whole_image_z.size(), 2u);
  EXPECT_NEAR(weighed.virtual_place, 2 * 1.324361, 1e-6);
  // The words give location 0 an eq. 3 value of 3: the channel stays out.
  Likelihood recognized = words;
  recognized.values[ids_[0]] = 3.0;
  WeighWholeImage(Descriptor(1), memory_, options, 2, recognized);
  EXPECT_EQ(recognized.values.at(ids_[1]), 1.0);
  EXPECT_EQ(recognized.virtual_place, 2.0);
  EXPECT_TRUE(recognized.whole_image_z.empty());
}

}  // namespace
}  // namespace memloop
