#include "memloop/evaluation.h"

#include <gtest/gtest.h>

#include <set>

namespace memloop {
namespace {

// Ground truth over `size` images with the given (query, match) loop pairs.
GroundTruth TruthOf(int size, const std::set<std::pair<int, int>>& pairs) {
  cv::Mat labels(size, size, CV_8U, cv::Scalar(GroundTruth::kNone));
  for (const auto& [query, match] : pairs)
    labels.at<unsigned char>(query, match) = GroundTruth::kLoop;
  return GroundTruth(labels);
}

TEST(EvaluationTest, HandMadeCase) {
  // Ground truth: 5 ~ 1, 6 ~ 1, 6 ~ 2, 8 ~ 3. Images with a loop: 5, 6, 8.
  const GroundTruth truth = TruthOf(10, {{5, 1}, {6, 1}, {6, 2}, {8, 3}});
  const std::vector<Detection> detections = {
      {5, {1}},     // true
      {6, {4, 2}},  // true: the matched location stands for images 4 and 2
      {7, {3}},     // false: image 7 has no loop
      {8, {2}},     // false: wrong place
  };
  const PrecisionRecall score = Evaluate(detections, truth);
  EXPECT_EQ(score.detections, 4);
  EXPECT_EQ(score.true_positives, 2);
  EXPECT_EQ(score.false_positives, 2);
  EXPECT_EQ(score.loop_images, 3);
  EXPECT_DOUBLE_EQ(score.Precision(), 0.5);
  EXPECT_DOUBLE_EQ(score.Recall(), 2.0 / 3);
}

TEST(EvaluationTest, NoDetectionIsFullPrecisionAndNoRecall) {
  const PrecisionRecall score = Evaluate({}, TruthOf(4, {{3, 0}}));
  EXPECT_DOUBLE_EQ(score.Precision(), 1.0);
  EXPECT_DOUBLE_EQ(score.Recall(), 0.0);
  EXPECT_EQ(score.loop_images, 1);
}

}  // namespace
}  // namespace memloop

namespace memloop {
namespace {

RunRow Row(ImageIndex image, std::vector<ImageIndex> matched, double value,
           std::vector<ImageIndex> hypothesis) {
  RunRow row;
  row.image = image;
  row.matched_images = std::move(matched);
  row.hypothesis_id = hypothesis.empty() ? kNoLocation : 1;
  row.hypothesis_value = value;
  row.hypothesis_images = std::move(hypothesis);
  row.iteration_ms = image * 10.0;
  row.wm_size = image;
  row.dictionary_size = 100 * image;
  return row;
}

// 7 images. Loops: 3 ~ 0, 4 ~ 1, 5 ~ 2; (6, 0) ignored. Images with a loop: 3, 4, 5.
GroundTruth SmallTruth() {
  cv::Mat labels(7, 7, CV_8U, cv::Scalar(GroundTruth::kNone));
  labels.at<unsigned char>(3, 0) = GroundTruth::kLoop;
  labels.at<unsigned char>(4, 1) = GroundTruth::kLoop;
  labels.at<unsigned char>(5, 2) = GroundTruth::kLoop;
  labels.at<unsigned char>(6, 0) = GroundTruth::kIgnored;
  return GroundTruth(labels);
}

// A hypothesis refused whatever T_loop (WM below T_minHyp, failed verification or support) is
// not a point of the curve: here image 2's false 0.30 no longer hides image 5's true one.
TEST(EvaluateRunTest, IneligibleHypothesesAreLeftOutOfTheCurve) {
  std::vector<RunRow> rows = {
      Row(0, {}, 0, {}),      Row(1, {}, 0.05, {0}),        Row(2, {}, 0.30, {1}),
      Row(3, {0}, 0.90, {0}), Row(4, {2, 1}, 0.50, {2, 1}), Row(5, {}, 0.30, {2})};
  rows[2].hypothesis_eligible = false;
  const RunEvaluation e = EvaluateRun(rows, SmallTruth());
  ASSERT_EQ(e.curve.size(), 4u);  // 0.9, 0.5, 0.3, 0.05
  EXPECT_DOUBLE_EQ(e.recall_at_full_precision, 1.0);
  EXPECT_DOUBLE_EQ(e.threshold_at_full_precision, 0.3);
}

// Iteration times 0, 10, ..., 60 ms. With T_time 25 ms: 30, 40, 50, 60 are over (4 of 7), the
// longest is 60 / 25 = 2.4 x T_time; the median is 30 ms.
TEST(EvaluateRunTest, TimeBoundCountsIterationsOverTheTimeLimit) {
  std::vector<RunRow> rows;
  for (int image = 0; image < 7; ++image) rows.push_back(Row(image, {}, 0, {}));
  const RunEvaluation bounded = EvaluateRun(rows, SmallTruth(), 25);
  EXPECT_DOUBLE_EQ(bounded.median_iteration_ms, 30);
  EXPECT_DOUBLE_EQ(bounded.max_iteration_ms, 60);
  EXPECT_EQ(bounded.iterations_over_time_limit, 4);
  EXPECT_DOUBLE_EQ(bounded.FractionOverTimeLimit(), 4.0 / 7);
  EXPECT_DOUBLE_EQ(bounded.max_over_time_limit, 2.4);
  const RunEvaluation exactly = EvaluateRun(rows, SmallTruth(), 60);  // at T_time is not over
  EXPECT_EQ(exactly.iterations_over_time_limit, 0);
  EXPECT_DOUBLE_EQ(exactly.max_over_time_limit, 1.0);
  const RunEvaluation unbounded = EvaluateRun(rows, SmallTruth());
  EXPECT_EQ(unbounded.iterations_over_time_limit, 0);
  EXPECT_DOUBLE_EQ(unbounded.max_over_time_limit, 0);
}

// The floor under T_time: iterations 0, 10, ..., 60 ms of which WM's stages took 0, 1, ..., 6 ms
// (image k: 10k and k): fixed costs 0, 9, 18, 27, 36, 45, 54, median 27 ms.
TEST(EvaluateRunTest, FixedCostIsTheMedianOutsideWmsStages) {
  std::vector<RunRow> rows;
  for (int image = 0; image < 7; ++image) {
    rows.push_back(Row(image, {}, 0, {}));
    rows.back().wm_stages_ms = image;
  }
  EXPECT_DOUBLE_EQ(EvaluateRun(rows, SmallTruth(), 25).median_fixed_ms, 27);
}

// Iterations 0, 10, ..., 60 ms whose thread ran 0, 9, 4, 27, 10, 45, 6 ms of them: shares
// (0 / 0 left out) 0.9, 0.2, 0.9, 0.25, 0.9, 0.1; sorted, the upper middle of six is 0.9.
// Over T_time 25 ms: 30 (0.9), 40 (0.25), 50 (0.9), 60 (0.1): two under half the time.
TEST(EvaluateRunTest, IterationsOverTheTimeLimitThatWaitedAreCounted) {
  const std::vector<double> cpu = {0, 9, 4, 27, 10, 45, 6};
  std::vector<RunRow> rows;
  for (int image = 0; image < 7; ++image) {
    rows.push_back(Row(image, {}, 0, {}));
    rows.back().cpu_ms = cpu[image];
  }
  const RunEvaluation e = EvaluateRun(rows, SmallTruth(), 25);
  EXPECT_EQ(e.iterations_over_time_limit, 4);
  EXPECT_EQ(e.over_time_limit_waiting, 2);
  EXPECT_DOUBLE_EQ(e.median_cpu_share, 0.9);
  for (RunRow& row : rows) row.cpu_ms = -1;  // a CSV without the column
  const RunEvaluation unknown = EvaluateRun(rows, SmallTruth(), 25);
  EXPECT_EQ(unknown.over_time_limit_waiting, 0);
  EXPECT_DOUBLE_EQ(unknown.median_cpu_share, -1);
}

TEST(MedianCpuShareTest, MedianOfCpuOverWallUnknownWhenNeverMeasured) {
  EXPECT_DOUBLE_EQ(MedianCpuShare({{3, 10}, {9, 10}, {5, 10}}), 0.5);
  EXPECT_DOUBLE_EQ(MedianCpuShare({{12, 10}}), 1.0);         // clocks of different grain: at most 1
  EXPECT_DOUBLE_EQ(MedianCpuShare({{0, 10}, {0, 12}}), -1);  // no thread clock on this system
  EXPECT_DOUBLE_EQ(MedianCpuShare({}), -1);
}

TEST(EvaluateRunTest, HandComputedCurveWithTiesMergedLocationsAndIgnoredPairs) {
  const std::vector<RunRow> rows = {
      Row(0, {}, 0, {}),
      Row(1, {}, 0.05, {0}),         // false (no loop for image 1), below everything
      Row(2, {}, 0.30, {1}),         // false, tied with image 5's value
      Row(3, {0}, 0.90, {0}),        // accepted, true
      Row(4, {2, 1}, 0.50, {2, 1}),  // accepted, true through the merged image 1
      Row(5, {}, 0.30, {2}),         // true, tied with image 2
      Row(6, {0}, 0.70, {0}),        // accepted on an ignored pair
  };
  const RunEvaluation e = EvaluateRun(rows, SmallTruth());
  EXPECT_EQ(e.accepted.loop_images, 3);
  EXPECT_EQ(e.accepted.detections, 2);
  EXPECT_EQ(e.accepted.true_positives, 2);
  EXPECT_EQ(e.accepted.false_positives, 0);
  EXPECT_EQ(e.accepted.ignored, 1);
  EXPECT_DOUBLE_EQ(e.accepted.Recall(), 2.0 / 3);
  // Sorted values: 0.9 (T), 0.7 (ignored), 0.5 (T), 0.3 (F and T together), 0.05 (F).
  ASSERT_EQ(e.curve.size(), 5u);
  const double expected[5][4] = {// threshold, TP, FP, recall
                                 {0.9, 1, 0, 1.0 / 3},
                                 {0.7, 1, 0, 1.0 / 3},
                                 {0.5, 2, 0, 2.0 / 3},
                                 {0.3, 3, 1, 1.0},
                                 {0.05, 3, 2, 1.0}};
  for (int i = 0; i < 5; ++i) {
    EXPECT_DOUBLE_EQ(e.curve[i].threshold, expected[i][0]) << i;
    EXPECT_EQ(e.curve[i].true_positives, expected[i][1]) << i;
    EXPECT_EQ(e.curve[i].false_positives, expected[i][2]) << i;
    EXPECT_DOUBLE_EQ(e.curve[i].recall, expected[i][3]) << i;
  }
  EXPECT_DOUBLE_EQ(e.curve[3].precision, 0.75);
  // The tie at 0.3 cannot be split: the best recall without a false positive is at 0.5.
  EXPECT_DOUBLE_EQ(e.recall_at_full_precision, 2.0 / 3);
  EXPECT_DOUBLE_EQ(e.threshold_at_full_precision, 0.5);
  // Table 1.
  EXPECT_EQ(e.images, 7);
  EXPECT_EQ(e.max_wm_size, 6);
  EXPECT_EQ(e.max_dictionary_size, 600);
  EXPECT_DOUBLE_EQ(e.max_iteration_ms, 60);
}

// --ignored-as-true (the paper's 2011 protocol): SmallTruth() with (5, 1) ignored too. Image 5 has
// a true match (2), so its ignored pair becomes a loop; image 6 has none, so its ignored (6, 0)
// stays ignored and the images with a loop stay 3, 4, 5.
TEST(EvaluateRunTest, IgnoredAsTrueCountsTheIgnoredBandOfImagesWithALoop) {
  cv::Mat labels(7, 7, CV_8U, cv::Scalar(GroundTruth::kNone));
  labels.at<unsigned char>(3, 0) = GroundTruth::kLoop;
  labels.at<unsigned char>(4, 1) = GroundTruth::kLoop;
  labels.at<unsigned char>(5, 2) = GroundTruth::kLoop;
  labels.at<unsigned char>(5, 1) = GroundTruth::kIgnored;
  labels.at<unsigned char>(6, 0) = GroundTruth::kIgnored;
  const GroundTruth strict(labels);
  const GroundTruth lenient = strict.IgnoredAsLoops();
  EXPECT_EQ(lenient.At(5, 1), GroundTruth::kLoop);
  EXPECT_EQ(lenient.At(1, 5), GroundTruth::kLoop);  // symmetric
  EXPECT_EQ(lenient.At(6, 0), GroundTruth::kIgnored);
  EXPECT_EQ(lenient.PairCount(), 4);
  const std::vector<RunRow> rows = {
      Row(0, {}, 0, {}),      Row(1, {}, 0.05, {0}),        Row(2, {}, 0.30, {1}),
      Row(3, {0}, 0.90, {0}), Row(4, {2, 1}, 0.50, {2, 1}), Row(5, {1}, 0.60, {1}),
      Row(6, {0}, 0.70, {0})};
  const RunEvaluation before = EvaluateRun(rows, strict);
  const RunEvaluation after = EvaluateRun(rows, lenient);
  EXPECT_EQ(before.accepted.true_positives, 2);  // 3, 4; 5 and 6 on ignored pairs
  EXPECT_EQ(before.accepted.ignored, 2);
  EXPECT_EQ(after.accepted.loop_images, 3);
  EXPECT_EQ(after.accepted.true_positives, 3);  // 3, 4 and 5
  EXPECT_EQ(after.accepted.ignored, 1);         // 6
  EXPECT_DOUBLE_EQ(after.accepted.Recall(), 1.0);
  // Sorted: 0.9 T, 0.7 ignored, 0.6 (5: ignored -> T), 0.5 T, 0.3 F, 0.05 F.
  EXPECT_DOUBLE_EQ(before.recall_at_full_precision, 2.0 / 3);
  EXPECT_DOUBLE_EQ(after.recall_at_full_precision, 1.0);
  EXPECT_DOUBLE_EQ(after.threshold_at_full_precision, 0.5);
}

}  // namespace
}  // namespace memloop
