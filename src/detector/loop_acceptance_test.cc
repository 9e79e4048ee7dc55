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
    LoopAcceptance acceptance(options_, map_.memory, map_.ltm, nullptr);
    Hypothesis hypothesis = OnL1(value);
    int inliers = -1;
    acceptance.Check({z_t_, z_t_, merged, nullptr, likelihood_, nullptr, keypoints_},
                     previous_value, hypothesis, &inliers);
    EXPECT_EQ(inliers, -1);  // verification is off
    return hypothesis;
  }

  testing::SmallMap map_;
  std::vector<LocationId> ids_;
  Options options_;
  Likelihood likelihood_;
  Signature z_t_ = testing::MakeSignature({1, 2, 3});
  DescribedView keypoints_;
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
    LoopAcceptance acceptance(options, map.memory, map.ltm, nullptr);
    Hypothesis hypothesis;
    hypothesis.id = ids[0];
    hypothesis.value = 0.2;
    hypothesis.eligible = hypothesis.accepted = true;
    double previous = 0;
    int inliers = -1;
    acceptance.Check({z_t, z_t, true, &own, likelihood, nullptr, {}}, previous, hypothesis,
                     &inliers);
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

// verify.loop_threshold (T_verified 0.05 under T_loop 0.11): L1 (40 words) and the image see one
// rigid scene, L3 the same words shuffled. Between the thresholds a hypothesis is a loop closure
// only when verified; over T_loop without verification; under T_verified never.
class TwoThresholdTest : public ::testing::Test {
 protected:
  TwoThresholdTest() {
    std::vector<WordId> words;
    for (WordId w = 1; w <= 40; ++w) words.push_back(w);
    ids_ = testing::AddChain(map_.memory, {words, {41}, words});
    map_.memory.MoveStmOverflowToWm(0);
    z_t_ = testing::MakeSignature(words);
    z_t_.keypoints.clear();
    for (LocationId id : {ids_[0], ids_[2]}) map_.memory.at(id).signature.keypoints.clear();
    cv::RNG rng(3);
    for (int k = 0; k < 40; ++k) {  // a sideways step of the camera in a 640x480 image
      const cv::Point3d p(rng.uniform(-2.0, 2.0), rng.uniform(-1.5, 1.5), rng.uniform(4.0, 9.0));
      const auto project = [&](double shift) {
        return cv::KeyPoint(static_cast<float>(320 + 500 * (p.x - shift) / p.z),
                            static_cast<float>(240 + 500 * p.y / p.z), 10.f);
      };
      z_t_.keypoints.push_back(project(0.0));
      map_.memory.at(ids_[0]).signature.keypoints.push_back(project(0.5));
      map_.memory.at(ids_[2]).signature.keypoints.emplace_back(rng.uniform(0.f, 640.f),
                                                               rng.uniform(0.f, 480.f), 10.f);
    }
    keypoints_.image_size = {640, 480};
    options_.filter.ltm_neighbour_check = 0;
    options_.filter.neighbour_range = 1;
    options_.filter.min_shared_words = 0;  // L2 shares none of the image's words
    options_.verification.min_inliers = 8;
    options_.verification.loop_threshold = 0.05;
    options_.verification.max_false_alarms = 1;
    options_.verification.correspondences = "words";
    options_.verification.previous_agrees = 0;  // its own test
    for (LocationId id : ids_) likelihood_.values[id] = 2.0;
    likelihood_.mean = 0.1;
  }

  Hypothesis Check(LoopAcceptance& acceptance, LocationId id, double value, int* inliers) {
    Hypothesis hypothesis;
    hypothesis.id = id;
    hypothesis.value = value;
    hypothesis.eligible = true;
    hypothesis.accepted = value > options_.filter.loop_threshold;
    double previous = 0;
    *inliers = -1;
    acceptance.Check({z_t_, z_t_, false, nullptr, likelihood_, nullptr, keypoints_}, previous,
                     hypothesis, inliers);
    return hypothesis;
  }

  testing::SmallMap map_;
  std::vector<LocationId> ids_;
  Options options_;
  Likelihood likelihood_;
  Signature z_t_;
  DescribedView keypoints_;
};

TEST_F(TwoThresholdTest, BetweenTheThresholdsOnlyAVerifiedHypothesisIsALoopClosure) {
  LoopAcceptance acceptance(options_, map_.memory, map_.ltm, nullptr);
  int inliers = -1;
  Hypothesis hypothesis = Check(acceptance, ids_[0], 0.08, &inliers);
  EXPECT_TRUE(hypothesis.accepted);
  EXPECT_GE(inliers, 38);
  hypothesis = Check(acceptance, ids_[2], 0.08, &inliers);  // the words, shuffled
  EXPECT_FALSE(hypothesis.accepted);
  EXPECT_TRUE(hypothesis.eligible);  // its value stays in the curves: the sweep is T_loop's
  EXPECT_GE(inliers, 0);
  hypothesis = Check(acceptance, ids_[2], 0.2, &inliers);  // over T_loop: the paper's decision
  EXPECT_TRUE(hypothesis.accepted);
  EXPECT_EQ(inliers, -1);
  hypothesis = Check(acceptance, ids_[0], 0.04, &inliers);  // under T_verified
  EXPECT_FALSE(hypothesis.accepted);
  EXPECT_EQ(inliers, -1);
}

TEST_F(TwoThresholdTest, TooManyFalseAlarmsRefuseWhatTheInlierCountAccepts) {
  options_.verification.max_false_alarms = 1e-200;  // 40 exact inliers in 640x480: ~1e-110
  LoopAcceptance acceptance(options_, map_.memory, map_.ltm, nullptr);
  int inliers = -1;
  EXPECT_FALSE(Check(acceptance, ids_[0], 0.08, &inliers).accepted);
  EXPECT_GE(inliers, 38);
  options_.verification.max_false_alarms = 0;  // not checked: the count decides
  LoopAcceptance counting(options_, map_.memory, map_.ltm, nullptr);
  EXPECT_TRUE(Check(counting, ids_[0], 0.08, &inliers).accepted);
}

// verify.previous_agrees: the previous image's hypothesis over T_verified within
// filter.neighbour_range (1) links of L_i. L3 is two links from L1.
TEST_F(TwoThresholdTest, PreviousImageMustAgreeWhenAsked) {
  options_.verification.previous_agrees = 1;
  LoopAcceptance acceptance(options_, map_.memory, map_.ltm, nullptr);
  int inliers = -1;
  EXPECT_FALSE(Check(acceptance, ids_[0], 0.08, &inliers).accepted);  // no previous image
  EXPECT_TRUE(Check(acceptance, ids_[0], 0.08, &inliers).accepted);   // L1 again
  EXPECT_TRUE(Check(acceptance, ids_[1], 0.2, &inliers).accepted);    // L2, over T_loop
  EXPECT_TRUE(Check(acceptance, ids_[0], 0.08, &inliers).accepted);   // L2 is L1's neighbour
  Check(acceptance, ids_[2], 0.06, &inliers);                         // L3, refused, over 0.05
  EXPECT_FALSE(Check(acceptance, ids_[0], 0.08, &inliers).accepted);  // L3 is 2 links away
  Check(acceptance, ids_[0], 0.03, &inliers);                         // L1, under T_verified
  EXPECT_FALSE(Check(acceptance, ids_[0], 0.08, &inliers).accepted);
}

// verify.previous_agrees = 2: the previous image's hypothesis near L_i was a loop closure or was
// verified; over T_verified is not enough.
TEST_F(TwoThresholdTest, PreviousImageMustHaveBeenVerifiedAtLevelTwo) {
  options_.verification.previous_agrees = 2;
  LoopAcceptance acceptance(options_, map_.memory, map_.ltm, nullptr);
  int inliers = -1;
  EXPECT_FALSE(Check(acceptance, ids_[0], 0.08, &inliers).accepted);  // none before: verified
  EXPECT_TRUE(Check(acceptance, ids_[0], 0.08, &inliers).accepted);   // after a verified one
  EXPECT_FALSE(Check(acceptance, ids_[1], 0.06, &inliers).accepted);  // L2 shares no word
  EXPECT_FALSE(Check(acceptance, ids_[0], 0.08, &inliers).accepted);  // L2 was not verified
  EXPECT_TRUE(Check(acceptance, ids_[1], 0.2, &inliers).accepted);    // L2 over T_loop
  EXPECT_TRUE(Check(acceptance, ids_[0], 0.08, &inliers).accepted);   // a loop closure before
}

}  // namespace
}  // namespace memloop
