#include "detector/likelihood.h"

#include <gtest/gtest.h>

#include <cmath>

#include "small_memory.h"

namespace memloop {
namespace {

TEST(LikelihoodTest, Equations3And4ByHand) {
  // Non-null scores 0.1, 0.5, 0.3: mu = 0.3, sigma = sqrt(0.08 / 3) = 0.1632993.
  const Likelihood likelihood = ComputeLikelihood({{1, 0.1}, {2, 0.5}, {3, 0.0}, {4, 0.3}});
  EXPECT_NEAR(likelihood.mean, 0.3, 1e-12);
  EXPECT_NEAR(likelihood.stddev, 0.16329931618554522, 1e-12);
  // Only s_2 = 0.5 >= mu + sigma = 0.463: (0.5 - sigma) / mu = 1.1223356.
  EXPECT_NEAR(likelihood.values.at(2), 1.1223356127148494, 1e-12);
  EXPECT_EQ(likelihood.values.at(1), 1.0);
  EXPECT_EQ(likelihood.values.at(3), 1.0);
  EXPECT_EQ(likelihood.values.at(4), 1.0);
  EXPECT_NEAR(likelihood.virtual_place, 0.3 / 0.16329931618554522 + 1, 1e-12);  // 2.8371173
}

TEST(LikelihoodTest, NoSimilarLocationMakesTheVirtualPlaceLikely) {
  const Likelihood likelihood = ComputeLikelihood({{1, 0.0}, {2, 0.0}});
  EXPECT_EQ(likelihood.values.at(1), 1.0);
  EXPECT_EQ(likelihood.values.at(2), 1.0);
  EXPECT_EQ(likelihood.virtual_place, 2.0);
}

// Eq. 4 as written jumps at sigma = 0: a tie gives 2, a near tie thousands.
TEST(LikelihoodTest, AsWrittenEquation4JumpsAtSigmaZero) {
  EXPECT_EQ(ComputeLikelihood({{1, 0.5}, {2, 0.5}}, 0).virtual_place, 2.0);
  // mu = 0.5001, sigma = 0.0001: 0.5001 / 0.0001 + 1 = 5002.
  EXPECT_NEAR(ComputeLikelihood({{1, 0.5}, {2, 0.5002}}, 0).virtual_place, 5002, 1e-6);
}

// With sigma floored at 0.1 mu, ties and near ties agree: sigma = 0.05 (tie) or 0.05001 (near
// tie), so mu/sigma + 1 = 11 in both; eq. 3 gives 1 to both locations (s < mu + sigma).
TEST(LikelihoodTest, FlooredSigmaMakesEquation4Continuous) {
  const Likelihood tie = ComputeLikelihood({{1, 0.5}, {2, 0.5}}, 0.1);
  const Likelihood near_tie = ComputeLikelihood({{1, 0.5}, {2, 0.5002}}, 0.1);
  EXPECT_NEAR(tie.virtual_place, 11, 1e-12);
  EXPECT_NEAR(near_tie.virtual_place, 11, 1e-12);
  EXPECT_EQ(near_tie.values.at(2), 1.0);
  // Far from a tie the floor changes nothing: mu = 0.3, sigma = 0.1633 > 0.03 (first test).
  const Likelihood spread = ComputeLikelihood({{1, 0.1}, {2, 0.5}, {3, 0.0}, {4, 0.3}}, 0.1);
  EXPECT_NEAR(spread.virtual_place, 0.3 / 0.16329931618554522 + 1, 1e-12);
  // One non-null score: sigma cannot be estimated, mu/sigma is taken as 1.
  EXPECT_EQ(ComputeLikelihood({{1, 0.4}, {2, 0.0}}, 0.1).virtual_place, 2.0);
}

TEST(LikelihoodTest, ScoresOfWorkingMemoryAreEquation1) {
  Memory memory(DescriptorKind::kFloat, 2, testing::SmallDictionaryOptions());
  const auto ids = testing::AddChain(memory, {{1, 2, 3}, {3, 4}, {5, 6, 7, 8}, {1, 3, 4, 9}});
  memory.MoveStmOverflowToWm(1);  // the last one stays in STM: it is L_t
  const Signature& z_t = memory.at(ids[3]).signature;
  const auto scores = ScoreWorkingMemory(z_t, memory);
  ASSERT_EQ(scores.size(), 3u);
  EXPECT_DOUBLE_EQ(scores.at(ids[0]), 2.0 / 4);  // {1, 3} of max(4, 3)
  EXPECT_DOUBLE_EQ(scores.at(ids[1]), 2.0 / 4);  // {3, 4}
  EXPECT_DOUBLE_EQ(scores.at(ids[2]), 0.0);
  for (LocationId id : {ids[0], ids[1], ids[2]}) {
    EXPECT_DOUBLE_EQ(scores.at(id), Similarity(z_t, memory.at(id).signature));
  }
}

// tf-idf by hand: N = 4 locations in memory (3 WM + L_t in STM); z_t = {1, 3, 4, 9}.
// Word 1: in L1 and L_t, n_w = 2, idf = log10(4/2); word 3: L1, L2, L_t, idf = log10(4/3);
// word 4: L2, L_t, idf = log10(2); word 9: only L_t (no WM location gains).
TEST(LikelihoodTest, TfIdfScoresByHand) {
  Memory memory(DescriptorKind::kFloat, 2, testing::SmallDictionaryOptions());
  const auto ids = testing::AddChain(memory, {{1, 2, 3}, {3, 4}, {5, 6, 7, 8}, {1, 3, 4, 9}});
  memory.MoveStmOverflowToWm(1);
  const auto scores = ScoreWorkingMemoryTfIdf(memory.at(ids[3]).signature, memory);
  ASSERT_EQ(scores.size(), 3u);
  const double idf2 = std::log10(4.0 / 2), idf3 = std::log10(4.0 / 3);
  EXPECT_NEAR(scores.at(ids[0]), 1.0 / 3 * idf2 + 1.0 / 3 * idf3, 1e-12);  // words 1, 3 of 3
  EXPECT_NEAR(scores.at(ids[1]), 1.0 / 2 * idf3 + 1.0 / 2 * idf2, 1e-12);  // words 3, 4 of 2
  EXPECT_DOUBLE_EQ(scores.at(ids[2]), 0.0);
}

// filter.no_signal_virtual_place (the paper's 2011 code): 2 when no score stands out.
TEST(LikelihoodTest, NoSignalVirtualPlace) {
  // Scores 0.1, 0.2, 0.3: mu 0.2, sigma 0.0816 (population); 0.3 >= mu + sigma = 0.2816 stands
  // out, so eq. 4 stands: 0.2 / 0.0816 + 1 = 3.449.
  const Likelihood signal = ComputeLikelihood({{1, 0.1}, {2, 0.2}, {3, 0.3}}, 0, 2.0);
  EXPECT_NEAR(signal.virtual_place, 0.2 / 0.081649658092772603 + 1, 1e-9);
  // Scores 0.1, 0.1, 0.1, 0.2: mu 0.125, sigma 0.0433; 0.2 >= 0.1683 stands out: eq. 4, 3.887.
  // Scores 0.1, 0.2 (two): mu 0.15, sigma 0.05; 0.2 >= 0.2 stands out too. One standing out is
  // enough; none standing out: 0.1, 0.1 gives sigma 0 (tie), the value 2 whatever eq. 4 says.
  const Likelihood tie = ComputeLikelihood({{1, 0.1}, {2, 0.1}}, 0.1, 2.5);
  EXPECT_DOUBLE_EQ(tie.virtual_place, 2.5);  // without it: 1 / 0.1 + 1 = 11
  EXPECT_DOUBLE_EQ(ComputeLikelihood({{1, 0.1}, {2, 0.1}}, 0.1).virtual_place, 11.0);
  // Nothing scored: no signal either.
  EXPECT_DOUBLE_EQ(ComputeLikelihood({{1, 0.0}, {2, 0.0}}, 0, 2.0).virtual_place, 2.0);
  // The likelihoods of the locations are eq. 3's whatever the option.
  EXPECT_NEAR(signal.values.at(3), (0.3 - 0.081649658092772603) / 0.2, 1e-9);
  EXPECT_DOUBLE_EQ(signal.values.at(1), 1.0);
}

}  // namespace
}  // namespace memloop
