// Refused runs change no byte of any file and create none; the map is never ahead of the CSV
// (issue 35).
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <sstream>
#include <string>

#include "cli_helpers.h"
#include "folder_state.h"
#include "memloop/detector.h"
#include "memloop/synthetic_route.h"
#include "route_images_test.h"
#include "short_route.h"
#include "storage/ltm_database.h"
#include "temp_dir.h"

namespace memloop {
namespace {

namespace fs = std::filesystem;

class RefusalTest : public testing::RouteImagesTest<RefusalTest> {
 protected:
  // Runs `arguments`, expects exit `code` with one error line containing `message`, and no
  // file of the test's folder created, changed or removed.
  void ExpectRefusedUntouched(const std::string& arguments, int code, const std::string& message) {
    const auto before = FolderState(dir_.path().string());
    const Outcome outcome = Memloop(arguments);
    EXPECT_EQ(outcome.exit_code, code) << arguments << "\n" << outcome.output;
    EXPECT_TRUE(Contains(outcome.output, message)) << arguments << "\n" << outcome.output;
    EXPECT_EQ(MessageLines(outcome.output), 1) << arguments << "\n" << outcome.output;
    EXPECT_EQ(Differences(before, FolderState(dir_.path().string())), "") << arguments;
  }
};

const char kSettings[] = " --set memory.time_limit_ms=0 memory.max_wm_locations=30";

// Before: an existing map was refused after SQLite had left an empty -wal and a 32 KB -shm
// beside it; --resume with another tool's CSV grew the map by 4 KB; --db X --out X, --rate nan
// and report --out INPUT exited 0.
TEST_F(RefusalTest, RefusedRunsChangeAndCreateNoFile) {
  const std::string map = dir_.File("map.db");
  const std::string csv = dir_.File("run.csv");
  ASSERT_EQ(Memloop("run " + Images() + kSettings + " --db " + map + " --out " + csv).exit_code, 0);
  ExpectRefusedUntouched("run " + Images() + " --db " + map, 1, "already holds a memloop map");
  ExpectRefusedUntouched("run " + Images() + " --db " + map + " --resume --set features.type=orb",
                         1, "features.type (map: surf, given: orb)");
  ExpectRefusedUntouched("run " + Images() + " --db " + map +
                             " --preset paper2011 --set "
                             "memory.localization=1",
                         1, "--preset");
  const std::string other = dir_.File("other_tool.csv");
  std::ofstream(other) << "time,x,y\n0,1,2\n";
  ExpectRefusedUntouched("run " + Images() + " --db " + map + " --resume --out " + other, 1,
                         "not a results CSV of this memloop");
  ExpectRefusedUntouched(
      "run " + Images() + " --db " + dir_.File("same.db") + " --out " + dir_.File("same.db"), 1,
      "is also the map (--db)");
  ExpectRefusedUntouched("run " + Images() + " --db " + map + " --out " + map, 1,
                         "is also the map (--db)");
  ExpectRefusedUntouched("run " + Images() + " --rate nan", 2, "--rate");
  ExpectRefusedUntouched("run --camera -1", 2, "a camera number (0 or more)");
  ExpectRefusedUntouched("frobnicate", 2, "unknown command 'frobnicate' (commands: run, demo");
  ExpectRefusedUntouched(
      "report " + csv + " " + folder_->File("ground_truth_pairs.csv") + " --out " + csv, 1,
      "is also the run's CSV");
}

// Depth maps given wrong: refused in one line naming the input or the option, nothing created.
TEST_F(RefusalTest, DepthGivenWrongIsRefusedInOneLine) {
  ExpectRefusedUntouched("run " + Images() + " --depth " + dir_.File("nowhere"), 1,
                         dir_.File("nowhere") + ": --depth: not a folder");
  fs::create_directories(dir_.File("depth"));
  std::ofstream(dir_.File("depth/other.png")) << "x";
  ExpectRefusedUntouched("run " + Images() + " --depth " + dir_.File("depth"), 1,
                         "--depth: holds no depth map named as the images are (e.g. 1.png)");
  ExpectRefusedUntouched("run " + Images() + " --depth-topic /camera/depth", 1,
                         "--depth-topic /camera/depth names a topic of a bag, and this is not one");
  for (const char* scale : {"0", "-3", "nan"}) {
    ExpectRefusedUntouched(
        "run " + Images() + " --depth-scale " + scale, 2,
        std::string("--depth-scale: must be units per metre, over 0, not '") + scale + "'");
  }
}

// Damaged, truncated and newer maps, and a damaged resume checkpoint: every use of them is
// refused with one line, and no file is created or changed (before: SQLite left an empty -wal
// and a 32 KB -shm beside each, and inspect printed the whole quick_check report, up to 101
// lines; on a damaged checkpoint it said "integrity: ok" while --resume refused the map).
TEST_F(RefusalTest, DamagedTruncatedAndNewerMapsAreRefusedInOneLineUntouched) {
  const std::string map = dir_.File("map.db");
  ASSERT_EQ(Memloop("run " + Images() + kSettings + " --db " + map).exit_code, 0);
  const std::string bytes = ReadFile(map);
  ASSERT_GT(bytes.size(), 40u * 4096);
  const auto copy = [&](const std::string& name, const std::string& content) {
    std::ofstream(dir_.File(name), std::ios::binary) << content;
    return dir_.File(name);
  };
  std::string scrambled = bytes;  // 20 pages of noise in the middle of the file
  for (size_t i = 16 * 4096; i < 36 * 4096; ++i)
    scrambled[i] = static_cast<char>(i * 2654435761u >> 13);
  const std::string damaged = copy("damaged.db", scrambled);
  const std::string truncated = copy("truncated.db", bytes.substr(0, bytes.size() / 2));
  const std::string newer = copy("newer.db", bytes);
  const std::string next = std::to_string(LtmDatabase::kFormatVersion + 1);
  Edit(newer, "PRAGMA user_version=" + next + "; UPDATE info SET value='" + next +
                  "' WHERE key='format_version'");
  const std::string checkpoint = copy("checkpoint.db", bytes);
  Edit(checkpoint, "UPDATE resume_state SET value=x'0102' WHERE key='counters'");

  const std::string run = "run " + Images() + kSettings;
  const std::vector<std::pair<std::string, std::string>> problems = {
      {damaged, ": the map is damaged ("},
      {truncated, ": the map is truncated: " + std::to_string(bytes.size() / 2) + " bytes of the " +
                      std::to_string(bytes.size())}};
  for (const auto& [path, problem] : problems) {
    for (const std::string& use :
         {run + " --db " + path + " --resume",
          run + " --db " + path + " --set memory.localization=1", "inspect " + path}) {
      ExpectRefusedUntouched(use, 1, path + problem);
    }
  }
  EXPECT_TRUE(Contains(Memloop("inspect " + damaged).output,
                       " problems found by SQLite's quick_check, the first: Page "));
  for (const std::string& use :
       {run + " --db " + newer + " --resume",
        run + " --db " + newer + " --set memory.localization=1", "inspect " + newer}) {
    ExpectRefusedUntouched(use, 1,
                           newer + ": map format " + next + " is newer than this memloop's (" +
                               std::to_string(LtmDatabase::kFormatVersion) + ")");
  }
  ExpectRefusedUntouched(run + " --db " + checkpoint + " --resume", 1,
                         checkpoint + ": cannot resume: the map is damaged (");
  ExpectRefusedUntouched(run + " --db " + map + " --resume --set memory.localization=1", 1,
                         "--resume extends the map, memory.localization=1 does not");
  // inspect shows what the LTM of a map with a damaged checkpoint holds, and exits 1 saying why.
  const auto before = FolderState(dir_.path().string());
  const Outcome inspect = Memloop("inspect " + checkpoint);
  EXPECT_EQ(inspect.exit_code, 1) << inspect.output;
  EXPECT_TRUE(Contains(inspect.output, "integrity: resume checkpoint damaged (")) << inspect.output;
  EXPECT_TRUE(Contains(inspect.output, "memloop: error: " + checkpoint +
                                           ": resume checkpoint damaged (the checkpoint's "
                                           "counters is truncated): --resume refuses it"))
      << inspect.output;
  EXPECT_EQ(Differences(before, FolderState(dir_.path().string())), "");
  EXPECT_TRUE(Contains(Memloop("inspect " + map).output, "integrity: ok)"));
}

// A sound map on a read-only file system is inspected and localized against (before: "not an
// SQLite database, or its header is damaged", as SQLite's WAL mode wanted to write a -shm file);
// one with a killed run's -wal, which SQLite cannot read without writing its -shm index beside
// it, is refused naming that cause.
TEST_F(RefusalTest, MapOnAReadOnlyFileSystemIsReadOrTheCauseNamed) {
  const std::string folder = fs::canonical(dir_.path()).string() + "/maps";
  fs::create_directories(folder);
  const std::string map = folder + "/map.db";
  ASSERT_EQ(Memloop("run " + Images() + kSettings + " --db " + map).exit_code, 0);
  const std::optional<Outcome> inspect = MemloopWithFolderReadOnly(folder, "inspect " + map);
  if (!inspect) GTEST_SKIP() << "no privilege to mount a folder read-only (unshare -m)";
  EXPECT_EQ(inspect->exit_code, 0) << inspect->output;
  EXPECT_TRUE(Contains(inspect->output, "integrity: ok)")) << inspect->output;
  const Outcome localize = *MemloopWithFolderReadOnly(
      folder, "run " + Images() + " --db " + map + " --set memory.localization=1");
  EXPECT_EQ(localize.exit_code, 0) << localize.output;
  EXPECT_TRUE(Contains(localize.output, "loop closures: ")) << localize.output;

  // A -wal with content: a copy of the map's log while a writer holds it open.
  const std::string copy = folder + "/copy.db";
  WithALog(map, "INSERT INTO info VALUES('note', 'x')", [&] {
    fs::copy_file(map, copy);
    fs::copy_file(map + "-wal", copy + "-wal");
  });
  const auto before = FolderState(dir_.path().string());
  const Outcome refused = *MemloopWithFolderReadOnly(folder, "inspect " + copy);
  EXPECT_EQ(refused.exit_code, 1) << refused.output;
  EXPECT_TRUE(Contains(refused.output, copy + ": cannot read the map's write-ahead log"))
      << refused.output;
  EXPECT_EQ(MessageLines(refused.output), 1) << refused.output;
  EXPECT_EQ(Differences(before, FolderState(dir_.path().string())), "");
}

// A CSV that lost its last rows (a full disk cut it) or belongs to another run is refused by
// --resume before anything is touched: the map would go on after rows the CSV lacks.
TEST_F(RefusalTest, ResumeRefusesACsvThatIsNotTheMapsOwn) {
  const std::string map = dir_.File("map.db");
  const std::string csv = dir_.File("run.csv");
  ASSERT_EQ(Memloop("run " + Images() + kSettings + " --db " + map + " --out " + csv).exit_code, 0);
  const std::string whole = ReadFile(csv);
  // The last two rows gone: the map holds images the CSV does not.
  std::string cut = whole.substr(0, whole.rfind('\n', whole.size() - 2) + 1);
  cut = cut.substr(0, cut.rfind('\n', cut.size() - 2) + 1);
  std::ofstream(csv, std::ios::trunc) << cut;
  ExpectRefusedUntouched("run " + Images() + " --db " + map + " --resume --out " + csv, 1,
                         "the rows between are lost");
  // Another run's CSV, with more rows than this map has images.
  std::ofstream(csv, std::ios::trunc) << whole << whole.substr(whole.find('\n') + 1);
  ExpectRefusedUntouched("run " + Images() + " --db " + map + " --resume --out " + csv, 1,
                         "is not this map's results");
}

// A looping symlink among the images is skipped and counted like a corrupt image (before, it
// stopped the whole run); a map left empty by a run killed before its first image says to start
// afresh.
TEST_F(RefusalTest, LoopingSymlinkIsSkippedAndEmptyMapSaysWhatToDo) {
  const std::string images = dir_.File("images");
  fs::create_directories(images);
  int copied = 0;
  for (const auto& entry : fs::directory_iterator(Images())) {
    if (copied++ < 6) fs::copy_file(entry.path(), images + "/" + entry.path().filename().string());
  }
  fs::create_symlink(images + "/loop.png", images + "/loop.png");
  const Outcome run = Memloop("run " + images + kSettings);
  EXPECT_EQ(run.exit_code, 0) << run.output;
  EXPECT_TRUE(Contains(run.output, "warning: skipping loop.png")) << run.output;
  EXPECT_TRUE(Contains(run.output, "6 processed, 1 skipped")) << run.output;

  std::ofstream(dir_.File("empty.db")).close();
  ExpectRefusedUntouched("run " + images + " --resume --db " + dir_.File("empty.db"), 1,
                         "run without --resume to start the map afresh");
}

// The CSV on a full disk (tests/full_disk_shim.cc: writes to it fail with ENOSPC past 8,192
// bytes, the last row cut) while the map's disk has room: the run stops with exit 1 naming the
// CSV, the map stays at the image before the cut row, and --resume writes every row of an
// uninterrupted run (before: the map held the cut row's image, --resume went on after it and the
// CSV lacked that row: 83 rows of 84).
TEST_F(RefusalTest, CsvOnAFullDiskThenResumeLosesNoRow) {
  const std::string map = dir_.File("map.db");
  const std::string csv = fs::canonical(dir_.path()).string() + "/run.csv";
  const std::string whole = dir_.File("whole.csv");
  ASSERT_EQ(Memloop("run " + Images() + kSettings + " --out " + whole).exit_code, 0);
  const Outcome full =
      MemloopWithEnvironment(std::string("LD_PRELOAD=") + FULL_DISK_SHIM +
                                 " FULL_DISK_FILE=" + csv + " FULL_DISK_BYTES=8192",
                             "run " + Images() + kSettings + " --db " + map + " --out " + csv);
  EXPECT_EQ(full.exit_code, 1) << full.output;
  EXPECT_TRUE(Contains(full.output, csv + ": writing the results failed")) << full.output;
  ASSERT_EQ(fs::file_size(csv), 8192u);
  ASSERT_LT(CsvRows(csv), CsvRows(whole));
  EXPECT_LE(ReadMapProgress(map).last_image, CsvRows(csv) - 1) << "the map is ahead of the CSV";
  const Outcome resumed =
      Memloop("run " + Images() + " --db " + map + " --out " + csv + " --resume");
  ASSERT_EQ(resumed.exit_code, 0) << resumed.output;
  EXPECT_EQ(WithoutTimes(ReadFile(csv)), WithoutTimes(ReadFile(whole)));
}

// The checkpoint of an image is written by the next Process(): a caller that cannot store a
// result closes at the checkpoint before it, and the map goes on from that image as if never
// stopped (before: the map held the image whose CSV row a full disk had cut, and --resume went
// on after it, the row lost).
TEST(MapBehindResultsTest, CloseAtLastCheckpointLeavesTheMapAtTheImageBefore) {
  const SyntheticRoute route(testing::ShortRoute());
  Options options;
  options.memory.time_limit_ms = 0;
  options.memory.max_wm_locations = 30;
  std::vector<Result> whole;
  {
    testing::TempDir dir;
    Detector detector(options, dir.File("whole.db"));
    for (int i = 0; i < 40; ++i) whole.push_back(detector.Process(route.Render(i), i));
  }
  testing::TempDir dir;
  const std::string map = dir.File("map.db");
  {
    Detector detector(options, map);
    for (int i = 0; i < 25; ++i) detector.Process(route.Render(i), i);
    detector.CloseAtLastCheckpoint();  // image 24's result could not be stored
  }
  EXPECT_EQ(ReadMapProgress(map).last_image, 23);
  EXPECT_EQ(ReadMapProgress(map).images_processed, 24);
  Detector resumed(ReadMapOptions(map), map, MapMode::kResume);
  ASSERT_EQ(resumed.last_image(), 23);
  for (int i = 24; i < 40; ++i) {
    const Result result = resumed.Process(route.Render(i), i);
    EXPECT_EQ(result.loop_closure_id, whole[i].loop_closure_id) << "image " << i;
    EXPECT_EQ(result.location_id, whole[i].location_id) << "image " << i;
    EXPECT_EQ(result.wm_size, whole[i].wm_size) << "image " << i;
  }
  EXPECT_TRUE(resumed.CheckConsistency().empty());
}

}  // namespace
}  // namespace memloop
