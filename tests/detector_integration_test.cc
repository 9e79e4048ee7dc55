// The whole detector on the generated route, whose ground truth is exact.
#include <gtest/gtest.h>

#include <algorithm>
#include <future>
#include <map>
#include <random>
#include <set>

#include "both_cores_loaded.h"
#include "memloop/detector.h"
#include "memloop/errors.h"
#include "memloop/evaluation.h"
#include "memloop/synthetic_route.h"
#include "short_route.h"
#include "storage/ltm_database.h"
#include "temp_dir.h"

namespace memloop {
namespace {

// Checks the map's invariants after every image (Detector::CheckConsistency).
void ExpectConsistent(Detector& detector, int index) {
  for (const std::string& problem : detector.CheckConsistency()) {
    ADD_FAILURE() << "after image " << index << ": " << problem;
  }
}

std::vector<Result> RunRoute(const SyntheticRoute& route, const Options& options,
                             bool check_every_image = true) {
  testing::TempDir dir;
  Detector detector(options, dir.File("map.db"));
  std::vector<Result> results;
  for (int index = 0; index < route.size(); ++index) {
    results.push_back(detector.Process(route.Render(index), index));
    if (check_every_image) ExpectConsistent(detector, index);
  }
  return results;
}

PrecisionRecall Score(const SyntheticRoute& route, const std::vector<Result>& results) {
  std::vector<Detection> detections;
  for (const Result& result : results) {
    if (result.HasLoopClosure()) {
      detections.push_back({result.image_index, result.loop_closure_images});
    }
  }
  return Evaluate(detections, route.Truth());
}

// Time-based transfer depends on the machine: deterministic tests turn it off.
Options Deterministic() {
  Options options;
  options.memory.time_limit_ms = 0;
  return options;
}

TEST(DetectorIntegrationTest, GeneratedRouteAtDefaultParameters) {
  const SyntheticRoute route;
  const std::vector<Result> results = RunRoute(route, Deterministic());
  const PrecisionRecall score = Score(route, results);
  EXPECT_EQ(score.false_positives, 0);
  EXPECT_DOUBLE_EQ(score.Precision(), 1.0);
  EXPECT_GE(score.Recall(), 0.80) << score.true_positives << "/" << score.loop_images;
  // The first lap is new places (but its last frame, back at its start): no loop closure there.
  for (const Result& result : results) {
    if (result.image_index < SyntheticRouteOptions().lap_frames - 1) {
      EXPECT_FALSE(result.HasLoopClosure()) << result.Brief();
    }
  }
}

TEST(DetectorIntegrationTest, SmallWorkingMemoryFindsLoopsThroughRetrieval) {
  const SyntheticRoute route;
  Options options = Deterministic();
  options.memory.max_wm_locations = 35;  // the unbounded run peaks above 40
  const std::vector<Result> results = RunRoute(route, options);
  std::set<LocationId> retrieved;
  int loops_on_retrieved = 0;
  size_t max_wm = 0;
  int max_ltm = 0;
  for (const Result& result : results) {
    if (result.HasLoopClosure() && retrieved.count(result.loop_closure_id)) ++loops_on_retrieved;
    retrieved.insert(result.retrieved_ids.begin(), result.retrieved_ids.end());
    max_wm = std::max<size_t>(max_wm, result.wm_size);
    max_ltm = std::max(max_ltm, result.ltm_size);
    EXPECT_LE(result.retrieved_ids.size(), 2u);
  }
  EXPECT_LE(max_wm, 35u);
  EXPECT_GT(max_ltm, 0);
  EXPECT_GT(loops_on_retrieved, 0) << "no loop closure on a location brought back from LTM";
  EXPECT_EQ(Score(route, results).false_positives, 0);
}

// Under T_time (on here, never reached) retrieval's rows are read by the read-ahead thread while
// the writer writes the same file: every retrieval waits for them (the iteration has all the time
// it needs), so none is left unread, and the detector's thread does not read the file itself.
// RunRoute checks the map's consistency at every image: a location brought up to date wrongly
// (a rename or link missed) shows there.
TEST(DetectorIntegrationTest, RetrievalUnderTimeLimitReadsAhead) {
  const SyntheticRoute route;
  Options options = Deterministic();
  options.memory.time_limit_ms = 1e9;
  options.memory.max_wm_locations = 35;
  ASSERT_TRUE(options.memory.retrieval_read_ahead);
  int retrieved = 0;
  int retrieving = 0;        // iterations that retrieved
  int reading_the_file = 0;  // of those, iterations that read the map file themselves
  for (const Result& result : RunRoute(route, options)) {
    retrieved += static_cast<int>(result.retrieved_ids.size());
    EXPECT_EQ(result.retrievals_unread, 0) << result.Brief();
    if (result.retrieved_ids.empty()) continue;
    ++retrieving;
    if (result.times.ltm_read_ms > 0) ++reading_the_file;
  }
  EXPECT_GT(retrieved, 0);
  // The rows come from the read-ahead thread. A few may be read again: a location whose store was
  // still queued when that thread read it (0 of 40-60 in three runs; every one before issue 9's
  // hand-over).
  EXPECT_LE(reading_the_file * 5, retrieving);
}

// memory.retrieval_min_value: the highest hypothesis' LTM neighbours come back only when its value
// reaches the threshold (retrieval by appearance off, so that every retrieval is the hypothesis').
TEST(DetectorIntegrationTest, RetrievalWaitsForAHypothesisValue) {
  const SyntheticRoute route;
  Options options = Deterministic();
  options.memory.max_wm_locations = 30;
  options.memory.appearance_retrieval = 0;
  options.memory.retrieval_min_value = 0.05;
  int retrievals = 0;
  for (const Result& result : RunRoute(route, options, false)) {
    if (result.retrieved_ids.empty()) continue;
    ++retrievals;
    EXPECT_GE(result.hypothesis_value, 0.05) << result.Brief();
  }
  EXPECT_GT(retrievals, 0);
  options.memory.retrieval_min_value = 1.0;  // the whole posterior on loop closures: never here
  for (const Result& result : RunRoute(route, options, false)) {
    EXPECT_TRUE(result.retrieved_ids.empty()) << result.Brief();
  }
}

// memory.retrieved_kept_last_iterations: a location retrieved in the last 10 iterations leaves
// WM only after all the others, and the budget still holds. Counted: retrieved locations
// transferred again within 10 iterations of their retrieval, under a WM budget of 30.
TEST(DetectorIntegrationTest, JustRetrievedLocationsLeaveWorkingMemoryLast) {
  const SyntheticRoute route;
  const auto quick_returns = [&](int kept_last_iterations) {
    Options options = Deterministic();
    options.memory.max_wm_locations = 30;
    options.memory.retrieved_kept_last_iterations = kept_last_iterations;
    std::map<LocationId, long long> retrieved_at;
    int returns = 0;
    long long iteration = 0;
    for (const Result& result : RunRoute(route, options, false)) {
      EXPECT_LE(result.wm_size, 30 + options.memory.max_retrieved) << result.Brief();
      for (LocationId id : result.transferred_ids) {
        const auto retrieved = retrieved_at.find(id);
        if (retrieved != retrieved_at.end() && iteration - retrieved->second < 10) ++returns;
      }
      for (LocationId id : result.retrieved_ids) retrieved_at[id] = iteration;
      ++iteration;
    }
    return returns;
  };
  const int by_weight_and_age = quick_returns(0);
  const int kept_last = quick_returns(10);
  std::cout << "retrieved locations transferred again within 10 images: " << by_weight_and_age
            << " (by weight and age), " << kept_last << " (kept last)\n";
  EXPECT_GT(by_weight_and_age, 0);
  EXPECT_LT(kept_last * 4, by_weight_and_age);
}

// Issue 8: recall degrades gracefully as the WM budget shrinks (the highest hypothesis'
// neighbourhood leaves WM last). Under a small budget a revisit is found only once a retrieval
// happens to bring its place back from LTM, so one route is a single draw: small differences (the
// forest's rebuild schedule) move one seed's recall at WM 20 anywhere from 2% to 90%. The floors
// are on the mean over six routes, a margin under the measured 78% / 91% / 97.5% at WM 20 / 30 /
// 45 (42% / 65% / 97% before memory.retrieved_kept_last_iterations, when a location retrieved for
// a revisit was often the first to leave again; 65% / 68% / 97.5% before that with
// memory.retrieval_min_value=0: retrievals for a hypothesis at noise level
// cycle a small LTM through WM, which helps on a 300-image route and is pure cost at scale,
// docs/design.md); the paper2011 preset's own rules are compared in the test after this one.
// Known gap: an image just after a revisited stretch (the first of the second detour, image 190)
// is sometimes accepted, budget or not: at most 3 false positives over the six routes.
// Command: memloop demo --seed S --set memory.time_limit_ms=0 memory.max_wm_locations=N
TEST(DetectorIntegrationTest, RecallDegradesGracefullyUnderWorkingMemoryBudgets) {
  const std::vector<int> seeds = {1, 2, 3, 4, 5, 7};
  const std::map<int, double> floors = {{20, 0.65}, {30, 0.80}, {45, 0.90}};
  for (const auto& [budget, floor] : floors) {
    std::vector<std::future<PrecisionRecall>> runs;
    for (int seed : seeds) {  // two at a time: the machine has 2 cores
      if (runs.size() >= 2) runs[runs.size() - 2].wait();
      runs.push_back(std::async(std::launch::async, [seed, budget = budget] {
        SyntheticRouteOptions route_options;
        route_options.seed = seed;
        const SyntheticRoute route(route_options);
        Options options = Deterministic();
        options.memory.max_wm_locations = budget;
        const std::vector<Result> results = RunRoute(route, options, false);
        for (const Result& result : results) EXPECT_LE(result.wm_size, budget + 2);  // + retrieved
        return Score(route, results);
      }));
    }
    double recall = 0;
    int false_positives = 0;
    for (auto& run : runs) {
      const PrecisionRecall score = run.get();
      recall += score.Recall() / seeds.size();
      false_positives += score.false_positives;
    }
    std::cout << "WM " << budget << ": mean recall " << recall << ", false positives "
              << false_positives << "\n";
    EXPECT_GE(recall, floor) << "budget " << budget;
    EXPECT_LE(false_positives, 3) << "budget " << budget;
  }
}

// The paper's transfer order under a budget of 30, for contrast: with the text's rule alone (a
// retrieved location immune for the retrieving iteration only) the retrieved neighbours, old and
// of weight 0, are the first to leave again and recall collapses; the paper's 2011 code kept
// them 10 iterations (memory.retrieved_immune_iterations, in the paper2011 preset), which brings
// it back. memloop keeps the highest hypothesis' neighbourhood last instead
// (memory.protect_hypothesis, on by default: the test before this one); measured here, 95%.
TEST(DetectorIntegrationTest, Paper2011TransferOrderNeedsItsRetrievalDelayUnderABudget) {
  const SyntheticRoute route;
  Options options = Options::Paper2011();
  options.memory.time_limit_ms = 0;
  options.memory.max_wm_locations = 30;
  // The map's invariants are checked after every image of the first run only (the preset's own
  // transfer order); the other differs from it by one parameter.
  const PrecisionRecall code = Score(route, RunRoute(route, options));
  options.memory.retrieved_immune_iterations = 1;
  const PrecisionRecall text = Score(route, RunRoute(route, options, false));
  EXPECT_LT(text.Recall(), 0.5);
  EXPECT_GT(code.Recall(), text.Recall() + 0.2);
  std::cout << "paper2011 under WM 30: recall " << text.Recall() << " (text), " << code.Recall()
            << " (2011 code)\n";
}

TEST(DetectorIntegrationTest, SameInputSameResults) {
  SyntheticRouteOptions small;
  small.lap_frames = 40;
  small.detour_frames = 10;
  small.third_lap_frames = 10;
  const SyntheticRoute route(small);
  Options options = Deterministic();
  options.memory.max_wm_locations = 20;
  const auto first = RunRoute(route, options);
  const auto second = RunRoute(route, options);
  ASSERT_EQ(first.size(), second.size());
  for (size_t i = 0; i < first.size(); ++i) {
    EXPECT_EQ(first[i].location_id, second[i].location_id) << i;
    EXPECT_EQ(first[i].word_count, second[i].word_count) << i;
    EXPECT_EQ(first[i].hypothesis_id, second[i].hypothesis_id) << i;
    EXPECT_EQ(first[i].hypothesis_value, second[i].hypothesis_value) << i;
    EXPECT_EQ(first[i].loop_closure_id, second[i].loop_closure_id) << i;
    EXPECT_EQ(first[i].retrieved_ids, second[i].retrieved_ids) << i;
    EXPECT_EQ(first[i].transferred_ids, second[i].transferred_ids) << i;
    EXPECT_EQ(first[i].dictionary_size, second[i].dictionary_size) << i;
  }
}

using testing::ShortRoute;

// T_time smaller than any iteration: every iteration is over the limit, whatever the machine.
TEST(DetectorIntegrationTest, TimeLimitTransfersEveryIterationItIsExceeded) {
  const SyntheticRoute route(ShortRoute());
  Options options;
  options.memory.time_limit_ms = 1e-6;
  const std::vector<Result> results = RunRoute(route, options);
  int iterations_with_transfer = 0;
  for (const Result& result : results) {
    // WM at the transfer step, less the retrieved (immune) ones: if any, one at least goes.
    const size_t candidates =
        result.wm_size + result.transferred_ids.size() - result.retrieved_ids.size();
    EXPECT_EQ(candidates > 0, !result.transferred_ids.empty()) << result.image_index;
    iterations_with_transfer += !result.transferred_ids.empty();
  }
  EXPECT_GT(iterations_with_transfer, 10);
  EXPECT_GT(results.back().ltm_size, 0);
}

// After Close(), the file holds the whole map and every accepted loop closure.
TEST(DetectorIntegrationTest, MapFileHoldsEveryLocationAndLoopClosure) {
  const SyntheticRoute route(ShortRoute());
  testing::TempDir dir;
  Options options = Deterministic();
  options.memory.max_wm_locations = 20;
  std::vector<Result> loops;
  {
    Detector detector(options, dir.File("map.db"));
    for (int index = 0; index < route.size(); ++index) {
      const Result result = detector.Process(route.Render(index), index);
      if (result.HasLoopClosure()) loops.push_back(result);
    }
    detector.Close();
    EXPECT_THROW(detector.Process(route.Render(0)), Error);
  }
  ASSERT_FALSE(loops.empty());
  LtmDatabase database(dir.File("map.db"), LtmDatabase::Mode::kOpen);
  const auto records = database.ReadLoopClosures();
  ASSERT_EQ(records.size(), loops.size());
  for (size_t i = 0; i < loops.size(); ++i) {
    EXPECT_EQ(records[i].query_image, loops[i].image_index);
    // The matched image, first of the location's images, is the one whose keypoints it holds
    // (the pose's view).
    EXPECT_EQ(records[i].match_image, loops[i].loop_closure_images.front());
    EXPECT_EQ(records[i].match_image, loops[i].loop_closure_geometry.match_view);
    EXPECT_EQ(records[i].match_location, loops[i].loop_closure_id);
  }
  // Every location links only to locations that exist, and every word it holds is stored.
  const long long count = database.CountLocations();
  EXPECT_GT(count, 20);
  int checked = 0;
  for (LocationId id = 1; checked < count && id < 10000; ++id) {
    const auto location = database.ReadLocation(id);
    if (!location) continue;
    ++checked;
    for (LocationId link : location->Links()) {
      EXPECT_TRUE(database.ReadLocation(link).has_value()) << id << " -> " << link;
    }
    for (WordId word : location->signature.words) {
      ASSERT_TRUE(database.ReadWord(word).has_value()) << "word " << word << " of " << id;
    }
  }
  EXPECT_EQ(checked, count);
}

// The other backends on the generated route with a small WM (SURF, the default, is tested above):
// loops are found, few false, and words (float or binary) go to LTM and come back. Known gap
// (issue 8): with the default upright descriptors, SIFT gets 1 false positive of 118 here and
// ORB 2 of 122 (oriented: 0 and 2), all on the first images past the second lap's end (190,
// 191), which the filter's prior still carries to the lap's end; on real data upright removes
// all 102 of SIFT's false positives on tum_fr1_rpy and 30 of ORB's 31 (docs/real-data.md).
TEST(DetectorIntegrationTest, OtherFeatureBackendsThroughTransferAndRetrieval) {
  const SyntheticRoute route;
  const std::map<std::string, int> max_false_positives = {{"sift", 1}, {"orb", 2}};
  for (const char* backend : {"sift", "orb"}) {
    Options options = Deterministic();
    options.features.type = backend;
    options.memory.max_wm_locations = 35;
    // Invariants after every image: ConsistencyTest.HoldsAfterEveryImageForEveryBackend.
    const std::vector<Result> results = RunRoute(route, options, false);
    const PrecisionRecall score = Score(route, results);
    int retrieved = 0;
    for (const Result& result : results) retrieved += static_cast<int>(result.retrieved_ids.size());
    EXPECT_GT(score.true_positives, 20) << backend;
    EXPECT_LE(score.false_positives, max_false_positives.at(backend)) << backend;
    EXPECT_GT(retrieved, 0) << backend;
  }
}

TEST(DetectorIntegrationTest, BadImageIsRefusedAndNothingChanges) {
  testing::TempDir dir;
  Detector detector(Deterministic(), dir.File("map.db"));
  EXPECT_THROW(detector.Process(cv::Mat()), InputError);
  EXPECT_THROW(detector.Process(cv::Mat(10, 10, CV_32F)), InputError);
  const Result result = detector.Process(SyntheticRoute().Render(0));
  EXPECT_EQ(result.location_id, 1);
  EXPECT_EQ(result.image_index, 0);
}

TEST(DetectorIntegrationTest, InvalidOptionsAreRefused) {
  testing::TempDir dir;
  Options options;
  options.filter.loop_threshold = 2;
  EXPECT_THROW(Detector(options, dir.File("map.db")), ParameterError);
}

TEST(DetectorIntegrationTest, DefaultResultSaysNotRun) {
  EXPECT_EQ(Result().Brief(), "Detector::Process was not called.");
}

}  // namespace
}  // namespace memloop

namespace memloop {
namespace {

// Everything a map file holds, as text, in a fixed order: two runs' files can be compared.
std::string MapContent(const std::string& path) {
  LtmDatabase database(path, LtmDatabase::Mode::kOpen);
  std::string text;
  for (LocationId id = 1; id < 5000; ++id) {
    const auto location = database.ReadLocation(id);
    if (!location) continue;
    text += "L" + std::to_string(id) + " w" + std::to_string(location->weight) + " n";
    for (LocationId link : location->neighbours) text += std::to_string(link) + ",";
    text += " c";
    for (LocationId link : location->loop_closures) text += std::to_string(link) + ",";
    text += " i";
    for (ImageIndex image : location->images) text += std::to_string(image) + ",";
    text += " z";
    for (WordId word : location->signature.words) {
      text += std::to_string(word) + ",";
      if (!database.ReadWord(word)) text += "(missing)";
    }
    text += "\n";
  }
  for (const LoopClosureRecord& record : database.ReadLoopClosures()) {
    text += "LC " + std::to_string(record.query_image) + " " + std::to_string(record.match_image) +
            " " + std::to_string(record.probability) + "\n";
  }
  return text;
}

// With T_time on, a checkpoint the writer has not committed is not waited for (issue 9). Image
// i's checkpoint is written at the start of image i + 1 (its Result's checkpoint_ms). With the
// writer held, image 0's is queued by image 1, the next memory.checkpoint_max_skipped are
// skipped, and the one after waits for it and queues the next (8: images 2-9 skip theirs, 10
// waits; 0: none skips). With T_time off every image writes one. The map resumes either way.
TEST(DetectorIntegrationTest, UncommittedCheckpointIsSkippedOnlyWithTimeLimit) {
  const SyntheticRoute route(ShortRoute());
  const int kDefault = Options().memory.checkpoint_max_skipped;
  ASSERT_GT(kDefault, 12);
  for (const auto& [time_limit, max_skipped] :
       std::vector<std::pair<double, int>>{{1e9, 8}, {1e9, 0}, {1e9, kDefault}, {0.0, 8}}) {
    testing::TempDir dir;
    Options options;
    options.memory.time_limit_ms = time_limit;  // 1e9: on, but never reached
    options.memory.checkpoint_max_skipped = max_skipped;
    {
      Detector detector(options, dir.File("map.db"));
      detector.SetWriterHeld(true);
      for (int index = 0; index < 12; ++index) {
        const Result result = detector.Process(route.Render(index), index);
        const bool skipped = index == 0 || (time_limit > 0 && (index - 1) % (max_skipped + 1) != 0);
        EXPECT_EQ(result.times.checkpoint_ms == 0, skipped)
            << "image " << index << ", T_time " << time_limit << ", skips " << max_skipped;
        if (!skipped && index > 1) {  // waited for the held writer: the iteration's LTM wait
          EXPECT_GT(result.times.ltm_wait_ms, 0.0) << "image " << index;
          EXPECT_LE(result.times.ltm_wait_ms, result.times.checkpoint_ms) << "image " << index;
        }
      }
      detector.Close();
    }
    Detector resumed(ReadMapOptions(dir.File("map.db")), dir.File("map.db"), MapMode::kResume);
    EXPECT_EQ(resumed.last_image(), 11);
  }
}

struct RouteRun {
  std::vector<Result> results;
  std::string map;
};

// The route with the LTM writer held back at random moments (seeded), or never.
RouteRun RunWithWriterHeld(const SyntheticRoute& route, const Options& options, unsigned seed) {
  testing::TempDir dir;
  RouteRun run;
  {
    Detector detector(options, dir.File("map.db"));
    std::mt19937 random(seed);
    for (int index = 0; index < route.size(); ++index) {
      if (seed != 0) detector.SetWriterHeld(random() % 3 != 0);
      run.results.push_back(detector.Process(route.Render(index), index));
    }
    detector.Close();
  }
  run.map = MapContent(dir.File("map.db"));
  return run;
}

// Determinism as a property: with T_time off, the writer's timing changes nothing, neither the
// results nor the map file.
class DeterminismTest : public ::testing::TestWithParam<int> {};

TEST_P(DeterminismTest, WriterTimingChangesNothing) {
  const SyntheticRoute route(ShortRoute());
  Options options;
  options.memory.time_limit_ms = 0;
  options.memory.max_wm_locations = GetParam();
  const RouteRun free_writer = RunWithWriterHeld(route, options, 0);
  for (unsigned seed : {1u, 2u, 3u}) {
    const RouteRun held = RunWithWriterHeld(route, options, seed);
    ASSERT_EQ(held.results.size(), free_writer.results.size());
    for (size_t i = 0; i < held.results.size(); ++i) {
      const Result& a = free_writer.results[i];
      const Result& b = held.results[i];
      ASSERT_EQ(a.hypothesis_id, b.hypothesis_id) << "image " << i << ", seed " << seed;
      ASSERT_EQ(a.hypothesis_value, b.hypothesis_value) << "image " << i << ", seed " << seed;
      ASSERT_EQ(a.loop_closure_id, b.loop_closure_id) << "image " << i;
      ASSERT_EQ(a.retrieved_ids, b.retrieved_ids) << "image " << i;
      ASSERT_EQ(a.transferred_ids, b.transferred_ids) << "image " << i;
      ASSERT_EQ(a.dictionary_size, b.dictionary_size) << "image " << i;
    }
    EXPECT_EQ(held.map, free_writer.map) << "seed " << seed;
    EXPECT_EQ(held.map.find("(missing)"), std::string::npos);
  }
}

INSTANTIATE_TEST_SUITE_P(WmBudgets, DeterminismTest, ::testing::Values(20, 30));

// Small budgets move locations back and forth between WM and LTM all the time: the map's
// invariants hold after every image, for every budget and every feature backend.
TEST(ConsistencyTest, HoldsAfterEveryImageUnderSmallBudgets) {
  const SyntheticRoute route;
  for (int budget : {20, 30, 45}) {
    Options options;
    options.memory.time_limit_ms = 0;
    options.memory.max_wm_locations = budget;
    RunRoute(route, options);
  }
}

TEST(ConsistencyTest, HoldsAfterEveryImageForEveryBackend) {
  const SyntheticRoute route(ShortRoute());
  for (const char* backend : {"surf", "sift", "orb"}) {
    SCOPED_TRACE(backend);
    Options options;
    options.features.type = backend;
    options.memory.time_limit_ms = 0;
    options.memory.max_wm_locations = 20;
    RunRoute(route, options);
  }
}

// A T_time that is never reached gives the results of no T_time (issue 35: three default runs
// of gp_walk_a accepted 67, 65 and 68 loop closures, with no iteration near T_time and no
// transfer, because the dictionary's forest rebuilt in the background was used as soon as it was
// built rather than at a fixed insertion). Both cores are loaded by two busy threads: a build
// that is due but not done is waited for within the iteration's time to spare (all of it here),
// however slow the machine.
TEST(DetectorIntegrationTest, TimeLimitNeverReachedGivesTheResultsOfNoTimeLimit) {
  const SyntheticRoute route(ShortRoute());
  Options off;
  off.memory.time_limit_ms = 0;
  Options on;
  on.memory.time_limit_ms = 1e6;  // on, but never reached
  const auto run = [&route](const Options& options) {
    testing::TempDir dir;
    Detector detector(options, dir.File("map.db"));
    std::vector<Result> results;
    for (int i = 0; i < route.size(); ++i) {
      results.push_back(detector.Process(route.Render(i), i));
    }
    return results;
  };
  const std::vector<Result> expected = run(off);
  const std::vector<Result> actual = [&] {
    const testing::BothCoresLoaded load;
    return run(on);
  }();
  int loop_closures = 0;
  ASSERT_EQ(actual.size(), expected.size());
  for (size_t i = 0; i < actual.size(); ++i) {
    EXPECT_EQ(actual[i].word_count, expected[i].word_count) << "image " << i;
    EXPECT_EQ(actual[i].dictionary_size, expected[i].dictionary_size) << "image " << i;
    EXPECT_EQ(actual[i].hypothesis_id, expected[i].hypothesis_id) << "image " << i;
    EXPECT_DOUBLE_EQ(actual[i].hypothesis_value, expected[i].hypothesis_value) << "image " << i;
    EXPECT_EQ(actual[i].loop_closure_id, expected[i].loop_closure_id) << "image " << i;
    loop_closures += expected[i].HasLoopClosure();
  }
  EXPECT_GT(loop_closures, 10);
}

}  // namespace
}  // namespace memloop
