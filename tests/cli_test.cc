// The memloop tool as a user runs it: outputs, and a clear error for every bad input.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/videoio.hpp>
#include <sstream>

#include "cli_helpers.h"
#include "memloop/detector.h"
#include "memloop/synthetic_route.h"
#include "route_images_test.h"
#include "short_route.h"
#include "temp_dir.h"

namespace memloop {
namespace {

class CliTest : public testing::RouteImagesTest<CliTest> {};

TEST_F(CliTest, ParamsListsTheRegistry) {
  const Outcome table = Memloop("params");
  EXPECT_EQ(table.exit_code, 0);
  EXPECT_TRUE(Contains(table.output, "memory.stm_size"));
  EXPECT_TRUE(Contains(table.output, "T_loop"));
  const Outcome json = Memloop("params --json");
  EXPECT_TRUE(Contains(json.output, "\"name\": \"filter.min_hypotheses\""));
}

// --preset paper2011 starts from the paper's values (its map records them); a wrong name is
// refused before any file is made.
TEST_F(CliTest, PresetChoosesTheStartingValues) {
  const std::string db = dir_.File("paper.db");
  const Outcome run =
      Memloop("run " + Images() + " --preset paper2011 --set memory.time_limit_ms=0 --db " + db);
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const memloop::Options map = memloop::ReadMapOptions(db);
  EXPECT_EQ(map.filter.hypothesis_value, "best_neighbours");
  EXPECT_EQ(map.memory.stm_size, 25);
  EXPECT_EQ(map.memory.time_limit_ms, 0);
  const std::string other = dir_.File("other.db");
  const Outcome bad = Memloop("run " + Images() + " --preset paper2013 --db " + other);
  EXPECT_NE(bad.exit_code, 0);
  EXPECT_TRUE(Contains(bad.output, "unknown preset 'paper2013'")) << bad.output;
  EXPECT_FALSE(std::filesystem::exists(other));
}

// preset, then --config, then --set (later wins); the map keeps every value at full precision.
TEST_F(CliTest, ConfigFileGoesBetweenPresetAndSet) {
  const std::string config = dir_.File("robot.ini");
  std::ofstream(config) << "# our robot\nmemory.stm_size = 12\n[dictionary]\nseed = 1234567\n"
                           "[filter]\nloop_threshold = 0.123456789\nrequire_support = off\n";
  const std::string db = dir_.File("config.db");
  const Outcome run = Memloop("run " + Images() + " --preset paper2011 --config " + config +
                              " --set memory.stm_size=14 memory.time_limit_ms=0 --db " + db);
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const memloop::Options map = memloop::ReadMapOptions(db);
  EXPECT_EQ(map.memory.stm_size, 14);
  EXPECT_EQ(map.dictionary.seed, 1234567);
  EXPECT_EQ(map.filter.loop_threshold, 0.123456789);
  EXPECT_EQ(map.filter.require_support, 0);
  EXPECT_EQ(map.filter.hypothesis_value, "best_neighbours");  // the preset's, untouched
  std::ofstream(config) << "memory.stm_size = 12\nmemory.stm = 3\n";
  const Outcome bad =
      Memloop("run " + Images() + " --config " + config + " --db " + dir_.File("bad.db"));
  EXPECT_EQ(bad.exit_code, 1);
  EXPECT_TRUE(Contains(bad.output,
                       "memloop: error: " + config + ": line 2: Unknown parameter 'memory.stm'"))
      << bad.output;
  EXPECT_FALSE(std::filesystem::exists(dir_.File("bad.db")));
}

TEST_F(CliTest, InspectTellsWhatAMapHoldsWithoutChangingIt) {
  const std::string db = dir_.File("inspected.db");
  const std::string csv = dir_.File("inspected.csv");
  ASSERT_EQ(Memloop("run " + Images() + " --db " + db + " --out " + csv +
                    " --set memory.time_limit_ms=0 memory.max_wm_locations=30")
                .exit_code,
            0);
  const std::string before = ReadFile(db);
  const Outcome inspect = Memloop("inspect " + db + " --json");
  ASSERT_EQ(inspect.exit_code, 0) << inspect.output;
  const auto info = nlohmann::json::parse(inspect.output);
  const std::string rows = ReadFile(csv);
  const int images = static_cast<int>(std::count(rows.begin(), rows.end(), '\n')) - 1;
  EXPECT_EQ(info["images"], images);
  EXPECT_EQ(info["last_image"], images - 1);
  EXPECT_EQ(info["format_version"], 6);
  EXPECT_EQ(info["integrity"], "ok");
  EXPECT_EQ(info["parameters"]["memory.max_wm_locations"], "30");
  EXPECT_GT(info["ltm_locations"].get<int>(), 0);  // WM 30 made it transfer
  EXPECT_EQ(info["loop_closures"].size(), static_cast<size_t>(RowsWithLoopClosure(rows)));
  EXPECT_EQ(ReadFile(db), before);
  const Outcome text = Memloop("inspect " + db);
  EXPECT_TRUE(Contains(text.output, "loop closures: " + std::to_string(RowsWithLoopClosure(rows))))
      << text.output;
  const Outcome foreign = Memloop("inspect " + csv);
  EXPECT_EQ(foreign.exit_code, 1);
  EXPECT_TRUE(Contains(foreign.output, "memloop: error: " + csv + ": not a memloop map"))
      << foreign.output;
}

TEST_F(CliTest, RunWritesOneRowPerImageInNaturalOrder) {
  const std::string csv = dir_.File("results.csv");
  const Outcome run = Memloop("run " + Images() + " --set memory.time_limit_ms=0 --out " + csv);
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_TRUE(Contains(run.output, "images: 110 processed, 0 skipped")) << run.output;
  EXPECT_TRUE(Contains(run.output, "loop closure with location")) << run.output;
  std::istringstream rows(ReadFile(csv));
  std::string line;
  std::getline(rows, line);
  EXPECT_EQ(line.substr(0, 45), "image,name,location_id,matched_image,matched_");
  int count = 0;
  while (std::getline(rows, line)) {
    EXPECT_EQ(line.substr(0, line.find(',')), std::to_string(count)) << line;
    ++count;
  }
  EXPECT_EQ(count, 110);  // 40 + 10 + 40 + 10 + 10 frames
}

TEST_F(CliTest, SameInputTwiceSameCsv) {
  const std::string options = " --set memory.time_limit_ms=0 memory.max_wm_locations=20 --out ";
  ASSERT_EQ(Memloop("run " + Images() + options + dir_.File("a.csv")).exit_code, 0);
  ASSERT_EQ(Memloop("run " + Images() + options + dir_.File("b.csv")).exit_code, 0);
  const std::string first = WithoutTimes(ReadFile(dir_.File("a.csv")));
  EXPECT_EQ(first, WithoutTimes(ReadFile(dir_.File("b.csv"))));
  EXPECT_GT(first.size(), 1000u);
}

TEST_F(CliTest, RunsOnAVideo) {
  const std::string video = dir_.File("route.avi");
  {
    cv::VideoWriter writer(video, cv::VideoWriter::fourcc('M', 'J', 'P', 'G'), 10,
                           cv::Size(320, 240));
    ASSERT_TRUE(writer.isOpened());
    for (int index = 1; index <= 30; ++index) {
      writer.write(cv::imread(Images() + "/" + std::to_string(index) + ".png"));
    }
  }
  const Outcome run = Memloop("run " + video + " --out " + dir_.File("video.csv"));
  EXPECT_EQ(run.exit_code, 0) << run.output;
  EXPECT_TRUE(Contains(run.output, "images: 30 processed, 0 skipped")) << run.output;
  EXPECT_TRUE(Contains(ReadFile(dir_.File("video.csv")), "\"frame 30\""));
  // 10 frames per second sampled at 4 Hz: frames at 0, 250, 500, ... ms, i.e. the first frame at
  // or after each: 1, 4, 6, 9, 11, ... (12 of 30), named by their number in the video.
  const Outcome sampled = Memloop("run " + video + " --rate 4 --out " + dir_.File("sampled.csv"));
  EXPECT_EQ(sampled.exit_code, 0) << sampled.output;
  EXPECT_TRUE(Contains(sampled.output, "images: 12 processed")) << sampled.output;
  const std::string rows = ReadFile(dir_.File("sampled.csv"));
  for (const char* frame :
       {"\"frame 1\"", "\"frame 4\"", "\"frame 6\"", "\"frame 9\"", "\"frame 29\""}) {
    EXPECT_TRUE(Contains(rows, frame)) << frame << "\n" << rows;
  }
  EXPECT_FALSE(Contains(rows, "\"frame 2\""));
  EXPECT_EQ(Memloop("run " + video + " --rate 0").exit_code, 2);  // not a positive rate
  const Outcome camera = Memloop("run --camera 57");
  EXPECT_EQ(camera.exit_code, 1);
  EXPECT_TRUE(Contains(camera.output, "memloop: error: camera 57: cannot be opened"))
      << camera.output;
}

TEST_F(CliTest, CorruptImageIsWarnedSkippedAndCounted) {
  const cv::Mat image = cv::imread(Images() + "/1.png");
  for (const char* name : {"1.png", "2.png", "4.png"}) cv::imwrite(dir_.File(name), image);
  std::ofstream(dir_.File("3.png")) << "truncated";
  // A JPEG cut in the middle decodes without an error (grey rows), so it is caught by its end.
  std::vector<unsigned char> jpeg;
  cv::imencode(".jpg", image, jpeg);
  std::ofstream(dir_.File("5.jpg"), std::ios::binary)
      .write(reinterpret_cast<const char*>(jpeg.data()), jpeg.size() / 2);
  const Outcome run = Memloop("run " + dir_.path().string());
  EXPECT_EQ(run.exit_code, 0) << run.output;
  EXPECT_TRUE(Contains(run.output, "skipping 3.png: not a readable image")) << run.output;
  EXPECT_TRUE(Contains(run.output, "skipping 5.jpg: truncated JPEG")) << run.output;
  EXPECT_TRUE(Contains(run.output, "3 processed, 2 skipped")) << run.output;
}

TEST_F(CliTest, BadInputsFailWithOneClearLine) {
  const std::string missing = dir_.File("missing");
  struct Case {
    std::string arguments;
    std::string message;
    bool alone = true;  // the error is all the output (no OpenCV, FFmpeg or GStreamer chatter)
  };
  std::filesystem::create_directories(dir_.File("empty"));
  std::filesystem::create_directories(dir_.File("junk"));
  std::ofstream(dir_.File("junk/a.jpg")) << "junk";
  std::ofstream(dir_.File("clip.mp4")) << "not a video";
  std::ofstream(dir_.File("noise.avi")) << std::string(5000, '\x5a') << "RIFF";
  const std::vector<Case> cases = {
      {"run " + missing, missing + ": no such file or folder"},
      {"run " + dir_.File("empty"), dir_.File("empty") + ": the folder holds no image"},
      {"run " + dir_.File("junk"), dir_.File("junk") + ": no readable image (1 skipped)", false},
      {"run " + dir_.File("clip.mp4"), dir_.File("clip.mp4") + ": cannot be opened as a video"},
      {"run " + dir_.File("noise.avi"), dir_.File("noise.avi") + ": cannot be opened as a video"},
      {"run " + Images() + " --set memory.stm=3", "Unknown parameter 'memory.stm'"},
      {"run " + Images() + " --set filter.loop_threshold=7",
       "Invalid parameter filter.loop_threshold = '7': must be in [0, 1]"},
      {"run " + Images() + " --db /dev/null", "/dev/null: is not a regular file"},
      {"run " + Images() + " --db " + dir_.File("empty"),
       dir_.File("empty") + ": is a folder; a map is a file"},
      {"run " + Images() + " --db " + missing + "/map.db",
       missing + "/map.db: cannot create the map: the folder " + missing + " does not exist"},
      {"run " + Images() + " --realtime-priority 100",
       "real-time priority 100 is out of range (1-99)"},
      {"run " + Images() + " --realtime-priority -3",
       "real-time priority -3 is out of range (1-99)"},
  };
  for (const Case& c : cases) {
    const Outcome outcome = Memloop(c.arguments);
    EXPECT_NE(outcome.exit_code, 0) << c.arguments;
    EXPECT_TRUE(Contains(outcome.output, "memloop: error: " + c.message)) << c.arguments << "\n"
                                                                          << outcome.output;
    if (c.alone) {
      EXPECT_EQ(std::count(outcome.output.begin(), outcome.output.end(), '\n'), 1)
          << outcome.output;
    }
  }
}

// Replaces field `field` of data line `row` (1 = first image) of a run CSV; row 0: every row.
std::string WithField(const std::string& csv, int row, int field, const std::string& value) {
  std::istringstream in(csv);
  std::string out;
  int number = 0;
  for (std::string line; std::getline(in, line); ++number) {
    if (number > 0 && (row == 0 || number == row)) {
      std::vector<std::string> fields;
      std::stringstream cells(line);
      for (std::string cell; std::getline(cells, cell, ',');) fields.push_back(cell);
      if (line.back() == ',') fields.emplace_back();
      fields[field] = value;
      line.clear();
      for (size_t i = 0; i < fields.size(); ++i) line += (i ? "," : "") + fields[i];
    }
    out += line + "\n";
  }
  return out;
}

// --ignored-as-true: the route's loops with the frame after each match marked ignored (2 in a
// text matrix) score, with the flag, exactly what they score with those frames made loops, and
// strictly no more than that.
TEST_F(CliTest, EvalIgnoredAsTrueCountsTheIgnoredBandAsFound) {
  const std::string csv_path = dir_.File("lenient.csv");
  ASSERT_EQ(
      Memloop("run " + Images() + " --set memory.time_limit_ms=0 --out " + csv_path).exit_code, 0);
  const int images = static_cast<int>(std::distance(std::filesystem::directory_iterator(Images()),
                                                    std::filesystem::directory_iterator()));
  std::vector<std::vector<char>> band(images, std::vector<char>(images, '0'));
  std::vector<std::vector<char>> loops = band;
  std::ifstream in(folder_->File("ground_truth_pairs.csv"));
  std::string line;
  std::getline(in, line);  // query,match: "80.png,1.png", image k is "k+1.png"
  while (std::getline(in, line)) {
    const int query = std::stoi(line.substr(0, line.find('.'))) - 1;
    const int match = std::stoi(line.substr(line.find(',') + 1)) - 1;
    band[query][match] = loops[query][match] = '1';
    if (match + 1 < query && band[query][match + 1] == '0') {
      band[query][match + 1] = '2';
      loops[query][match + 1] = '1';
    }
  }
  const auto write = [&](const std::string& name, const std::vector<std::vector<char>>& matrix) {
    std::ofstream out(dir_.File(name));
    for (const auto& row : matrix) {
      for (char cell : row) out << cell << ' ';
      out << "\n";
    }
  };
  write("band.txt", band);
  write("loops.txt", loops);
  const auto recall_line = [](const std::string& output) {
    const size_t at = output.find("recall at 100% precision");
    return output.substr(at, output.find('\n', at) - at);
  };
  const Outcome strict = Memloop("eval " + csv_path + " " + dir_.File("band.txt"));
  const Outcome lenient =
      Memloop("eval " + csv_path + " " + dir_.File("band.txt") + " --ignored-as-true");
  const Outcome as_loops = Memloop("eval " + csv_path + " " + dir_.File("loops.txt"));
  ASSERT_EQ(strict.exit_code, 0) << strict.output;
  ASSERT_EQ(lenient.exit_code, 0) << lenient.output;
  ASSERT_EQ(as_loops.exit_code, 0) << as_loops.output;
  EXPECT_TRUE(Contains(lenient.output, "(ignored pairs counted as loops)")) << lenient.output;
  EXPECT_EQ(recall_line(lenient.output), recall_line(as_loops.output)) << lenient.output;
  const auto percent = [&](const Outcome& outcome) {
    const std::string text = recall_line(outcome.output);
    return std::stod(text.substr(text.find(':') + 1));
  };
  EXPECT_LE(percent(strict), percent(lenient));
  EXPECT_GT(percent(lenient), 50.0);
  const Outcome json =
      Memloop("eval " + csv_path + " " + dir_.File("band.txt") + " --ignored-as-true --json");
  EXPECT_TRUE(Contains(json.output, "\"ignored_as_true\": true")) << json.output;
  const Outcome report = Memloop("report " + csv_path + " " + dir_.File("band.txt") +
                                 " --ignored-as-true --out " + dir_.File("lenient.html"));
  ASSERT_EQ(report.exit_code, 0) << report.output;
  EXPECT_TRUE(Contains(ReadFile(dir_.File("lenient.html")), "ignored pairs counted as loops"));
}

TEST_F(CliTest, EvalRefusesMalformedRunCsvsWithOneLine) {
  const std::string csv_path = dir_.File("good.csv");
  ASSERT_EQ(
      Memloop("run " + Images() + " --set memory.time_limit_ms=0 --out " + csv_path).exit_code, 0);
  ASSERT_EQ(Memloop("generate " + dir_.File("new/route")).exit_code, 0);  // creates the folder
  EXPECT_TRUE(std::filesystem::exists(dir_.File("new/route/ground_truth_pairs.csv")));
  const std::string truth = folder_->File("ground_truth_pairs.csv");
  ASSERT_EQ(Memloop("eval " + csv_path + " " + truth).exit_code, 0);
  const std::string good = ReadFile(csv_path);
  const int last_row = static_cast<int>(std::count(good.begin(), good.end(), '\n')) - 1;
  // Columns: 0 image, 5 matched_images, 7 hypothesis_value.
  struct Case {
    std::string csv;
    std::string message;
  };
  const std::vector<Case> cases = {
      {WithField(good, 3, 0, "-3"), "line 4: image '-3' is out of range"},
      {WithField(good, 0, 0, "-5"), "line 2: image '-5' is out of range"},
      {WithField(good, 3, 0, "nan"), "line 4: image 'nan' is not a whole number"},
      {WithField(good, 3, 0, "1.5"), "line 4: image '1.5' is not a whole number"},
      {WithField(good, 3, 0, "1"), "line 4: image '1' does not follow image 1"},
      {WithField(good, 3, 7, "nan"), "line 4: hypothesis_value 'nan' is not a number"},
      {WithField(good, 3, 7, "1.5"), "line 4: hypothesis_value '1.5' is out of range"},
      {WithField(good, 60, 5, "-2"), "line 61: matched_images '-2' is out of range"},
      {WithField(good, last_row, 0, "30000"), "image 30000 (last line) is beyond"},
  };
  for (const Case& c : cases) {
    std::ofstream(dir_.File("bad.csv")) << c.csv;
    const Outcome outcome = Memloop("eval " + dir_.File("bad.csv") + " " + truth);
    EXPECT_EQ(outcome.exit_code, 1) << c.message;
    EXPECT_TRUE(
        Contains(outcome.output, "memloop: error: " + dir_.File("bad.csv") + ": " + c.message))
        << outcome.output;
    EXPECT_EQ(std::count(outcome.output.begin(), outcome.output.end(), '\n'), 1) << outcome.output;
  }
  // A 16-bit ground-truth image is refused, not read as labels.
  cv::Mat wide(60, 60, CV_16U, cv::Scalar(255));
  cv::imwrite(dir_.File("truth16.png"), wide);
  const Outcome wide_truth = Memloop("eval " + csv_path + " " + dir_.File("truth16.png"));
  EXPECT_EQ(wide_truth.exit_code, 1);
  EXPECT_TRUE(Contains(wide_truth.output, "must be 8-bit grayscale")) << wide_truth.output;
  // report: a negative or non-finite T_time is a usage error (exit 2).
  for (const char* bad : {"-5", "nan"}) {
    const Outcome report = Memloop("report " + csv_path + " " + truth + " --time-limit-ms " + bad +
                                   " --out " + dir_.File("r.html"));
    EXPECT_EQ(report.exit_code, 2) << bad << report.output;
    EXPECT_FALSE(std::filesystem::exists(dir_.File("r.html")));
  }
}

// /dev/full fails every write with ENOSPC, as a full disk does.
TEST_F(CliTest, FullDiskIsAnErrorNamingTheFile) {
  if (!std::filesystem::exists("/dev/full")) GTEST_SKIP() << "no /dev/full on this system";
  const Outcome run = Memloop("run " + Images() + " --set memory.time_limit_ms=0 --out /dev/full");
  EXPECT_EQ(run.exit_code, 1) << run.output;
  EXPECT_TRUE(Contains(run.output, "memloop: error: /dev/full: writing the results failed"))
      << run.output;
  const std::string csv = dir_.File("full.csv");
  ASSERT_EQ(Memloop("run " + Images() + " --set memory.time_limit_ms=0 --out " + csv).exit_code, 0);
  const Outcome report =
      Memloop("report " + csv + " " + folder_->File("ground_truth_pairs.csv") + " --out /dev/full");
  EXPECT_EQ(report.exit_code, 1) << report.output;
  EXPECT_TRUE(Contains(report.output, "memloop: error: /dev/full: cannot write the report"))
      << report.output;
}

TEST_F(CliTest, ForeignOrExistingDatabasesAreRefusedAndKept) {
  const std::string notes = dir_.File("notes.db");
  std::ofstream(notes) << "my notes";
  Outcome outcome = Memloop("run " + Images() + " --db " + notes);
  EXPECT_NE(outcome.exit_code, 0);
  EXPECT_TRUE(Contains(outcome.output, notes + ": not a memloop map")) << outcome.output;
  EXPECT_EQ(ReadFile(notes), "my notes");

  const std::string map = dir_.File("map.db");
  ASSERT_EQ(Memloop("run " + Images() + " --db " + map).exit_code, 0);
  const std::string before = ReadFile(map);
  outcome = Memloop("run " + Images() + " --db " + map);
  EXPECT_NE(outcome.exit_code, 0);
  EXPECT_TRUE(Contains(outcome.output, "already holds a memloop map")) << outcome.output;
  EXPECT_EQ(ReadFile(map), before);

  std::string damaged = before;
  for (size_t i = 4096; i < std::min<size_t>(damaged.size(), 12288); ++i) damaged[i] = 'x';
  std::ofstream(map, std::ios::binary | std::ios::trunc) << damaged;
  outcome = Memloop("run " + Images() + " --db " + map);
  EXPECT_NE(outcome.exit_code, 0);
  EXPECT_TRUE(Contains(outcome.output, map + ": ")) << outcome.output;
  EXPECT_EQ(ReadFile(map), damaged);
}

// A run refused for one output creates none of the others, so that the same command, once the
// output is fixed, is not refused for a map the failed run made.
TEST_F(CliTest, RefusedRunLeavesNoFileBehind) {
  const std::string map = dir_.File("map.db");
  std::filesystem::create_directories(dir_.File("folder"));
  for (const std::string& out : {dir_.File("missing/run.csv"), dir_.File("folder")}) {
    const Outcome refused = Memloop("run " + Images() + " --db " + map + " --out " + out);
    EXPECT_EQ(refused.exit_code, 1) << refused.output;
    EXPECT_TRUE(Contains(refused.output, "memloop: error: " + out + ": ")) << refused.output;
    EXPECT_FALSE(std::filesystem::exists(map)) << out;
  }
  const Outcome fixed = Memloop("run " + Images() + " --db " + map + " --out " +
                                dir_.File("run.csv") + " --set memory.time_limit_ms=0");
  EXPECT_EQ(fixed.exit_code, 0) << fixed.output;
  // And the other way: a map refused creates no CSV.
  const Outcome existing =
      Memloop("run " + Images() + " --db " + map + " --out " + dir_.File("second.csv"));
  EXPECT_EQ(existing.exit_code, 1);
  EXPECT_FALSE(std::filesystem::exists(dir_.File("second.csv")));
}

// run + eval on the generated route reproduce the precision and recall the run itself reports.
TEST_F(CliTest, EvalReproducesTheDemosOwnScore) {
  const Outcome demo = Memloop("demo --set memory.time_limit_ms=0 --out " + dir_.File("demo.csv"));
  ASSERT_EQ(demo.exit_code, 0) << demo.output;
  ASSERT_EQ(Memloop("generate " + dir_.path().string()).exit_code, 0);
  const std::string truth = dir_.File("ground_truth_pairs.csv");
  const Outcome eval = Memloop("eval " + dir_.File("demo.csv") + " " + truth);
  ASSERT_EQ(eval.exit_code, 0) << eval.output;
  // demo: "precision 100.0% (116/116), recall 96.7% (116/120 images with a loop)"
  const auto demo_line = demo.output.substr(demo.output.rfind("precision"));
  const auto counts = demo_line.substr(demo_line.find('(') + 1);
  const int true_positives = std::stoi(counts);
  const int detections = std::stoi(counts.substr(counts.find('/') + 1));
  EXPECT_TRUE(Contains(eval.output, "the run accepted, at its T_loop: " +
                                        std::to_string(detections) + " loop closures (true " +
                                        std::to_string(true_positives) + ", false " +
                                        std::to_string(detections - true_positives)))
      << eval.output;
  EXPECT_TRUE(Contains(eval.output, demo_line.substr(0, demo_line.find(" (")))) << eval.output;
  const std::string recall = demo_line.substr(demo_line.find("recall"));
  EXPECT_TRUE(Contains(eval.output, recall.substr(0, recall.find(" (")))) << eval.output;
  const std::string loop_images = recall.substr(recall.find('/') + 1);  // "121 images with a loop)"
  EXPECT_TRUE(Contains(eval.output, loop_images.substr(0, loop_images.find(')')))) << eval.output;
  EXPECT_TRUE(Contains(eval.output, "482 pairs")) << eval.output;  // SyntheticRoute's own count
  const Outcome json = Memloop("eval " + dir_.File("demo.csv") + " " + truth + " --json");
  EXPECT_TRUE(Contains(json.output, "\"recall_at_100_precision\"")) << json.output;
  EXPECT_TRUE(Contains(json.output, "\"curve\"")) << json.output;

  // Bad input to eval: a clear line and a nonzero exit.
  std::ofstream(dir_.File("bad_truth.txt")) << "0 1\n1\n";
  const Outcome bad = Memloop("eval " + dir_.File("demo.csv") + " " + dir_.File("bad_truth.txt"));
  EXPECT_NE(bad.exit_code, 0);
  EXPECT_TRUE(Contains(bad.output, "memloop: error: " + dir_.File("bad_truth.txt") +
                                       ": line 2 has 1 values, line 1 has 2"))
      << bad.output;
  const Outcome not_run = Memloop("eval " + truth + " " + truth);
  EXPECT_NE(not_run.exit_code, 0);
  EXPECT_TRUE(Contains(not_run.output, "not a memloop run CSV")) << not_run.output;
}

TEST_F(CliTest, ReportWithoutGnuplotSaysSo) {
  const std::string csv = dir_.File("run.csv");
  ASSERT_EQ(Memloop("run " + Images() + " --out " + csv).exit_code, 0);
  const std::string command = "PATH=/nonexistent " + std::string(MEMLOOP_CLI) + " report " + csv +
                              " " + folder_->File("ground_truth_pairs.csv") + " --out " +
                              dir_.File("r2.html") + " > " + dir_.File("out.txt") + " 2>&1";
  const int status = std::system(command.c_str());
  EXPECT_NE(WEXITSTATUS(status), 0);
  EXPECT_TRUE(
      Contains(ReadFile(dir_.File("out.txt")), "memloop: error: memloop report needs gnuplot"))
      << ReadFile(dir_.File("out.txt"));
}

// Issue 9's long sequences: generate writes one (images + pairs) that eval reads, and demo runs
// the same sequence on the fly, scored against the same ground truth.
TEST_F(CliTest, GeneratedPlacesOfAnyLength) {
  const std::string places =
      " --places 12 --frames-per-place 5 --revisit-every 3 --min-revisit-age 20";
  const std::string folder = dir_.File("places");
  ASSERT_EQ(Memloop("generate " + folder + places).exit_code, 0);
  int images = 0;
  for (const auto& entry : std::filesystem::directory_iterator(folder + "/images")) {
    images += entry.path().extension() == ".png";
  }
  const Outcome demo =
      Memloop("demo" + places + " --set memory.time_limit_ms=0 --out " + dir_.File("places.csv"));
  ASSERT_EQ(demo.exit_code, 0) << demo.output;
  EXPECT_TRUE(Contains(demo.output, "Generated places: " + std::to_string(images) + " images"))
      << demo.output;
  const auto line = demo.output.substr(demo.output.rfind("precision"));
  const std::string recall = line.substr(line.find("recall"));
  const Outcome eval = Memloop("eval " + dir_.File("places.csv") + " " + folder +
                               "/ground_truth_pairs.csv --time-limit-ms 1000");
  ASSERT_EQ(eval.exit_code, 0) << eval.output;
  EXPECT_TRUE(Contains(eval.output, recall.substr(0, recall.find(" (")))) << eval.output;
  EXPECT_TRUE(Contains(eval.output, "over T_time: 0 (0.00%)")) << eval.output;
  EXPECT_NE(Memloop("demo --places 0 --revisit-every -1").exit_code, 0);
}

TEST_F(CliTest, DemoPrintsPrecisionAndRecall) {
  const Outcome demo = Memloop("demo --set memory.time_limit_ms=0");
  ASSERT_EQ(demo.exit_code, 0) << demo.output;
  EXPECT_TRUE(Contains(demo.output, "precision 100.0%")) << demo.output;
  EXPECT_FALSE(Contains(demo.output, "[FALSE]")) << demo.output;
}

// A T_time under the machine's floor is said, with the floor and a T_time that leaves room for
// it (issue 37): 1 ms is under any machine's features for a 320x240 image, 700 ms over them.
TEST_F(CliTest, TimeLimitUnderTheFixedCostIsWarnedWithTheFloor) {
  const Outcome tight = Memloop("run " + Images() + " --set memory.time_limit_ms=1");
  ASSERT_EQ(tight.exit_code, 0) << tight.output;
  EXPECT_TRUE(Contains(tight.output,
                       "warning: T_time 1 ms is under this machine's floor: the "
                       "stages WM does not drive"))
      << tight.output;
  const Outcome roomy = Memloop("run " + Images() + " --out " + dir_.File("run.csv"));
  ASSERT_EQ(roomy.exit_code, 0) << roomy.output;
  EXPECT_FALSE(Contains(roomy.output, "floor")) << roomy.output;
  const Outcome eval = Memloop("eval " + dir_.File("run.csv") + " " +
                               folder_->File("ground_truth_pairs.csv") + " --time-limit-ms 700");
  EXPECT_TRUE(Contains(eval.output, "| fixed cost ")) << eval.output;
  // How much of each iteration the detector's thread had the CPU (cpu_ms): waits for it are
  // not the detector's work, and no transfer makes up for them.
  EXPECT_TRUE(Contains(eval.output, "detector's thread on the CPU: median ")) << eval.output;
}

// A real-time priority changes when the work runs, never what it finds: the same CSV as without
// (T_time off). Where the system refuses it, the run is refused saying what it takes, and leaves
// no file behind.
TEST_F(CliTest, RealTimePriorityGivesTheSameResults) {
  const std::string plain = dir_.File("plain.csv"), realtime = dir_.File("realtime.csv");
  ASSERT_EQ(Memloop("run " + Images() + " --set memory.time_limit_ms=0 --out " + plain).exit_code,
            0);
  const Outcome run = Memloop("run " + Images() + " --set memory.time_limit_ms=0 --out " +
                              realtime + " --realtime-priority 5");
  if (run.exit_code != 0) {
    EXPECT_TRUE(Contains(run.output, "cannot run at real-time priority 5 (SCHED_FIFO)"))
        << run.output;
    EXPECT_FALSE(std::filesystem::exists(realtime));
    GTEST_SKIP() << "this machine refuses SCHED_FIFO: " << run.output;
  }
  EXPECT_TRUE(Contains(run.output, "per-image threads at real-time priority 5")) << run.output;
  EXPECT_EQ(WithoutTimes(ReadFile(realtime)), WithoutTimes(ReadFile(plain)));
}

// Paced as a camera at 50 Hz: no frame is handed over sooner than 20 ms after the last, none is
// dropped, and the results are the run's at full speed (T_time off).
TEST_F(CliTest, PacedFramesComeNoFasterThanTheRate) {
  const std::string fast = dir_.File("fast.csv"), paced = dir_.File("paced.csv");
  ASSERT_EQ(Memloop("run " + Images() + " --set memory.time_limit_ms=0 --out " + fast).exit_code,
            0);
  const auto start = std::chrono::steady_clock::now();
  const Outcome run =
      Memloop("run " + Images() + " --set memory.time_limit_ms=0 --pace 50 --out " + paced);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const std::string rows = WithoutTimes(ReadFile(paced));
  EXPECT_EQ(rows, WithoutTimes(ReadFile(fast)));
  const auto images = std::count(rows.begin(), rows.end(), '\n') - 1;  // less the header
  ASSERT_GT(images, 10);
  EXPECT_GE(seconds, static_cast<double>(images - 1) / 50);
  const Outcome zero = Memloop("run " + Images() + " --pace 0");
  EXPECT_NE(zero.exit_code, 0);
  EXPECT_TRUE(Contains(zero.output, "--pace")) << zero.output;
}

// Long work is never silent in a log: with stdout not a terminal (here a pipe), a progress line
// every 500 images (or 30 s). Before, a 10,700-image run printed nothing for 3,103 images.
TEST_F(CliTest, LongWorkPrintsProgressLinesInALog) {
  const std::string folder = dir_.File("places");
  const Outcome generate = Memloop("generate " + folder + " --places 60 --revisit-every 0");
  ASSERT_EQ(generate.exit_code, 0) << generate.output;
  EXPECT_TRUE(Contains(generate.output, "progress: 500/600 images written (")) << generate.output;
  const Outcome run = Memloop("run " + folder + "/images --set memory.time_limit_ms=0");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_TRUE(Contains(run.output, "progress: 500/600 images, ")) << run.output;
  EXPECT_FALSE(Contains(run.output, "\r")) << "a terminal's bar in a log";
}

}  // namespace
}  // namespace memloop
