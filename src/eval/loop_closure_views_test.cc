#include "eval/loop_closure_views.h"

#include <gtest/gtest.h>

#include "memloop/evaluation.h"

namespace memloop {
namespace {

RunRow Row(ImageIndex image, std::vector<ImageIndex> matched) {
  RunRow row;
  row.image = image;
  row.name = std::to_string(image) + ".png";
  row.matched_images = std::move(matched);
  row.hypothesis_value = 0.5;
  return row;
}

// The figure's points are eval's verdicts: a loop closure on an ignored pair is not a false
// positive (before, the report drew tum_fr1_rpy's 84 such as red crosses while eval counted 0).
TEST(LoopClosureViewsTest, AcceptedLoopClosuresAreJudgedAsEvalJudgesThem) {
  cv::Mat labels = cv::Mat::zeros(6, 6, CV_8U);
  labels.at<unsigned char>(3, 0) = GroundTruth::kLoop;
  labels.at<unsigned char>(4, 1) = GroundTruth::kIgnored;
  labels.at<unsigned char>(5, 1) = GroundTruth::kIgnored;
  labels.at<unsigned char>(5, 2) = GroundTruth::kLoop;
  const GroundTruth truth(labels);
  std::vector<RunRow> rows;
  for (ImageIndex image = 0; image < 6; ++image) rows.push_back(Row(image, {}));
  rows[2].matched_images = {0};     // false
  rows[3].matched_images = {0};     // true
  rows[4].matched_images = {1};     // on an ignored pair
  rows[5].matched_images = {1, 2};  // true through its second image

  const std::vector<LoopClosureView> views = AcceptedLoopClosures(rows, &truth);
  ASSERT_EQ(views.size(), 4u);
  EXPECT_EQ(views[0].verdict, "false");
  EXPECT_EQ(views[0].match, 0);
  EXPECT_EQ(views[1].verdict, "true");
  EXPECT_EQ(views[2].verdict, "ignored");
  EXPECT_EQ(views[2].match, 1);
  EXPECT_EQ(views[3].verdict, "true");
  EXPECT_EQ(views[3].match, 2);  // the image that makes it true is the one shown
  const RunEvaluation e = EvaluateRun(rows, truth);
  const auto count = [&](const std::string& verdict) {
    return std::count_if(views.begin(), views.end(),
                         [&](const LoopClosureView& view) { return view.verdict == verdict; });
  };
  EXPECT_EQ(count("true"), e.accepted.true_positives);
  EXPECT_EQ(count("false"), e.accepted.false_positives);
  EXPECT_EQ(count("ignored"), e.accepted.ignored);
  // Without ground truth, nothing is judged.
  for (const LoopClosureView& view : AcceptedLoopClosures(rows, nullptr)) {
    EXPECT_EQ(view.verdict, "");
  }
}

// A miss is an image with a true earlier match and no loop closure accepted: it names what its
// highest hypothesis chose (or no earlier place) and its most recent true match. A false positive
// names its true match too; an image accepted on a true pair, or with no true match, is no miss.
TEST(LoopClosureViewsTest, MissesNameTheChoiceAndTheLatestTrueMatch) {
  cv::Mat labels = cv::Mat::zeros(7, 7, CV_8U);
  labels.at<unsigned char>(4, 0) = GroundTruth::kLoop;
  labels.at<unsigned char>(4, 1) = GroundTruth::kLoop;
  labels.at<unsigned char>(5, 2) = GroundTruth::kLoop;
  labels.at<unsigned char>(6, 3) = GroundTruth::kLoop;
  labels.at<unsigned char>(6, 1) = GroundTruth::kIgnored;
  const GroundTruth truth(labels);
  std::vector<RunRow> rows;
  for (ImageIndex image = 0; image < 7; ++image) rows.push_back(Row(image, {}));
  rows[4].hypothesis_images = {3};  // missed: chose 3, its true matches are 0 and 1
  rows[4].hypothesis_value = 0.07;
  rows[5].matched_images = {2};     // found
  rows[6].matched_images = {0};     // false, true match 3
  rows[3].hypothesis_images = {1};  // no true match: not a miss

  const std::vector<LoopClosureView> misses = MissedLoopClosures(rows, truth);
  ASSERT_EQ(misses.size(), 1u);
  EXPECT_EQ(misses[0].query, 4);
  EXPECT_EQ(misses[0].match, 3);
  EXPECT_DOUBLE_EQ(misses[0].probability, 0.07);
  EXPECT_EQ(misses[0].true_match, 1);  // the most recent of 0 and 1
  EXPECT_EQ(misses[0].verdict, "missed");
  const std::vector<LoopClosureView> accepted = AcceptedLoopClosures(rows, &truth);
  ASSERT_EQ(accepted.size(), 2u);
  EXPECT_EQ(accepted[0].true_match, kNoImage);  // true: nothing else to show
  EXPECT_EQ(accepted[1].verdict, "false");
  EXPECT_EQ(accepted[1].true_match, 3);
  // The virtual place as the highest hypothesis: no earlier place chosen.
  rows[4].hypothesis_images.clear();
  EXPECT_EQ(MissedLoopClosures(rows, truth)[0].match, kNoImage);
  // Misses come after false positives, before the others.
  std::vector<LoopClosureView> all = accepted;
  all.insert(all.end(), misses.begin(), misses.end());
  const std::vector<LoopClosureView> order = ChooseViews(all, 10);
  EXPECT_EQ(order[0].verdict, "false");
  EXPECT_EQ(order[1].verdict, "missed");
  EXPECT_EQ(order[2].verdict, "true");
}

TEST(LoopClosureViewsTest, FalsePositivesComeFirstTheOthersSpreadEvenly) {
  std::vector<LoopClosureView> views;
  for (int k = 0; k < 6; ++k) views.push_back({10 + k, k, 0.5, "true"});
  views.push_back({30, 1, 0.5, "false"});
  views.push_back({31, 2, 0.5, "false"});
  const std::vector<LoopClosureView> chosen = ChooseViews(views, 5);
  ASSERT_EQ(chosen.size(), 5u);
  EXPECT_EQ(chosen[0].query, 30);
  EXPECT_EQ(chosen[1].query, 31);
  EXPECT_EQ(chosen[2].query, 10);  // 3 of the 6 true ones: the 1st, 3rd and 5th
  EXPECT_EQ(chosen[3].query, 12);
  EXPECT_EQ(chosen[4].query, 14);
  EXPECT_EQ(ChooseViews(views, 100).size(), views.size());
}

}  // namespace
}  // namespace memloop
