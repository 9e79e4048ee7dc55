// Resuming a map: after Close, after a crash right after a checkpoint (a copy of the file), and
// after kill -9 at random moments of the memloop tool. With T_time off, the resumed run gives the
// results an uninterrupted run gives, image for image.
#include <gtest/gtest.h>
#include <signal.h>
#include <sqlite3.h>
#include <sys/resource.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <random>
#include <thread>

#include "cli_helpers.h"
#include "memloop/detector.h"
#include "memloop/errors.h"
#include "memloop/run_csv.h"
#include "memloop/synthetic_route.h"
#include "short_route.h"
#include "temp_dir.h"

namespace memloop {
namespace {

namespace fs = std::filesystem;

using testing::ShortRoute;

Options WithBudget(int max_wm_locations) {
  Options options;
  options.memory.time_limit_ms = 0;
  options.memory.max_wm_locations = max_wm_locations;
  return options;
}

std::vector<Result> Process(Detector& detector, const SyntheticRoute& route, int begin, int end) {
  std::vector<Result> results;
  for (int index = begin; index < end; ++index) {
    results.push_back(detector.Process(route.Render(index), index));
  }
  return results;
}

void ExpectSameResults(const std::vector<Result>& expected, const std::vector<Result>& actual) {
  ASSERT_EQ(expected.size(), actual.size());
  for (size_t i = 0; i < expected.size(); ++i) {
    const Result& a = expected[i];
    const Result& b = actual[i];
    ASSERT_EQ(a.image_index, b.image_index);
    ASSERT_EQ(a.location_id, b.location_id) << "image " << a.image_index;
    ASSERT_EQ(a.hypothesis_id, b.hypothesis_id) << "image " << a.image_index;
    ASSERT_EQ(a.hypothesis_value, b.hypothesis_value) << "image " << a.image_index;
    ASSERT_EQ(a.loop_closure_id, b.loop_closure_id) << "image " << a.image_index;
    ASSERT_EQ(a.retrieved_ids, b.retrieved_ids) << "image " << a.image_index;
    ASSERT_EQ(a.transferred_ids, b.transferred_ids) << "image " << a.image_index;
    ASSERT_EQ(a.dictionary_size, b.dictionary_size) << "image " << a.image_index;
  }
}

int LoopClosures(const std::vector<Result>& results) {
  int count = 0;
  for (const Result& result : results) count += result.HasLoopClosure();
  return count;
}

class ResumeTest : public ::testing::TestWithParam<int> {
 protected:
  ResumeTest() : route_(ShortRoute()), options_(WithBudget(GetParam())) {
    testing::TempDir dir;
    Detector detector(options_, dir.File("map.db"));
    uninterrupted_ = Process(detector, route_, 0, route_.size());
  }
  std::vector<Result> After(int image) const {
    return {uninterrupted_.begin() + image, uninterrupted_.end()};
  }

  SyntheticRoute route_;
  Options options_;
  std::vector<Result> uninterrupted_;
  testing::TempDir dir_;
};

TEST_P(ResumeTest, ClosedMapGoesOnAsIfNeverStopped) {
  const int stop = route_.size() / 2 + 3;
  {
    Detector detector(options_, dir_.File("map.db"));
    Process(detector, route_, 0, stop);
    detector.Close();
  }
  Detector resumed(options_, dir_.File("map.db"), MapMode::kResume);
  EXPECT_EQ(resumed.last_image(), stop - 1);
  EXPECT_EQ(resumed.images_processed(), stop);
  EXPECT_EQ(resumed.CheckConsistency(), std::vector<std::string>());
  ExpectSameResults(After(stop), Process(resumed, route_, stop, route_.size()));
  EXPECT_GT(LoopClosures(After(stop)), 0) << "the test needs loop closures after the stop";
  EXPECT_EQ(resumed.CheckConsistency(), std::vector<std::string>());
}

// A crash right after a checkpoint: the file copied then is what a killed run leaves.
TEST_P(ResumeTest, FileLeftAtACheckpointGoesOnAsTheOriginal) {
  const int stop = route_.size() / 3;
  const std::string original_path = dir_.File("map.db");
  const std::string copy_path = dir_.File("copy.db");
  {
    Detector original(options_, original_path);
    original.SetWriterHeld(true);  // the copy must not depend on the writer having kept up
    Process(original, route_, 0, stop);
    original.Flush();
    for (const char* suffix : {"", "-wal"}) {
      if (fs::exists(original_path + suffix))
        fs::copy_file(original_path + suffix, copy_path + suffix);
    }
  }
  Detector resumed(options_, copy_path, MapMode::kResume);
  EXPECT_EQ(resumed.last_image(), stop - 1);
  EXPECT_EQ(resumed.CheckConsistency(), std::vector<std::string>());
  ExpectSameResults(After(stop), Process(resumed, route_, stop, route_.size()));
}

INSTANTIATE_TEST_SUITE_P(WmBudgets, ResumeTest, ::testing::Values(20, 30));

std::string FileBytes(const std::string& path) { return ReadFile(path); }

TEST(ResumeRefusalTest, OnlyAMemloopMapWithItsOwnWordsIsResumed) {
  const SyntheticRoute route(ShortRoute());
  testing::TempDir dir;
  const std::string path = dir.File("map.db");
  {
    Detector detector(WithBudget(20), path);
    Process(detector, route, 0, 5);
  }
  const std::string before = FileBytes(path);
  Options other_words = WithBudget(20);
  other_words.dictionary.nndr_ratio = 0.7;
  other_words.features.surf_hessian_threshold = 60;
  try {
    Detector refused(other_words, path, MapMode::kResume);
    ADD_FAILURE() << "other map-defining parameters were accepted";
  } catch (const ParameterError& error) {
    EXPECT_NE(std::string(error.what()).find("dictionary.nndr_ratio (map: 0.8, given: 0.7)"),
              std::string::npos)
        << error.what();
    EXPECT_NE(std::string(error.what()).find("surf.hessian_threshold"), std::string::npos);
  }
  EXPECT_EQ(FileBytes(path), before);
  EXPECT_THROW(Detector(WithBudget(20), dir.File("absent.db"), MapMode::kResume), DatabaseError);

  // The budget and the decision's parameters may change on resume.
  EXPECT_EQ(ReadMapOptions(path).memory.max_wm_locations, 20);
  Options other_budget = WithBudget(30);
  other_budget.filter.loop_threshold = 0.2;
  Detector resumed(other_budget, path, MapMode::kResume);
  EXPECT_EQ(resumed.last_image(), 4);
  resumed.Close();
  EXPECT_EQ(ReadMapOptions(path).memory.max_wm_locations, 30);
}

TEST(ResumeRefusalTest, MapOfAnOlderFormatIsRefusedUntouched) {
  testing::TempDir dir;
  const std::string path = dir.File("map.db");
  { Detector detector(WithBudget(20), path); }
  sqlite3* db = nullptr;
  ASSERT_EQ(sqlite3_open(path.c_str(), &db), SQLITE_OK);
  ASSERT_EQ(sqlite3_exec(db, "DELETE FROM resume_state; PRAGMA user_version=1;", nullptr, nullptr,
                         nullptr),
            SQLITE_OK);
  sqlite3_close(db);
  const std::string before = FileBytes(path);
  try {
    Detector refused(WithBudget(20), path, MapMode::kResume);
    ADD_FAILURE() << "a map of format 1 was resumed";
  } catch (const DatabaseError& error) {
    EXPECT_NE(std::string(error.what()).find("older memloop"), std::string::npos) << error.what();
  }
  EXPECT_EQ(FileBytes(path), before);
}

// Rewrites a map's LTM marks as maps of format 4-5 hold them: chunks of 65,536 word ids under
// ltm_marks.N, instead of 4,096 under word_marks.N (each a count of 64-bit blocks, then the
// blocks). Returns the number of marked words.
int RewriteMarksAsFormatFive(sqlite3* db) {
  std::vector<uint64_t> blocks;  // of every id, from id 0
  sqlite3_stmt* select = nullptr;
  sqlite3_prepare_v2(db, "SELECT key, value FROM resume_state WHERE key LIKE 'word_marks.%'", -1,
                     &select, nullptr);
  while (sqlite3_step(select) == SQLITE_ROW) {
    const size_t chunk = std::stoul(std::string(
        reinterpret_cast<const char*>(sqlite3_column_text(select, 0)) + strlen("word_marks.")));
    const auto* bytes = static_cast<const unsigned char*>(sqlite3_column_blob(select, 1));
    uint64_t count = 0;
    std::memcpy(&count, bytes, sizeof(count));
    if (blocks.size() < chunk * 64 + count) blocks.resize(chunk * 64 + count, 0);
    std::memcpy(blocks.data() + chunk * 64, bytes + sizeof(count), count * sizeof(uint64_t));
  }
  sqlite3_finalize(select);
  sqlite3_exec(db, "DELETE FROM resume_state WHERE key LIKE 'word_marks.%'", nullptr, nullptr,
               nullptr);
  int marked = 0;
  for (size_t first = 0; first < blocks.size(); first += 1024) {  // 1,024 blocks a chunk
    const std::vector<uint64_t> chunk(blocks.begin() + first,
                                      blocks.begin() + std::min(first + 1024, blocks.size()));
    std::vector<unsigned char> bytes(sizeof(uint64_t) * (chunk.size() + 1));
    const uint64_t count = chunk.size();
    std::memcpy(bytes.data(), &count, sizeof(count));
    std::memcpy(bytes.data() + sizeof(count), chunk.data(), count * sizeof(uint64_t));
    for (uint64_t block : chunk) marked += __builtin_popcountll(block);
    sqlite3_stmt* insert = nullptr;
    sqlite3_prepare_v2(db, "INSERT INTO resume_state(key, value) VALUES(?, ?)", -1, &insert,
                       nullptr);
    const std::string key = "ltm_marks." + std::to_string(first / 1024);
    sqlite3_bind_text(insert, 1, key.c_str(), -1, SQLITE_TRANSIENT);
    sqlite3_bind_blob(insert, 2, bytes.data(), static_cast<int>(bytes.size()), SQLITE_TRANSIENT);
    sqlite3_step(insert);
    sqlite3_finalize(insert);
  }
  return marked;
}

// The first value of the first row `query` gives, as text ("no answer" without one).
std::string FirstValue(sqlite3* db, const std::string& query) {
  std::string value = "no answer";
  sqlite3_exec(
      db, query.c_str(),
      [](void* out, int, char** values, char**) {
        *static_cast<std::string*>(out) = values[0] ? values[0] : "null";
        return 0;
      },
      &value, nullptr);
  return value;
}

// A map of format 4 (before images and location views were recorded, its LTM marks by chunks of
// 65,536 word ids) resumes with its marks, and is format 6 once its first checkpoint is written.
TEST(ResumeRefusalTest, MapOfFormatFourResumesAndIsUpgraded) {
  testing::TempDir dir;
  const std::string path = dir.File("map.db");
  const SyntheticRoute route(testing::ShortRoute());
  {
    Detector detector(WithBudget(5), path);
    for (int i = 0; i < 60; ++i) detector.Process(route.Render(i), i);
  }
  sqlite3* db = nullptr;
  ASSERT_EQ(sqlite3_open(path.c_str(), &db), SQLITE_OK);
  ASSERT_EQ(sqlite3_exec(db,
                         "UPDATE memory_locations SET data = substr(data, 1, length(data) - 4);"
                         "DROP TABLE images; DROP TABLE location_views;"
                         "UPDATE info SET value='4' WHERE key='format_version';"
                         "PRAGMA user_version=4;",
                         nullptr, nullptr, nullptr),
            SQLITE_OK);
  EXPECT_GT(RewriteMarksAsFormatFive(db), 0);  // LTM holds locations: their words are marked
  sqlite3_close(db);
  ASSERT_EQ(InspectMap(path).format_version, 4);
  {
    Detector resumed(WithBudget(5), path, MapMode::kResume);
    EXPECT_EQ(resumed.last_image(), 59);
    EXPECT_EQ(resumed.session_first_image(), 0);
    const std::vector<std::string> problems = resumed.CheckConsistency();  // the marks read back
    EXPECT_TRUE(problems.empty()) << problems.front();
    for (int i = 60; i < 70; ++i) resumed.Process(route.Render(i), i);
    EXPECT_TRUE(resumed.CheckConsistency().empty());
  }
  ASSERT_EQ(sqlite3_open(path.c_str(), &db), SQLITE_OK);
  const auto count = [&](const std::string& where) {
    return std::stoi(FirstValue(db, "SELECT count(*) FROM resume_state WHERE " + where));
  };
  EXPECT_EQ(count("key LIKE 'ltm_marks.%'"), 0);
  EXPECT_GT(count("key LIKE 'word_marks.%'"), 0);
  sqlite3_close(db);
  const MapInfo info = InspectMap(path);
  EXPECT_EQ(info.format_version, 6);
  EXPECT_EQ(info.integrity, "ok");
  ASSERT_EQ(info.sessions.size(), 1u);  // the images recorded since
  EXPECT_EQ(info.sessions[0].first_image, 60);
  {
    Detector again(WithBudget(5), path, MapMode::kResume);
    EXPECT_EQ(again.session_first_image(), 0);  // the first session starts at image 0
    EXPECT_EQ(again.last_image(), 69);
  }
}

// kill -9 of the memloop tool at random moments.
// The first value `query` answers on the map at `path` ("cannot open", "no answer").
std::string FirstValueIn(const std::string& path, const std::string& query) {
  sqlite3* db = nullptr;
  if (sqlite3_open(path.c_str(), &db) != SQLITE_OK) return "cannot open";
  const std::string value = FirstValue(db, query);
  sqlite3_close(db);
  return value;
}

std::string IntegrityCheck(const std::string& path) {
  return FirstValueIn(path, "PRAGMA integrity_check");
}

// FirstValueIn as a number (-1: no answer).
long long QueryNumber(const std::string& path, const std::string& query) {
  const std::string value = FirstValueIn(path, query);
  return value == "no answer" || value == "cannot open" ? -1 : std::stoll(value);
}

TEST(ResumeCliTest, KilledAtRandomMomentsResumesToTheUninterruptedResult) {
  testing::TempDir dir;
  SyntheticRoute(ShortRoute()).Write(dir.path().string());
  const std::string images = dir.File("images");
  const std::vector<std::string> budget = {"--set", "memory.time_limit_ms=0",
                                           "memory.max_wm_locations=30"};
  ASSERT_EQ(Memloop("run " + images + " --set memory.time_limit_ms=0 memory.max_wm_locations=30" +
                    " --out " + dir.File("whole.csv"))
                .exit_code,
            0);
  const std::string expected = WithoutTimes(ReadFile(dir.File("whole.csv")));
  const int total = CsvRows(dir.File("whole.csv"));
  ASSERT_GT(total, 60);
  ASSERT_TRUE(Contains(ReadFile(dir.File("whole.csv")), ";"));  // loop closures are in it

  // Kills at random rows, in order (3, or MEMLOOP_TEST_KILLS); each resumed run is killed
  // again, the last completes. A kill may come as a resumed run starts, before its first image.
  const char* kills_wanted = std::getenv("MEMLOOP_TEST_KILLS");
  const int kills = kills_wanted ? std::max(1, std::atoi(kills_wanted)) : 3;
  std::random_device device;
  std::vector<int> kill_rows;
  for (int k = 0; k < kills; ++k)
    kill_rows.push_back(10 + static_cast<int>(device() % (total - 30)));
  std::sort(kill_rows.begin(), kill_rows.end());
  const std::string map = dir.File("map.db");
  const std::string csv = dir.File("run.csv");
  int rows_at_kill = 0;
  int killed = 0;
  for (size_t k = 0; k <= kill_rows.size(); ++k) {
    std::vector<std::string> arguments = {"run", images, "--db", map, "--out", csv};
    if (k == 0) {
      arguments.insert(arguments.end(), budget.begin(), budget.end());
    } else {
      arguments.push_back("--resume");  // with the map's own parameters
    }
    const std::string log = dir.File("log" + std::to_string(k));
    const pid_t child = Start(arguments, log);
    int status = 0;
    if (k < kill_rows.size()) {
      status = SignalAfterRows(child, csv, kill_rows[k], SIGKILL);
      killed += WIFSIGNALED(status) && WTERMSIG(status) == SIGKILL;
    } else {
      waitpid(child, &status, 0);
    }
    const bool completed = WIFEXITED(status) && WEXITSTATUS(status) == 0;
    ASSERT_TRUE(completed || (k < kill_rows.size() && WIFSIGNALED(status))) << ReadFile(log);
    if (k > 0) {
      // The documented bound: with memory.checkpoint_interval=1, at most 2 images whose rows
      // were written are processed again: the kill may come while the image after them waits
      // for the older one's checkpoint to commit (CI, loaded: 40 rows, resumed after image 37).
      // A run killed as it starts may not have said where it resumes.
      const std::string output = ReadFile(log);
      const size_t at = output.find("after image ");
      ASSERT_TRUE(at != std::string::npos || k < kill_rows.size()) << output;
      if (at != std::string::npos) {
        const int resumed_after = std::stoi(output.substr(at + 12));
        EXPECT_GE(resumed_after + 1, rows_at_kill - 2) << "rows before the kill: " << rows_at_kill;
        EXPECT_LE(resumed_after + 1, rows_at_kill + 1);
      }
    }
    if (k < kill_rows.size()) {
      rows_at_kill = CsvRows(csv);
      const std::string text = ReadFile(csv);
      EXPECT_TRUE(text.empty() || text.back() == '\n') << "kill " << k << ": the CSV ends mid-line";
      EXPECT_EQ(IntegrityCheck(map), "ok") << "after kill " << k;
    }
  }
  EXPECT_GT(killed, 0) << "every run ended before its kill";
  std::istringstream resumed(WithoutTimes(ReadFile(csv)));
  std::istringstream whole(expected);
  std::string resumed_line;
  std::string whole_line;
  for (int line = 1; std::getline(whole, whole_line); ++line) {
    ASSERT_TRUE(std::getline(resumed, resumed_line)) << "the resumed CSV ends at line " << line;
    ASSERT_EQ(resumed_line, whole_line) << "line " << line << " (without times) differs";
  }
  EXPECT_FALSE(std::getline(resumed, resumed_line)) << "extra line: " << resumed_line;
}

// A map that cannot grow (the file size limit of the process, as a full disk would) stops the
// run with an error; the file stays at its last checkpoint, and --resume then completes the run
// with the results of an uninterrupted one.
TEST(ResumeCliTest, MapWriteFailureStopsTheRunAndTheMapResumes) {
  testing::TempDir dir;
  SyntheticRoute(ShortRoute()).Write(dir.path().string());
  const std::string images = dir.File("images");
  const std::string settings = " --set memory.time_limit_ms=0 memory.max_wm_locations=30";
  ASSERT_EQ(Memloop("run " + images + settings + " --out " + dir.File("whole.csv")).exit_code, 0);
  const std::string map = dir.File("map.db");
  const std::string csv = dir.File("run.csv");
  const pid_t child = fork();
  if (child == 0) {
    // Bytes per file: the map (8.8 MB at the end) outgrows it after 13 of 110 images. The first
    // commit (the map's creation, image 1 and its checkpoint, and what image 2 queued meanwhile,
    // more when the writer lags) must fit: at 512 KB it failed under load, before any checkpoint.
    const rlimit limit = {2 << 20, 2 << 20};
    setrlimit(RLIMIT_FSIZE, &limit);
    signal(SIGXFSZ, SIG_IGN);  // writes past the limit then fail with EFBIG
    freopen(dir.File("log").c_str(), "w", stdout);
    dup2(fileno(stdout), fileno(stderr));
    execl(MEMLOOP_CLI, MEMLOOP_CLI, "run", images.c_str(), "--db", map.c_str(), "--out",
          csv.c_str(), "--set", "memory.time_limit_ms=0", "memory.max_wm_locations=30", nullptr);
    _exit(127);
  }
  int status = 0;
  waitpid(child, &status, 0);
  const std::string log = ReadFile(dir.File("log"));
  ASSERT_TRUE(WIFEXITED(status)) << log;
  EXPECT_EQ(WEXITSTATUS(status), 1) << log;
  EXPECT_TRUE(Contains(log, "writing the map failed")) << log;
  EXPECT_TRUE(
      Contains(log, "map.db: writing the map failed: cannot read or write the file (SQLite: "))
      << log;
  EXPECT_LT(CsvRows(csv), CsvRows(dir.File("whole.csv")));
  EXPECT_EQ(IntegrityCheck(map), "ok");
  const Outcome resumed = Memloop("run " + images + " --db " + map + " --out " + csv + " --resume");
  ASSERT_EQ(resumed.exit_code, 0) << resumed.output << "\nthe stopped run's output:\n"
                                  << log << "rows: " << CsvRows(csv);
  EXPECT_EQ(WithoutTimes(ReadFile(csv)), WithoutTimes(ReadFile(dir.File("whole.csv"))));
}

// bench/pad_map.py (issue 39: a million LTM locations without two million images) adds copies
// of a map's LTM: the padded map passes SQLite's check, holds (copies + 1) x the LTM, and a run
// resumes on it. Kept here so that a change of the map's format that the script misses fails.
TEST(ResumeCliTest, PaddedMapHoldsCopiesOfLtmAndResumes) {
  testing::TempDir dir;
  SyntheticRoute(ShortRoute()).Write(dir.path().string());
  const std::string images = dir.File("images");
  fs::create_directories(dir.File("first"));
  for (int image = 1; image <= 70; ++image) {
    const std::string name = "/" + std::to_string(image) + ".png";
    fs::create_symlink(images + name, dir.File("first") + name);
  }
  // Stored locations, as inspect counts them (LTM and, since the close, STM and WM).
  const auto stored = [](const std::string& path) {
    const std::string info = Memloop("inspect " + path).output;
    const size_t at = info.find("locations: ");
    return at == std::string::npos ? -1 : std::stoi(info.substr(at + 11));
  };
  const std::string map = dir.File("map.db");
  const std::string settings =
      " --set memory.time_limit_ms=0 memory.stm_size=5 memory.max_wm_locations=10";
  const std::string first = "run " + dir.File("first") + settings + " --db " + map;
  ASSERT_EQ(Memloop(first + " --out " + dir.File("first.csv")).exit_code, 0);
  const int ltm = ReadRunCsv(dir.File("first.csv")).back().ltm_size;
  ASSERT_GT(ltm, 10);  // 70 images, STM 5, WM 10: most locations have left memory

  const std::string pad = std::string("python3 ") + MEMLOOP_SOURCE_DIR + "/bench/pad_map.py ";
  const std::string padded = dir.File("padded.db");
  const int stored_before = stored(map);
  ASSERT_EQ(std::system((pad + map + " " + padded + " 2 >/dev/null").c_str()), 0);
  EXPECT_EQ(stored(padded), stored_before + 2 * ltm);  // LTM's copies, not memory's
  // Each copy has words of its own, as many as LTM's locations hold, each held as often as its
  // original: no word is held by more LTM locations than before.
  const std::string ltm_words =
      "SELECT count(DISTINCT word_id) FROM signature_words WHERE location_id NOT IN "
      "(SELECT id FROM memory_locations)";
  const std::string most_held =
      "SELECT max(n) FROM (SELECT count(*) AS n FROM signature_words GROUP BY word_id)";
  const long long words_before = QueryNumber(map, "SELECT count(*) FROM words");
  const long long words_of_ltm = QueryNumber(map, ltm_words);
  ASSERT_GT(words_of_ltm, 100);
  EXPECT_EQ(QueryNumber(padded, "SELECT count(*) FROM words"), words_before + 2 * words_of_ltm);
  EXPECT_EQ(QueryNumber(padded, ltm_words), 3 * words_of_ltm);
  EXPECT_EQ(QueryNumber(padded, most_held), QueryNumber(map, most_held));
  EXPECT_EQ(IntegrityCheck(padded), "ok");
  EXPECT_EQ(stored(map), stored_before);  // the source is read, not changed

  const std::string csv = dir.File("resumed.csv");
  const Outcome resumed = Memloop("run " + images + " --db " + padded + " --resume --out " + csv);
  ASSERT_EQ(resumed.exit_code, 0) << resumed.output;
  EXPECT_EQ(CsvRows(csv), 110 - 70);
  // The copies are LTM to the resumed run (3 x ltm at its start; one image moves a few).
  EXPECT_GT(ReadRunCsv(csv).front().ltm_size, 3 * ltm - 5);

  // Refusals: a missing map, an output that exists (never overwritten).
  EXPECT_NE(
      std::system((pad + dir.File("none.db") + " " + dir.File("x.db") + " 2 2>/dev/null").c_str()),
      0);
  EXPECT_FALSE(fs::exists(dir.File("x.db")));
  const int resumed_map = stored(padded);
  EXPECT_NE(std::system((pad + map + " " + padded + " 2 2>/dev/null").c_str()), 0);
  EXPECT_EQ(stored(padded), resumed_map);
}

TEST(ResumeCliTest, UsageAndRefusals) {
  testing::TempDir dir;
  SyntheticRouteOptions tiny = ShortRoute();
  tiny.lap_frames = 12;
  tiny.detour_frames = 2;
  tiny.third_lap_frames = 2;
  SyntheticRoute(tiny).Write(dir.path().string());
  const std::string images = dir.File("images");
  const Outcome without_db = Memloop("run " + images + " --resume");
  EXPECT_EQ(without_db.exit_code, 2) << without_db.output;
  const Outcome absent = Memloop("run " + images + " --resume --db " + dir.File("absent.db"));
  EXPECT_EQ(absent.exit_code, 1);
  EXPECT_TRUE(Contains(absent.output, "absent.db")) << absent.output;
  ASSERT_EQ(Memloop("run " + images + " --db " + dir.File("map.db")).exit_code, 0);
  const std::string before = ReadFile(dir.File("map.db"));
  const Outcome other = Memloop("run " + images + " --resume --db " + dir.File("map.db") +
                                " --set features.type=orb");
  EXPECT_EQ(other.exit_code, 1);
  EXPECT_TRUE(Contains(other.output, "features.type (map: surf, given: orb)")) << other.output;
  EXPECT_EQ(ReadFile(dir.File("map.db")), before);
  // A completed map resumes with nothing left to do.
  const Outcome done = Memloop("run " + images + " --resume --db " + dir.File("map.db"));
  EXPECT_EQ(done.exit_code, 0) << done.output;
  EXPECT_TRUE(Contains(done.output, "images: 0 processed")) << done.output;
}

}  // namespace
}  // namespace memloop
