// filter.cap_merged_images on a generated camera that glimpses a wall it mapped and drifts away
// from it. Rehearsal (III-B) merges each drifting image into the glimpse's location and gives it
// the glimpse's words ("z_t is cleared and z_c is copied into z_t"): the filter observes the
// glimpse again and again, and the loop-closure value climbs past T_loop on the same evidence,
// while the camera no longer sees the wall. Ground truth is exact: each image is a crop of one
// panorama, and a loop closure on a place whose crops do not overlap the image's is false.
#include <gtest/gtest.h>

#include "memloop/detector.h"
#include "noise_texture.h"
#include "panorama_crops.h"

namespace memloop {
namespace {

constexpr int kWidth = 320, kHeight = 240;
constexpr int kWallImages = 40;  // the wall, mapped left to right at y = 0, side by side
constexpr int kDrift = 5;        // a glimpse 3/16 over the wall, then 4 steps of H/16 down
constexpr int kAway = 6;         // then places never seen, side by side, far below the wall
// The wall image each glimpse is of: out of STM by then.
const std::vector<int> kGlimpseAt = {3, 11, 19, 27};

std::vector<cv::Rect> Crops() {
  std::vector<cv::Rect> crops;
  for (int i = 0; i < kWallImages; ++i) crops.emplace_back(i * kWidth, 0, kWidth, kHeight);
  int away = 0;
  for (int at : kGlimpseAt) {
    for (int step = 0; step < kDrift; ++step) {
      crops.emplace_back(at * kWidth, (13 + step) * kHeight / 16, kWidth, kHeight);
    }
    for (int i = 0; i < kAway; ++i, ++away) {
      crops.emplace_back(away * kWidth, 3 * kHeight, kWidth, kHeight);
    }
  }
  return crops;
}

struct DriftRun {
  // Loop closures on a location whose images' crops do not overlap the image's, on images that
  // Rehearsal merged (the drift) and on the others.
  int merged_false_positives = 0;
  int other_false_positives = 0;
};

DriftRun RunDrifts(bool cap_merged_images, int support_from_image) {
  const std::vector<cv::Rect> crops = Crops();
  const cv::Mat panorama =
      testing::NoiseTexture(cv::Size(kWallImages * kWidth, 4 * kHeight), 29, 2.0);
  Options options;
  options.filter.cap_merged_images = cap_merged_images;
  options.filter.support_from_image = support_from_image;
  DriftRun run;
  for (const Result& result : testing::RunCrops(options, panorama, crops).loop_closures) {
    if (testing::BestOverlap(crops, result) > 0) continue;
    ++(result.rehearsal_merged_id != kNoLocation ? run.merged_false_positives
                                                 : run.other_false_positives);
  }
  return run;
}

TEST(RepeatedEvidenceTest, AMergedImageDoesNotStartALoopClosureOnWhatItNoLongerSees) {
  // The cap alone: the merged words decide support, as the paper (filter.support_from_image 0).
  const DriftRun repeated = RunDrifts(false, 0);
  const DriftRun capped = RunDrifts(true, 0);
  const DriftRun own_words = RunDrifts(false, 2);  // the default: the image's own words too
  std::cout << "drifting images closed on the wall: " << repeated.merged_false_positives
            << " (value as the filter gives it), " << capped.merged_false_positives << " (capped), "
            << own_words.merged_false_positives
            << " (the image's own words); other false positives " << repeated.other_false_positives
            << " / " << capped.other_false_positives << " / " << own_words.other_false_positives
            << "\n";
  // Measured: 8 -> 0 (capped), 0 (own words). The premise: the glimpse's words, observed again
  // and again, carry the value past T_loop on images that show none of the wall.
  EXPECT_GE(repeated.merged_false_positives, 4);
  EXPECT_EQ(capped.merged_false_positives, 0);
  EXPECT_EQ(own_words.merged_false_positives, 0);
  // The cap leaves the filter as the paper has it: the first unseen place after a drift starts
  // from the posterior the repeated evidence built, and its own chance words (a noise texture)
  // can then support the wall. Measured: 1 in both runs. Not more with the cap.
  EXPECT_LE(capped.other_false_positives, repeated.other_false_positives);
}

}  // namespace
}  // namespace memloop
