#include "detector/whole_image_likelihood.h"

#include <gtest/gtest.h>

#include <cmath>

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

}  // namespace
}  // namespace memloop
