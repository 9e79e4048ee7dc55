#include "detector/loop_acceptance.h"

#include <gtest/gtest.h>

#include "small_map.h"

namespace memloop {
namespace {

// A chain L1 .. L5 whose L2, L3 and L4 are in LTM: L1 (words 1, 2, 3) links to L2 in LTM.
class LoopAcceptanceTest : public ::testing::Test {
 protected:
  LoopAcceptanceTest() {
    ids_ = map_.ChainWithMiddleInLtm({{1, 2, 3}, {4}, {5}, {6}, {8, 9, 10}});
    options_.filter.ltm_neighbour_check = 0;  // on in one test only
    likelihood_.values[ids_[0]] = 2.0;        // eq. 3: L1 stands out
    likelihood_.mean = 0.1;
  }

  // The highest hypothesis L1 at `value`, eligible, accepted over T_loop (0.11).
  Hypothesis OnL1(double value) const {
    Hypothesis hypothesis;
    hypothesis.id = ids_[0];
    hypothesis.value = value;
    hypothesis.eligible = true;
    hypothesis.accepted = value > options_.filter.loop_threshold;
    return hypothesis;
  }

  // Runs the checks on an image whose words are `z_t`: the hypothesis after them.
  Hypothesis Check(double value, bool merged, double& previous_value) const {
    const LoopAcceptance acceptance(options_, map_.memory, map_.ltm, nullptr);
    Hypothesis hypothesis = OnL1(value);
    int inliers = -1;
    acceptance.Check({z_t_, z_t_, merged, nullptr, likelihood_, nullptr}, previous_value,
                     hypothesis, &inliers);
    EXPECT_EQ(inliers, -1);  // verification is off
    return hypothesis;
  }

  testing::SmallMap map_;
  std::vector<LocationId> ids_;
  Options options_;
  Likelihood likelihood_;
  Signature z_t_ = testing::MakeSignature({1, 2, 3});
};

TEST_F(LoopAcceptanceTest, SupportedHypothesisOverTLoopIsAcceptedAndBecomesThePreviousValue) {
  double previous = 0.05;
  const Hypothesis hypothesis = Check(0.2, false, previous);
  EXPECT_TRUE(hypothesis.accepted);
  EXPECT_DOUBLE_EQ(hypothesis.value, 0.2);
  EXPECT_DOUBLE_EQ(previous, 0.2);
}

TEST_F(LoopAcceptanceTest, MergedImageIsCappedAtThePreviousValueWhenTheCapIsOn) {
  options_.filter.cap_merged_images = 1;
  double previous = 0.05;
  Hypothesis hypothesis = Check(0.2, true, previous);
  EXPECT_FALSE(hypothesis.accepted);  // 0.05 <= T_loop 0.11: it does not start a loop closure
  EXPECT_DOUBLE_EQ(hypothesis.value, 0.05);
  EXPECT_DOUBLE_EQ(previous, 0.05);  // the capped value is what the next image compares with
  previous = 0.15;
  hypothesis = Check(0.2, true, previous);
  EXPECT_TRUE(hypothesis.accepted);  // 0.15 > 0.11: it keeps one
  EXPECT_DOUBLE_EQ(hypothesis.value, 0.15);
  previous = 0.05;
  EXPECT_TRUE(Check(0.2, false, previous).accepted);  // the image's own words: no cap
  options_.filter.cap_merged_images = 0;
  previous = 0.05;
  EXPECT_TRUE(Check(0.2, true, previous).accepted);  // the paper
}

TEST_F(LoopAcceptanceTest, HypothesisWithoutSupportOrWithTooFewSharedWordsIsRefused) {
  double previous = 0;
  likelihood_.values[ids_[0]] = 0.9;  // eq. 3 under 1: carried by the prior alone
  EXPECT_FALSE(Check(0.2, false, previous).accepted);
  EXPECT_DOUBLE_EQ(previous, 0.2);  // refused, it keeps its value for the curves
  options_.filter.require_support = 0;
  EXPECT_TRUE(Check(0.2, false, previous).accepted);
  z_t_ = testing::MakeSignature({1, 2, 11});  // two words shared with L1, three needed
  EXPECT_FALSE(Check(0.2, false, previous).accepted);
  options_.filter.min_shared_words = 2;
  EXPECT_TRUE(Check(0.2, false, previous).accepted);
}

TEST_F(LoopAcceptanceTest, LoopRatioComparesWithThePreviousImagesValue) {
  options_.filter.loop_ratio = 0.9;
  double previous = 0.2;
  EXPECT_FALSE(Check(0.15, false, previous).accepted);  // 0.15 < 0.9 x 0.2 = 0.18
  EXPECT_DOUBLE_EQ(previous, 0.15);
  EXPECT_TRUE(Check(0.14, false, previous).accepted);  // 0.14 >= 0.9 x 0.15 = 0.135
}

TEST_F(LoopAcceptanceTest, LinkedLocationInLtmRefusesWithoutDescriptionsToCompare) {
  double previous = 0;
  EXPECT_TRUE(Check(0.2, false, previous).accepted);
  options_.filter.ltm_neighbour_check = 1;  // L2, linked to L1, is in LTM
  EXPECT_FALSE(Check(0.2, false, previous).accepted);
}

// filter.support_from_image on an image Rehearsal merged into L1's words: its own words share
// none with L1 but 3 of 4 with L2, linked to L1 (eq. 1: 3 / max(4, 4) = 0.75 >= mu 0.1).
TEST(LoopAcceptanceOwnWordsTest, MergedImageNamesTheLinkedPlaceItsOwnWordsSupport) {
  testing::SmallMap map;
  const std::vector<LocationId> ids =
      testing::AddChain(map.memory, {{1, 2, 3}, {4, 5, 6, 7}, {8, 9, 10, 11}});
  map.memory.MoveStmOverflowToWm(0);
  Options options;
  options.filter.ltm_neighbour_check = 0;
  Likelihood likelihood;
  likelihood.values[ids[0]] = 2.0;  // eq. 3: L1 stands out for the merged words
  likelihood.mean = 0.1;
  const Signature z_t = testing::MakeSignature({1, 2, 3});  // L1's words, after the merge
  const auto check = [&](const Signature& own) {
    const LoopAcceptance acceptance(options, map.memory, map.ltm, nullptr);
    Hypothesis hypothesis;
    hypothesis.id = ids[0];
    hypothesis.value = 0.2;
    hypothesis.eligible = hypothesis.accepted = true;
    double previous = 0;
    int inliers = -1;
    acceptance.Check({z_t, z_t, true, &own, likelihood, nullptr}, previous, hypothesis, &inliers);
    return hypothesis;
  };
  const Signature sees_l2 = testing::MakeSignature({4, 5, 6, 12});
  const Signature sees_l3 = testing::MakeSignature({8, 9, 10, 12});  // two links from L1

  options.filter.support_from_image = 2;
  Hypothesis hypothesis = check(sees_l2);
  EXPECT_TRUE(hypothesis.accepted);
  EXPECT_EQ(hypothesis.id, ids[1]);
  EXPECT_FALSE(check(sees_l3).eligible);
  hypothesis = check(testing::MakeSignature({1, 2, 3, 12}));  // its own words support L1 itself
  EXPECT_TRUE(hypothesis.accepted);
  EXPECT_EQ(hypothesis.id, ids[0]);

  options.filter.support_from_image = 1;  // L1 alone: refused
  EXPECT_FALSE(check(sees_l2).eligible);
  options.filter.support_from_image = 0;  // the paper: the merged words decide
  hypothesis = check(sees_l2);
  EXPECT_TRUE(hypothesis.accepted);
  EXPECT_EQ(hypothesis.id, ids[0]);
}

}  // namespace
}  // namespace memloop
