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
