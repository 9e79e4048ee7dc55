#include "detector/hypothesis.h"

#include <gtest/gtest.h>

namespace memloop {
namespace {

// 1 - 2 - 3 - 4 in a line, 10 alone.
Neighbourhoods Graph() {
  Neighbourhoods graph;
  graph[1] = {{1, 0}, {2, 1}, {3, 2}, {4, 3}};
  graph[2] = {{2, 0}, {1, 1}, {3, 1}, {4, 2}};
  graph[3] = {{3, 0}, {2, 1}, {4, 1}, {1, 2}};
  graph[4] = {{4, 0}, {3, 1}, {2, 2}, {1, 3}};
  graph[10] = {{10, 0}};
  return graph;
}

const IdMap<double> kPosterior = {{1, 0.05}, {2, 0.3}, {3, 0.1}, {4, 0.02}, {10, 0.25}};

FilterOptions Neighbours() {
  FilterOptions options;
  options.hypothesis_value = "neighbours";  // the paper's value
  options.loop_threshold = 0.1;
  return options;
}

TEST(HypothesisTest, HighestPosteriorWithItsNeighboursSummed) {
  FilterOptions options = Neighbours();
  options.min_hypotheses = 5;
  const Hypothesis hypothesis = SelectHypothesis(kPosterior, 0.5, Graph(), options);
  EXPECT_EQ(hypothesis.id, 2);
  EXPECT_NEAR(hypothesis.value, 0.05 + 0.3 + 0.1 + 0.02, 1e-12);  // 0.47
  EXPECT_TRUE(hypothesis.accepted);                               // 0.47 > T_loop = 0.1
}

TEST(HypothesisTest, NotAcceptedBelowTLoopOrWithTooFewHypotheses) {
  FilterOptions options = Neighbours();
  options.min_hypotheses = 5;
  options.loop_threshold = 0.5;
  EXPECT_FALSE(SelectHypothesis(kPosterior, 0.5, Graph(), options).accepted);
  options.loop_threshold = 0.1;
  options.min_hypotheses = 6;  // WM holds 5 < T_minHyp
  const Hypothesis hypothesis = SelectHypothesis(kPosterior, 0.5, Graph(), options);
  EXPECT_FALSE(hypothesis.accepted);
  EXPECT_EQ(hypothesis.id, 2);  // still reported, marked not eligible
  EXPECT_FALSE(hypothesis.eligible);
}

// memloop's default value: 1 - p(virtual place), whatever the neighbourhood.
TEST(HypothesisTest, LoopMassIsOneMinusTheVirtualPlace) {
  FilterOptions options;
  options.hypothesis_value = "loop_mass";
  options.min_hypotheses = 5;
  options.loop_threshold = 0.7;
  Hypothesis hypothesis = SelectHypothesis(kPosterior, 0.28, Graph(), options);
  EXPECT_EQ(hypothesis.id, 2);
  EXPECT_NEAR(hypothesis.value, 0.72, 1e-12);
  EXPECT_TRUE(hypothesis.eligible);
  EXPECT_TRUE(hypothesis.accepted);  // 0.72 > 0.7; the neighbour sum, 0.47, would not be
  hypothesis = SelectHypothesis(kPosterior, 0.31, Graph(), options);
  EXPECT_FALSE(hypothesis.accepted);  // 0.69
}

TEST(HypothesisTest, RangeLimitsTheSum) {
  FilterOptions options = Neighbours();
  options.neighbour_range = 1;
  EXPECT_NEAR(SelectHypothesis(kPosterior, 0.5, Graph(), options).value, 0.05 + 0.3 + 0.1, 1e-12);
}

TEST(HypothesisTest, EmptyWorkingMemoryHasNoHypothesis) {
  const Hypothesis hypothesis = SelectHypothesis({}, 1.0, {}, FilterOptions());
  EXPECT_EQ(hypothesis.id, kNoLocation);
  EXPECT_FALSE(hypothesis.accepted);
}

// z_t = {7, 7, 8, 9} and z_i = {7, 8, 8, 5}: word 7 makes min(2, 1) = 1 pair, word 8 min(1, 2) = 1,
// 9 and 5 none: N_pair = 2.
TEST(HypothesisTest, TooFewSharedWordsRefuse) {
  Signature z_t, z_i;
  z_t.words = {7, 7, 8, 9};
  z_i.words = {7, 8, 8, 5};
  EXPECT_TRUE(SharesWords(z_t, z_i, 2));  // 7 once in common (min(2, 1)), 8 once
  EXPECT_TRUE(SharesWords(z_t, z_i, 0));  // off
  EXPECT_FALSE(SharesWords(z_t, z_i, 3));
}

// The image's own words {1, 2, 3, 4} against z_i = {1, 2, 3, 9, 10, 11}: N_pair = 3, eq. 1
// s = 3 / max(4, 6) = 0.5.
TEST(HypothesisTest, TheImageItselfSupportsLiWhenItsOwnWordsScoreAtLeastTheMean) {
  Signature image, z_i;
  image.words = {1, 2, 3, 4};
  z_i.words = {1, 2, 3, 9, 10, 11};
  EXPECT_TRUE(SupportedByImage(image, z_i, 0.5, 3));
  EXPECT_FALSE(SupportedByImage(image, z_i, 0.51, 3));  // under the mean
  EXPECT_FALSE(SupportedByImage(image, z_i, 0.1, 4));   // 3 shared words, 4 asked
  Signature elsewhere;
  elsewhere.words = {20, 21, 22};
  EXPECT_FALSE(SupportedByImage(elsewhere, z_i, 0, 0));  // s = 0 never supports
}

// L_i = 2 linked to 1 and 3; 3 is in LTM. Image scores: L_i 0.4, 1 0.9 (in WM: not counted).
TEST(HypothesisTest, AnLtmNeighbourThatLooksMoreLikeTheImageRefuses) {
  const auto in_ltm = [](LocationId id) { return id == 3; };
  const auto accepted = [] {
    Hypothesis hypothesis;
    hypothesis.id = 2;
    hypothesis.eligible = hypothesis.accepted = true;
    return hypothesis;
  };
  const auto scored = [](double three) {
    return [three](LocationId id) { return id == 2 ? 0.4 : id == 1 ? 0.9 : three; };
  };
  Hypothesis hypothesis = accepted();
  CheckLtmNeighbours({1, 3}, in_ltm, scored(0.3), hypothesis);  // 3 looks less like it
  EXPECT_TRUE(hypothesis.accepted);
  CheckLtmNeighbours({1, 3}, in_ltm, scored(0.4), hypothesis);  // a tie keeps L_i
  EXPECT_TRUE(hypothesis.accepted);
  CheckLtmNeighbours({1, 3}, in_ltm, scored(0.5), hypothesis);
  EXPECT_FALSE(hypothesis.accepted);
  EXPECT_FALSE(hypothesis.eligible);  // at any T_loop

  hypothesis = accepted();  // without descriptions, any linked LTM location refuses
  CheckLtmNeighbours({1, 3}, in_ltm, nullptr, hypothesis);
  EXPECT_FALSE(hypothesis.accepted);
  hypothesis = accepted();
  CheckLtmNeighbours({1}, in_ltm, nullptr, hypothesis);
  EXPECT_TRUE(hypothesis.accepted);
}

// hypothesis_value "best_neighbours" (the paper's 2011 code): every location's neighbour sum.
TEST(HypothesisTest, BestNeighboursTakesTheHighestSumNamedByItsHighestPosterior) {
  // 1-2-3-4 as Graph(), 5-6 apart: posterior 0.2, 0.02, 0.02, 0.02 | 0.3, 0.25.
  Neighbourhoods graph = Graph();
  graph.erase(10);
  graph[5] = {{5, 0}, {6, 1}};
  graph[6] = {{6, 0}, {5, 1}};
  const IdMap<double> posterior = {{1, 0.2}, {2, 0.02}, {3, 0.02}, {4, 0.02}, {5, 0.3}, {6, 0.25}};
  FilterOptions options = Neighbours();
  options.min_hypotheses = 1;
  options.neighbour_range = 1;
  // Sums within 1 link: 1: 0.22, 2: 0.24, 3: 0.06, 4: 0.04, 5 and 6: 0.55 (5 the older).
  Hypothesis hypothesis = SelectHypothesis(posterior, 0.5, graph, options);
  EXPECT_EQ(hypothesis.id, 5);
  EXPECT_NEAR(hypothesis.value, 0.55, 1e-12);
  // Location 6 alone at 0.31 over 5's 0.3: the highest posterior is 6 and names the sum.
  graph[5] = {{5, 0}};
  graph[6] = {{6, 0}};
  graph[2] = {{2, 0}, {1, 1}, {3, 1}};
  const IdMap<double> spread = {{1, 0.2}, {2, 0.19}, {3, 0.19}, {4, 0.0}, {5, 0.0}, {6, 0.31}};
  options.hypothesis_value = "best_neighbours";
  hypothesis = SelectHypothesis(spread, 0.5, graph, options);
  EXPECT_EQ(hypothesis.id, 1);                 // the sum around 2 (0.58), named by 1 (0.2)
  EXPECT_NEAR(hypothesis.value, 0.58, 1e-12);  // 0.2 + 0.19 + 0.19
  options.hypothesis_value = "neighbours";     // around the highest posterior, 6: 0.31
  hypothesis = SelectHypothesis(spread, 0.5, graph, options);
  EXPECT_EQ(hypothesis.id, 6);
  EXPECT_NEAR(hypothesis.value, 0.31, 1e-12);
}

// filter.loop_ratio (the paper's 2011 code, LoopRatio 0.9).
TEST(HypothesisTest, LoopRatioRefusesAHypothesisBelowTheRatioOfThePreviousOne) {
  FilterOptions options = Neighbours();
  options.min_hypotheses = 5;
  Hypothesis hypothesis = SelectHypothesis(kPosterior, 0.5, Graph(), options);  // 0.47
  RequireLoopRatio(0.52, 0.9, hypothesis);  // 0.47 >= 0.9 * 0.52 = 0.468
  EXPECT_TRUE(hypothesis.accepted);
  RequireLoopRatio(0.53, 0.9, hypothesis);  // 0.47 < 0.477
  EXPECT_FALSE(hypothesis.accepted);
  EXPECT_FALSE(hypothesis.eligible);
  hypothesis = SelectHypothesis(kPosterior, 0.5, Graph(), options);
  RequireLoopRatio(0.0, 0.9, hypothesis);  // no previous hypothesis: refused
  EXPECT_FALSE(hypothesis.accepted);
  hypothesis = SelectHypothesis(kPosterior, 0.5, Graph(), options);
  RequireLoopRatio(0.0, 0.0, hypothesis);  // off
  EXPECT_TRUE(hypothesis.accepted);
}

// filter.cap_merged_images: a merged image's value is at most the previous image's.
TEST(HypothesisTest, AMergedImageKeepsALoopClosureButDoesNotStartOne) {
  FilterOptions options = Neighbours();
  options.min_hypotheses = 5;
  options.loop_threshold = 0.11;
  Hypothesis hypothesis = SelectHypothesis(kPosterior, 0.5, Graph(), options);  // 0.47, accepted
  CapRepeatedObservation(0.1065, 0.11, hypothesis);  // the previous image was under T_loop
  EXPECT_NEAR(hypothesis.value, 0.1065, 1e-12);
  EXPECT_FALSE(hypothesis.accepted);
  EXPECT_TRUE(hypothesis.eligible);  // a lower threshold would accept it: PR curves sweep it
  hypothesis = SelectHypothesis(kPosterior, 0.5, Graph(), options);
  CapRepeatedObservation(0.2, 0.11, hypothesis);  // the previous image was accepted at 0.2
  EXPECT_NEAR(hypothesis.value, 0.2, 1e-12);
  EXPECT_TRUE(hypothesis.accepted);
  hypothesis = SelectHypothesis(kPosterior, 0.5, Graph(), options);
  CapRepeatedObservation(0.6, 0.11, hypothesis);  // a value that falls is not raised
  EXPECT_NEAR(hypothesis.value, 0.47, 1e-12);
  EXPECT_TRUE(hypothesis.accepted);
}

// verify.max_roll_degrees: a known roll over the bound refuses, an unknown one does not.
TEST(HypothesisTest, ViewRollOverTheBoundRefuses) {
  FilterOptions options = Neighbours();
  options.min_hypotheses = 5;
  const auto check = [&](double degrees, bool known, double max) {
    ViewRoll roll;
    roll.degrees = degrees;
    roll.known = known;
    Hypothesis hypothesis = SelectHypothesis(kPosterior, 0.5, Graph(), options);
    RequireSimilarRoll(roll, max, hypothesis);
    return hypothesis.accepted;
  };
  EXPECT_TRUE(check(12, true, 18));
  EXPECT_TRUE(check(-18, true, 18));  // at the bound
  EXPECT_FALSE(check(-18.5, true, 18));
  EXPECT_FALSE(check(170, true, 18));
  EXPECT_TRUE(check(40, false, 18));  // unknown: the filter's to carry
  EXPECT_TRUE(check(40, true, 0));    // no check
}

}  // namespace
}  // namespace memloop
