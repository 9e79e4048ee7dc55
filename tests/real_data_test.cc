// Checks on ../shared/datasets when present (a fresh clone has none: the tests skip, saying so).
#include <gtest/gtest.h>

#include <filesystem>
#include <opencv2/imgcodecs.hpp>

#include "memloop/detector.h"
#include "memloop/evaluation.h"
#include "memloop/ground_truth.h"
#include "memloop/image_sequence.h"
#include "temp_dir.h"

namespace memloop {
namespace {

const std::string kSamples = std::string(MEMLOOP_DATASETS) + "/rtabmap_samples";

TEST(RealDataTest, RtabmapSamplesHaveNoFalsePositive) {
  if (!std::filesystem::exists(kSamples + "/images")) {
    GTEST_SKIP() << kSamples << " is absent (it ships beside the project, not in it)";
  }
  testing::TempDir dir;
  Options options;
  options.memory.time_limit_ms = 0;
  Detector detector(options, dir.File("map.db"));
  auto sequence = ImageSequence::Open(kSamples + "/images");
  std::vector<Detection> detections;
  std::vector<std::string> names;
  Frame frame;
  int images = 0;
  while (sequence->Next(&frame)) {
    ASSERT_TRUE(frame.error.empty()) << frame.name;
    ASSERT_EQ(frame.name, std::to_string(frame.index + 1) + ".jpg");  // natural order
    const Result result = detector.Process(frame.image, frame.index);
    if (result.HasLoopClosure()) detections.push_back({frame.index, result.loop_closure_images});
    names.push_back(frame.name);
    ++images;
  }
  EXPECT_EQ(images, 84);
  const GroundTruth truth = GroundTruth::Load(kSamples + "/ground_truth_pairs.csv",
                                              GroundTruthFormat::kPairs, names, images);
  EXPECT_EQ(truth.PairCount(), 228);
  const PrecisionRecall score = Evaluate(detections, truth);
  EXPECT_EQ(score.loop_images, 44);
  EXPECT_EQ(score.false_positives, 0);
  EXPECT_GT(score.true_positives, 0);
  std::cout << "rtabmap_samples: precision " << score.Precision() << ", recall " << score.Recall()
            << " (" << score.true_positives << "/" << score.loop_images << ")\n";
}

}  // namespace
}  // namespace memloop
