// Checks on the real data sets when present: ../shared/datasets beside the project, or the folder
// named by the MEMLOOP_DATASETS environment variable (or CMake variable) when set. A fresh clone
// has none: the tests skip, saying so.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <map>
#include <memory>
#include <opencv2/imgcodecs.hpp>

#include "eval/loop_closure_views.h"
#include "memloop/detector.h"
#include "memloop/evaluation.h"
#include "memloop/ground_truth.h"
#include "memloop/image_sequence.h"
#include "memloop/run_csv.h"
#include "temp_dir.h"

namespace memloop {
namespace {

std::string Datasets() {
  const char* given = std::getenv("MEMLOOP_DATASETS");
  return given != nullptr && *given != '\0' ? given : MEMLOOP_DATASETS;
}

const std::string kSamples = Datasets() + "/rtabmap_samples";

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

namespace memloop {
namespace {

struct DataSetRun {
  RunEvaluation evaluation;
  RunEvaluation lenient;  // ignored pairs counted as loops (eval --ignored-as-true)
  int images = 0;
  // The accepted loop closures as `memloop report` draws them: true, false, on ignored pairs.
  int drawn_true = 0, drawn_false = 0, drawn_ignored = 0;
};

// Runs every image of `name` (T_time off: the same verdict on any machine), writes the run's CSV
// and scores it as `memloop eval` does, against its ground_truth.bmp. From image
// `second_session_from` on (if any), the images are a new session of the map, as
// bench/real_data.sh maps the second walk of the Gardens Point sets.
DataSetRun RunDataSet(const std::string& name, Options options, int second_session_from = -1) {
  const std::string folder = Datasets() + "/" + name;
  options.memory.time_limit_ms = 0;
  testing::TempDir dir;
  {
    auto detector = std::make_unique<Detector>(options, dir.File("map.db"));
    RunCsvWriter csv(dir.File("run.csv"));
    auto sequence = ImageSequence::Open(folder + "/images");
    Frame frame;
    while (sequence->Next(&frame)) {
      if (frame.index == second_session_from) {
        detector.reset();
        detector = std::make_unique<Detector>(options, dir.File("map.db"), MapMode::kNewSession);
      }
      if (frame.error.empty()) csv.Write(frame.name, detector->Process(frame.image, frame.index));
    }
    csv.Close();
  }
  const std::vector<RunRow> rows = ReadRunCsv(dir.File("run.csv"));
  DataSetRun run;
  run.images = static_cast<int>(rows.size());
  const GroundTruth truth =
      GroundTruth::Load(folder + "/ground_truth.bmp", GroundTruthFormat::kAuto, {}, run.images);
  run.evaluation = EvaluateRun(rows, truth);
  run.lenient = EvaluateRun(rows, truth.IgnoredAsLoops());
  for (const LoopClosureView& view : AcceptedLoopClosures(rows, &truth)) {
    ++(view.verdict == "true"    ? run.drawn_true
       : view.verdict == "false" ? run.drawn_false
                                 : run.drawn_ignored);
  }
  return run;
}

// Issue 8's floors with the default parameters, a margin under what docs/real-data.md measured
// (recall at 100% precision: rtabmap_samples 97.7%, gp_walk_a 82-89%, tum_fr1_rpy 28.7%,
// corridor 11.7% since its 160x120 images are enlarged 2x, features.min_image_side), and no false
// positive at the default T_loop. corridor's floor is wide: its recall moved between 0% and 4.5%
// with the forest's random splits alone before the enlargement. lip6_outdoor, the paper's data
// (issue 33): RTAB-Map 0.23.8's 51.8% strict and 83.7% lenient are the floors; measured 56.1% /
// 88.4% with the rolled view (surf.rolled_view_degrees), 48.8% / 78.1% without.
// The second floor is on what the run itself accepted, recall at T_loop (measured 97.7%, 63%,
// 28.4%, 9.9%, 51.5%).
struct Floors {
  double at_full_precision, at_loop_threshold;
};

TEST(RealDataTest, RecallFloorsOnEverySharedDataSet) {
  const std::map<std::string, Floors> floors = {{"rtabmap_samples", {0.95, 0.95}},
                                                {"gp_walk_a", {0.77, 0.60}},
                                                {"tum_fr1_rpy", {0.20, 0.25}},
                                                {"corridor", {0.05, 0.07}},
                                                {"lip6_outdoor", {0.518, 0.50}}};
  int present = 0;
  for (const auto& [name, floor] : floors) {
    if (!std::filesystem::exists(Datasets() + "/" + name + "/images")) continue;
    ++present;
    const DataSetRun run = RunDataSet(name, Options());
    EXPECT_GE(run.evaluation.recall_at_full_precision, floor.at_full_precision) << name;
    EXPECT_GE(run.evaluation.accepted.Recall(), floor.at_loop_threshold) << name;
    if (name == "lip6_outdoor") {
      EXPECT_GE(run.lenient.recall_at_full_precision, 0.837);
    }
    EXPECT_EQ(run.evaluation.accepted.false_positives, 0) << name;
    // The report draws what eval counts (before, tum_fr1_rpy's 84 loop closures on ignored pairs
    // were drawn as false positives while eval counted none).
    EXPECT_EQ(run.drawn_false, run.evaluation.accepted.false_positives) << name;
    EXPECT_EQ(run.drawn_true, run.evaluation.accepted.true_positives) << name;
    EXPECT_EQ(run.drawn_ignored, run.evaluation.accepted.ignored) << name;
    std::cout << name << ": recall at 100% precision " << run.evaluation.recall_at_full_precision
              << ", at T_loop " << run.evaluation.accepted.Recall() << "\n";
  }
  if (present == 0) GTEST_SKIP() << Datasets() << " holds none of the shared data sets";
}

// `--preset verified`: loop closures between T_verified (0.05) and T_loop that geometry
// confirms and the previous image agrees with (docs/design.md, "Verification under T_loop").
// Measured at T_loop: gp_walk_a 81%, lip6_outdoor 52.8% (RTAB-Map 0.23.8 at its own threshold:
// 81% with 2 false positives, 52.2% with 1), corridor 18.0%, no false positive; recall at 100%
// precision as the defaults'.
TEST(RealDataTest, VerifiedPresetAcceptsMoreAtTLoopWithoutFalsePositives) {
  const std::map<std::string, Floors> floors = {
      {"gp_walk_a", {0.77, 0.78}}, {"lip6_outdoor", {0.518, 0.522}}, {"corridor", {0.05, 0.15}}};
  int present = 0;
  for (const auto& [name, floor] : floors) {
    if (!std::filesystem::exists(Datasets() + "/" + name + "/images")) continue;
    ++present;
    const DataSetRun run = RunDataSet(name, Options::Verified());
    EXPECT_EQ(run.evaluation.accepted.false_positives, 0) << name;
    EXPECT_GE(run.evaluation.accepted.Recall(), floor.at_loop_threshold) << name;
    EXPECT_GE(run.evaluation.recall_at_full_precision, floor.at_full_precision) << name;
    std::cout << name << ", verified: at T_loop " << run.evaluation.accepted.Recall()
              << ", at 100% precision " << run.evaluation.recall_at_full_precision << "\n";
  }
  if (present == 0) GTEST_SKIP() << Datasets() << " holds none of these data sets";
}

// ORB on tum_fr1_rpy with a quarter of the unbounded WM (22 of 91 locations; without a budget,
// bench/real_data.sh's ORB row: no false positive, 40.1% at 100% precision): the views closest
// to the image had gone to LTM, and four images were accepted on views turned 25-34 degrees from
// them, linked to the closer ones. filter.ltm_neighbour_check at every image (not only after a
// deferred retrieval) refuses L_i while a linked LTM location looks more like the image: 4 -> 0
// false positives, recall at 100% precision 19.6% -> 31.9% (docs/real-data.md); 29.8% with
// retrieval by appearance's 32,768-entry vocabulary searched up to 40,000 postings (2026-12-03).
TEST(RealDataTest, OrbOnTumRpyUnderAQuarterOfWmAcceptsNoFalsePositive) {
  if (!std::filesystem::exists(Datasets() + "/tum_fr1_rpy/images")) {
    GTEST_SKIP() << Datasets() << "/tum_fr1_rpy is absent (it ships beside the project)";
  }
  Options options;
  options.features.type = "orb";
  options.memory.max_wm_locations = 22;
  const DataSetRun run = RunDataSet("tum_fr1_rpy", options);
  EXPECT_EQ(run.evaluation.accepted.false_positives, 0);
  EXPECT_GE(run.evaluation.recall_at_full_precision, 0.27);
}

// --preset paper2011 on the paper's own data (Table 1, Lip6Outdoor: 77% with its labels). With the
// text alone it found 2.0% (strict) / 2.7% (ignored pairs as loops); with the 2011 code's choices
// where the text is silent (the ratio test on squared distances, its SURF and kd-tree settings,
// the highest neighbour sum, LoopRatio) 54.2% / 77.4%, with no false positive (docs/design.md).
TEST(RealDataTest, Paper2011PresetReproducesTable1OnLip6Outdoor) {
  if (!std::filesystem::exists(Datasets() + "/lip6_outdoor/images")) {
    GTEST_SKIP() << Datasets() << "/lip6_outdoor is absent (it ships beside the project)";
  }
  const DataSetRun run = RunDataSet("lip6_outdoor", Options::Paper2011());
  EXPECT_EQ(run.images, 531);
  EXPECT_GE(run.lenient.recall_at_full_precision, 0.70);
  EXPECT_GE(run.evaluation.recall_at_full_precision, 0.48);
  EXPECT_EQ(run.evaluation.accepted.false_positives, 0);
  EXPECT_GE(run.lenient.accepted.true_positives, 200);  // 227 accepted at T_loop 0.10, all true
  std::cout << "lip6_outdoor, paper2011: recall at 100% precision "
            << run.evaluation.recall_at_full_precision << " strict, "
            << run.lenient.recall_at_full_precision << " lenient\n";
}

// Table 1's 0.4 s column (WM 102, 81% with the paper's labels): its deterministic analogue, a WM
// budget of 102. A retrieved location stays in WM 10 iterations (the 2011 code's DelayRequired):
// with only the retrieving one (III-F's text), the retrieved old locations are the first to leave
// again and recall at 100% precision fell to 6.0% / 10.0%; with 10, 52.2% / 77.1%.
TEST(RealDataTest, Paper2011PresetKeepsItsRecallUnderTable1sSmallWm) {
  if (!std::filesystem::exists(Datasets() + "/lip6_outdoor/images")) {
    GTEST_SKIP() << Datasets() << "/lip6_outdoor is absent (it ships beside the project)";
  }
  Options options = Options::Paper2011();
  options.memory.max_wm_locations = 102;
  const DataSetRun run = RunDataSet("lip6_outdoor", options);
  EXPECT_GE(run.lenient.recall_at_full_precision, 0.70);
  EXPECT_EQ(run.evaluation.accepted.false_positives, 0);
  EXPECT_LE(run.evaluation.max_wm_size, 102 + 20);  // + retrieved, immune for 10 iterations
}

// Issue 33: `--preset hand-held` on the walk whose last 60 images are rolled 9-25 degrees
// (measured 53.8% strict / 85.0% lenient; RTAB-Map 0.23.8: 51.8% / 83.7%), and on tum_fr1_rpy,
// whose ground truth calls views rolled more than 25 degrees apart other places: the preset's
// roll compensation makes them alike, its view-roll check (verify.max_roll_degrees) refuses them.
TEST(RealDataTest, HandHeldPresetFindsRolledRevisitsAndRefusesRolledApartViews) {
  if (!std::filesystem::exists(Datasets() + "/lip6_outdoor/images") ||
      !std::filesystem::exists(Datasets() + "/tum_fr1_rpy/images")) {
    GTEST_SKIP() << Datasets()
                 << "/lip6_outdoor or tum_fr1_rpy is absent (they ship beside the project)";
  }
  const DataSetRun lip6 = RunDataSet("lip6_outdoor", Options::HandHeld());
  EXPECT_GE(lip6.evaluation.recall_at_full_precision, 0.518);
  EXPECT_GE(lip6.lenient.recall_at_full_precision, 0.837);
  EXPECT_EQ(lip6.evaluation.accepted.false_positives, 0);
  const DataSetRun tum = RunDataSet("tum_fr1_rpy", Options::HandHeld());
  EXPECT_EQ(tum.evaluation.accepted.false_positives, 0);
  EXPECT_GE(tum.evaluation.recall_at_full_precision, 0.12);  // 17.3%
  std::cout << "hand-held: lip6_outdoor " << lip6.evaluation.recall_at_full_precision << " / "
            << lip6.lenient.recall_at_full_precision << ", tum_fr1_rpy "
            << tum.evaluation.recall_at_full_precision << "\n";
}

// Issue 34: `--preset day-night` on the route walked by day, then by night as a new session of
// the map, where words alone find nothing (measured 57% at 100% precision, 55% at T_loop, no false
// positive). On the route walked twice by day, from two sides, the channel stays out where the
// words recognize the place (filter.whole_image_words_first): measured 60% / 59% (the defaults:
// 89% / 63%), no false positive.
TEST(RealDataTest, DayNightPresetFindsNightRevisitsOfDayPlaces) {
  if (!std::filesystem::exists(Datasets() + "/gp_daynight_a/images")) {
    GTEST_SKIP() << Datasets() << "/gp_daynight_a is absent (it ships beside the project)";
  }
  constexpr int kSecondWalk = 100;  // each set's README: images 0101-0200
  const DataSetRun run = RunDataSet("gp_daynight_a", Options::DayNight(), kSecondWalk);
  EXPECT_GE(run.evaluation.recall_at_full_precision, 0.5);
  EXPECT_GE(run.evaluation.accepted.Recall(), 0.45);
  EXPECT_EQ(run.evaluation.accepted.false_positives, 0);
  std::cout << "day-night: gp_daynight_a " << run.evaluation.recall_at_full_precision
            << " at 100% precision, " << run.evaluation.accepted.Recall() << " at T_loop\n";
  if (!std::filesystem::exists(Datasets() + "/gp_walk_a/images")) return;
  const DataSetRun day = RunDataSet("gp_walk_a", Options::DayNight(), kSecondWalk);
  EXPECT_GE(day.evaluation.recall_at_full_precision, 0.5);
  EXPECT_EQ(day.evaluation.accepted.false_positives, 0);
  std::cout << "day-night: gp_walk_a " << day.evaluation.recall_at_full_precision
            << " at 100% precision, " << day.evaluation.accepted.Recall() << " at T_loop\n";
}

}  // namespace
}  // namespace memloop
