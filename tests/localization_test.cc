// Localization (memory.localization): a map of the first lap, the second lap localized against
// it. Places are recognized, through retrieval from LTM too, and the map file is not changed.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>

#include "cli_helpers.h"
#include "memloop/detector.h"
#include "memloop/errors.h"
#include "memloop/synthetic_route.h"
#include "short_route.h"
#include "temp_dir.h"

namespace memloop {
namespace {

namespace fs = std::filesystem;

// The short route: lap 1 is images 0-39 and a detour 40-49, lap 2 is images 50-89.
constexpr int kMapEnd = 50;
constexpr int kLapTwoEnd = 90;
constexpr int kBudget = 20;  // WM locations: lap 1's first places are in LTM when lap 2 starts

Options Mapping() {
  Options options;
  options.memory.time_limit_ms = 0;
  options.memory.max_wm_locations = kBudget;
  return options;
}

Options Localizing() {
  Options options = Mapping();
  options.memory.localization = 1;
  return options;
}

std::vector<Result> ProcessImages(Detector& detector, const SyntheticRoute& route, int begin,
                                  int end) {
  std::vector<Result> results;
  for (int index = begin; index < end; ++index) {
    results.push_back(detector.Process(route.Render(index), index));
  }
  return results;
}

// The bytes of the map and of its WAL (SQLite may create an empty one beside a read-only map).
std::string MapBytes(const std::string& path) {
  std::error_code no_wal;
  const auto wal_size = fs::file_size(path + "-wal", no_wal);
  return ReadFile(path) + "|wal:" + std::to_string(no_wal ? 0 : wal_size);
}

class LocalizationTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    route_ = new SyntheticRoute(testing::ShortRoute());
    folder_ = new testing::TempDir();
    Detector mapping(Mapping(), Map());
    ProcessImages(mapping, *route_, 0, kMapEnd);
    mapping.Close();
  }
  static void TearDownTestSuite() {
    delete folder_;
    delete route_;
  }
  static std::string Map() { return folder_->File("lap1.db"); }

  static SyntheticRoute* route_;
  static testing::TempDir* folder_;
  testing::TempDir dir_;
};
SyntheticRoute* LocalizationTest::route_ = nullptr;
testing::TempDir* LocalizationTest::folder_ = nullptr;

TEST_F(LocalizationTest, SecondLapIsLocalizedAndTheMapFileIsUnchanged) {
  const std::string before = MapBytes(Map());
  std::vector<Result> results;
  {
    Detector detector(Localizing(), Map());
    results = ProcessImages(detector, *route_, kMapEnd, kLapTwoEnd);
    EXPECT_EQ(detector.CheckConsistency(), std::vector<std::string>());
    detector.Close();
  }
  int localized = 0;
  int retrieved = 0;
  int transferred = 0;
  for (const Result& result : results) {
    EXPECT_EQ(result.location_id, kNoLocation) << "image " << result.image_index;
    EXPECT_LE(result.wm_size, kBudget);
    retrieved += static_cast<int>(result.retrieved_ids.size());
    transferred += static_cast<int>(result.transferred_ids.size());
    if (!result.HasLoopClosure()) continue;
    ++localized;
    // A location holds the images Rehearsal merged into it: one of them must be the place.
    EXPECT_TRUE(
        std::any_of(result.loop_closure_images.begin(), result.loop_closure_images.end(),
                    [&](ImageIndex match) { return route_->IsLoop(result.image_index, match); }))
        << "image " << result.image_index << " localized at location " << result.loop_closure_id;
  }
  // Measured: all 40 images, 11 retrievals, 18 transfers.
  EXPECT_GE(localized, 30);
  EXPECT_GT(retrieved, 0) << "lap 1's first places are in LTM: localization retrieves them";
  EXPECT_GT(transferred, 0);
  EXPECT_EQ(MapBytes(Map()), before);
}

// Verification by descriptor (`--preset verified`) matches the localized image's own keypoints:
// with every eligible hypothesis between T_verified and T_loop (0.001 and 0.99 here), lap 2's
// images are checked against lap 1's places and the right ones fit one geometry.
TEST_F(LocalizationTest, VerificationUsesTheLocalizedImagesKeypoints) {
  Options options = Options::Verified();
  options.memory.time_limit_ms = 0;
  options.memory.max_wm_locations = kBudget;
  options.memory.localization = 1;
  options.verification.loop_threshold = 0.001;
  options.filter.loop_threshold = 0.99;
  Detector localizing(options, Map());
  int verified = 0;
  for (const Result& result : ProcessImages(localizing, *route_, kMapEnd, kLapTwoEnd)) {
    verified += result.hypothesis_inliers >= 20 ? 1 : 0;
  }
  EXPECT_GE(verified, 10) << "of 40 lap-2 images";
}

// Nothing localization does stays in the map: localizing twice gives the same answers, and the
// map then resumes exactly as a copy nobody localized against.
TEST_F(LocalizationTest, LeavesNothingBehind) {
  const std::string copy = dir_.File("copy.db");
  fs::copy_file(Map(), copy);
  std::vector<Result> first;
  std::vector<Result> second;
  {
    Detector detector(Localizing(), Map());
    first = ProcessImages(detector, *route_, kMapEnd, kLapTwoEnd);
  }
  {
    Detector detector(Localizing(), Map());
    second = ProcessImages(detector, *route_, kMapEnd, kLapTwoEnd);
  }
  ASSERT_EQ(first.size(), second.size());
  for (size_t i = 0; i < first.size(); ++i) {
    EXPECT_EQ(first[i].loop_closure_id, second[i].loop_closure_id) << "image " << i;
    EXPECT_EQ(first[i].hypothesis_value, second[i].hypothesis_value) << "image " << i;
    EXPECT_EQ(first[i].retrieved_ids, second[i].retrieved_ids) << "image " << i;
  }
  Detector localized_map(Mapping(), Map(), MapMode::kResume);
  Detector untouched_copy(Mapping(), copy, MapMode::kResume);
  for (int index = kMapEnd; index < kMapEnd + 10; ++index) {
    const Result a = localized_map.Process(route_->Render(index), index);
    const Result b = untouched_copy.Process(route_->Render(index), index);
    EXPECT_EQ(a.location_id, b.location_id) << "image " << index;
    EXPECT_EQ(a.hypothesis_value, b.hypothesis_value) << "image " << index;
    EXPECT_EQ(a.dictionary_size, b.dictionary_size) << "image " << index;
  }
}

TEST_F(LocalizationTest, NeedsAnExistingMap) {
  const std::string missing = dir_.File("missing.db");
  EXPECT_THROW(Detector(Localizing(), missing), DatabaseError);
  EXPECT_FALSE(fs::exists(missing));

  const std::string notes = dir_.File("notes.txt");
  std::ofstream(notes) << "not a map";
  EXPECT_THROW(Detector(Localizing(), notes), DatabaseError);
  EXPECT_EQ(ReadFile(notes), "not a map");

  Options other = Localizing();
  other.dictionary.nndr_ratio = 0.6;  // defines the map: its words would not be the map's
  try {
    Detector detector(other, Map());
    FAIL() << "a map made with other dictionary parameters was accepted";
  } catch (const ParameterError& error) {
    EXPECT_NE(std::string(error.what()).find("cannot localize against it with other values"),
              std::string::npos)
        << error.what();
    EXPECT_NE(std::string(error.what()).find("dictionary.nndr_ratio"), std::string::npos);
  }
}

// The README's commands: map one walk, localize another against it.
TEST_F(LocalizationTest, CommandLine) {
  const fs::path images = dir_.path() / "route" / "images";
  SyntheticRoute(testing::ShortRoute()).Write((dir_.path() / "route").string());
  fs::create_directories(dir_.path() / "lap1");
  fs::create_directories(dir_.path() / "lap2");
  for (int n = 1; n <= kLapTwoEnd; ++n) {
    const std::string name = std::to_string(n) + ".png";
    fs::create_symlink(images / name, dir_.path() / (n <= kMapEnd ? "lap1" : "lap2") / name);
  }
  const std::string lap1 = dir_.File("lap1");
  const std::string lap2 = dir_.File("lap2");
  const std::string map = dir_.File("map.db");
  const std::string budget =
      " --set memory.time_limit_ms=0 memory.max_wm_locations=" + std::to_string(kBudget);
  ASSERT_EQ(Memloop("run " + lap1 + " --db " + map + budget).exit_code, 0);
  const std::string before = MapBytes(map);

  const Outcome run = Memloop("run " + lap2 + " --db " + map + budget +
                              " --set memory.localization=1 --out " + dir_.File("lap2.csv"));
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_TRUE(Contains(run.output, "localizing against " + map)) << run.output;
  EXPECT_TRUE(Contains(run.output, ": localized at location")) << run.output;
  EXPECT_GE(RowsWithLoopClosure(ReadFile(dir_.File("lap2.csv"))), 30);
  EXPECT_EQ(MapBytes(map), before);

  const std::string localize = " --set memory.localization=1";
  const Outcome no_map = Memloop("run " + lap2 + localize);
  EXPECT_NE(no_map.exit_code, 0);
  EXPECT_TRUE(Contains(no_map.output, "needs --db MAP")) << no_map.output;
  const Outcome resume = Memloop("run " + lap2 + " --db " + map + " --resume" + localize);
  EXPECT_NE(resume.exit_code, 0);
  EXPECT_TRUE(Contains(resume.output, "--resume extends the map")) << resume.output;
  const Outcome preset = Memloop("run " + lap2 + " --db " + map + " --preset paper2011" + localize);
  EXPECT_NE(preset.exit_code, 0);
  EXPECT_TRUE(Contains(preset.output, "parameters of the map")) << preset.output;
  const Outcome missing = Memloop("run " + lap2 + " --db " + dir_.File("none.db") + localize);
  EXPECT_NE(missing.exit_code, 0);
  EXPECT_FALSE(fs::exists(dir_.File("none.db")));
  EXPECT_EQ(MapBytes(map), before);
}

}  // namespace
}  // namespace memloop
