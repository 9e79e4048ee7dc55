// Nothing destroyed, nothing misnamed: no command writes over one of its inputs or another of its
// outputs however the path is spelled, whole files are written or none, a map another process is
// writing is named as such (not "damaged"), and each refusal names its real cause.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <csignal>
#include <filesystem>
#include <fstream>
#include <string>

#include "cli_helpers.h"
#include "folder_state.h"
#include "memloop/detector.h"
#include "memloop/errors.h"
#include "memloop/synthetic_route.h"
#include "route_images_test.h"
#include "short_route.h"
#include "temp_dir.h"

namespace memloop {
namespace {

namespace fs = std::filesystem;

const char kSettings[] = " --set memory.time_limit_ms=0 memory.max_wm_locations=30";

class OutputRuleTest : public testing::RouteImagesTest<OutputRuleTest> {
 protected:
  // Runs `arguments`: exit `code`, one line containing `message`, and no file of `folder` (this
  // test's own by default) created, changed or removed.
  void ExpectRefusedUntouched(const std::string& arguments, int code, const std::string& message,
                              const std::string& folder = "") {
    const std::string watched = folder.empty() ? dir_.path().string() : folder;
    const auto before = FolderState(watched);
    const Outcome outcome = Memloop(arguments);
    EXPECT_EQ(outcome.exit_code, code) << arguments << "\n" << outcome.output;
    EXPECT_TRUE(Contains(outcome.output, message)) << arguments << "\n" << outcome.output;
    EXPECT_EQ(MessageLines(outcome.output), 1) << arguments << "\n" << outcome.output;
    EXPECT_EQ(Differences(before, FolderState(watched)), "") << arguments;
  }

  // A map of the short route in this test's folder.
  std::string MakeMap(const std::string& name = "map.db") {
    const std::string map = dir_.File(name);
    EXPECT_EQ(Memloop("run " + Images() + kSettings + " --db " + map).exit_code, 0);
    return map;
  }

  // A copy of the first `count` route images in a folder of this test's.
  std::string FirstImages(int count) {
    const std::string folder = dir_.File("first" + std::to_string(count));
    fs::create_directories(folder);
    for (int i = 1; i <= count; ++i) {
      fs::copy_file(Images() + "/" + std::to_string(i) + ".png",
                    folder + "/" + std::to_string(i) + ".png");
    }
    return folder;
  }
};

// Before: `export MAP --out MAP` replaced a 14 MB map by a 79 KB JSON file, exit 0.
TEST_F(OutputRuleTest, ExportNeverWritesOverItsMapHoweverSpelled) {
  const std::string map = MakeMap();
  fs::create_directories(dir_.File("sub"));
  fs::create_symlink(map, dir_.File("link.db"));
  fs::create_hard_link(map, dir_.File("hard.db"));
  for (const std::string& out : {map, dir_.File("sub/../map.db"), dir_.File("./map.db"),
                                 dir_.File("link.db"), dir_.File("hard.db")}) {
    ExpectRefusedUntouched("export " + map + " --out " + out, 1, out + ": is also the map");
    ExpectRefusedUntouched(
        "export " + map + " --format pairs --intrinsics 300,300,160,120 --out " + out, 1,
        "is also the map");
  }
  EXPECT_EQ(Memloop("inspect " + map).exit_code, 0);
}

// Before: `run imgs --out imgs/1.png` replaced an image with the CSV, and `--config cfg.ini --out
// cfg.ini` the parameter file, exit 0.
TEST_F(OutputRuleTest, RunNeverWritesOverItsInputs) {
  const std::string images = FirstImages(8);
  ExpectRefusedUntouched("run " + images + kSettings + " --out " + images + "/3.png", 1,
                         images + "/3.png: is in the input folder");
  // A new file in a folder whose every file is read would be read as an image next time.
  ExpectRefusedUntouched("run " + images + kSettings + " --out " + images + "/run.csv", 1,
                         "whose every file is read as an image");
  ExpectRefusedUntouched("run " + images + kSettings + " --db " + images + "/map.db", 1,
                         "whose every file is read as an image");
  fs::create_symlink(images + "/2.png", dir_.File("alias.png"));
  ExpectRefusedUntouched("run " + images + kSettings + " --out " + dir_.File("alias.png"), 1,
                         "is in the input folder");
  const std::string config = dir_.File("settings.ini");
  std::ofstream(config) << "memory.time_limit_ms = 0\n";
  ExpectRefusedUntouched("run " + images + " --config " + config + " --out " + config, 1,
                         config + ": is also the parameter file (--config)");
  // A dataset folder: its listing and images are inputs, a results file beside them is not.
  const std::string tum = dir_.File("tum");
  ASSERT_EQ(Memloop("generate " + tum + " --layout tum").exit_code, 0);
  ExpectRefusedUntouched("run " + tum + kSettings + " --out " + tum + "/rgb.txt", 1,
                         tum + "/rgb.txt: is also the input's listing");
  ExpectRefusedUntouched("run " + tum + kSettings + " --out " + tum + "/rgb/5.png", 1,
                         "is also an image of the input");
}

// Before: only `--db X --out X` spelled alike was caught; ./X, an absolute path, sub/../X or a
// symlink to X gave exit 0 and the CSV was lost in the map (or the map in the CSV).
TEST_F(OutputRuleTest, TheMapAndTheCsvAreNeverOneFile) {
  const std::string images = FirstImages(6);
  fs::create_directories(dir_.File("sub"));
  fs::create_symlink(dir_.File("new.db"), dir_.File("dangling.csv"));
  for (const std::string& out : {dir_.File("./new.db"), dir_.File("sub/../new.db"),
                                 dir_.File("dangling.csv"), dir_.File("new.db-wal")}) {
    ExpectRefusedUntouched(
        "run " + images + kSettings + " --db " + dir_.File("new.db") + " --out " + out, 1,
        out + ": is also the map (--db)");
  }
  const std::string map = MakeMap();
  ExpectRefusedUntouched(
      "run " + Images() + " --db " + map + " --resume --out " + dir_.File("sub/../map.db"), 1,
      "is also the map (--db)");
  ExpectRefusedUntouched("run " + Images() + " --db " + map +
                             " --set memory.localization=1 --out " + dir_.File("./map.db"),
                         1, "is also the map (--db)");
}

// Before: while one run wrote Y.db, `--resume` on it said "the map is damaged (word 12337 is not
// in the dictionary's index history)"; a user told so may delete a good map.
TEST_F(OutputRuleTest, AMapAnotherProcessWritesIsNamedSoAndReadAsCommitted) {
  const std::string map = dir_.File("busy.db");
  const SyntheticRoute route(testing::ShortRoute());
  Options options;
  options.memory.time_limit_ms = 0;
  options.memory.max_wm_locations = 30;
  auto writer = std::make_unique<Detector>(options, map);
  for (int i = 0; i < 60; ++i) writer->Process(route.Render(i), i);
  const std::string pid = "(pid " + std::to_string(getpid()) + ")";
  const std::string busy = "the map is being written by another process " + pid;
  const std::string run = "run " + Images() + " --db " + map;
  const auto expect_refused = [&](const std::string& arguments, const std::string& use) {
    const Outcome outcome = Memloop(arguments);
    EXPECT_EQ(outcome.exit_code, 1) << outcome.output;
    EXPECT_TRUE(Contains(outcome.output, map + ": cannot " + use + ": " + busy)) << outcome.output;
    EXPECT_FALSE(Contains(outcome.output, "damaged")) << outcome.output;
    EXPECT_EQ(MessageLines(outcome.output), 1) << outcome.output;
  };
  expect_refused(run + " --resume", "resume");
  expect_refused(run + " --new-session", "add a session to it");
  expect_refused(run + " --set memory.localization=1", "localize against it");
  const Outcome inspect = Memloop("inspect " + map);
  EXPECT_EQ(inspect.exit_code, 0) << inspect.output;
  EXPECT_TRUE(Contains(inspect.output, "being written by another process " + pid))
      << inspect.output;
  const Outcome exported = Memloop("export " + map + " --out " + dir_.File("loops.json"));
  EXPECT_EQ(exported.exit_code, 0) << exported.output;
  EXPECT_TRUE(Contains(exported.output, "what it has committed so far")) << exported.output;
  // In this process too: a second writer is refused, as is localization.
  EXPECT_THROW({ Detector second(options, map, MapMode::kResume); }, DatabaseError);
  writer->Close();
  writer.reset();
  EXPECT_FALSE(fs::exists(map + "-lock"));
  const Outcome resumed = Memloop(run + " --resume");
  EXPECT_EQ(resumed.exit_code, 0) << resumed.output;
  EXPECT_FALSE(Contains(Memloop("inspect " + map).output, "being written"));
}

// Before: SQL statements, "cannot resume" for localization, "rgb.txt: cannot be read", and
// "cannot write the export file" without the reason.
TEST_F(OutputRuleTest, EachRefusalNamesItsRealCause) {
  const std::string map = MakeMap();
  // Localization against a map whose checkpoint is damaged.
  const std::string damaged = dir_.File("checkpoint.db");
  fs::copy_file(map, damaged);
  Edit(damaged, "UPDATE resume_state SET value=x'0102' WHERE key='counters'");
  ExpectRefusedUntouched("run " + Images() + " --db " + damaged + " --set memory.localization=1", 1,
                         damaged + ": cannot localize against it: the map is damaged (");
  // A damaged ROS 2 bag.
  const std::string bag = dir_.File("broken.db3");
  std::ofstream(bag) << std::string(8192, 'x');
  const Outcome broken = Memloop("run " + bag);
  EXPECT_EQ(broken.exit_code, 1) << broken.output;
  EXPECT_TRUE(Contains(broken.output, bag + ": not a readable ROS 2 bag")) << broken.output;
  EXPECT_FALSE(Contains(broken.output, "SELECT")) << broken.output;
  // --format tum on a folder that is not one, as euroc and kitti say.
  ExpectRefusedUntouched("run " + Images() + " --format tum", 1,
                         Images() + ": not a TUM folder (no rgb.txt)");
  // export to a missing folder, and on a full disk: the old file stays, no new one is left.
  ExpectRefusedUntouched(
      "export " + map + " --out " + dir_.File("missing/loops.json"), 1,
      "cannot write the export file: the folder " + dir_.File("missing") + " does not exist");
  const std::string out_folder = fs::canonical(dir_.path()).string() + "/out";
  fs::create_directories(out_folder);
  std::ofstream(out_folder + "/loops.json") << "previous export\n";
  const auto before = FolderState(out_folder);
  const Outcome full =
      MemloopWithEnvironment(std::string("LD_PRELOAD=") + FULL_DISK_SHIM +
                                 " FULL_DISK_FOLDER=" + out_folder + " FULL_DISK_BYTES=100",
                             "export " + map + " --out " + out_folder + "/loops.json");
  EXPECT_EQ(full.exit_code, 1) << full.output;
  EXPECT_TRUE(Contains(full.output, "No space left on device")) << full.output;
  EXPECT_EQ(Differences(before, FolderState(out_folder)), "");
}

// A sound map on read-only storage: --resume and --new-session name the folder (before: "unable
// to open database file (while running: PRAGMA journal_mode=WAL; ...)").
TEST_F(OutputRuleTest, AMapOnReadOnlyStorageNamesTheFolder) {
  const std::string folder = fs::canonical(dir_.path()).string() + "/maps";
  fs::create_directories(folder);
  const std::string map = folder + "/map.db";
  ASSERT_EQ(Memloop("run " + Images() + kSettings + " --db " + map).exit_code, 0);
  for (const char* mode : {" --resume", " --new-session"}) {
    const std::optional<Outcome> outcome =
        MemloopWithFolderReadOnly(folder, "run " + Images() + " --db " + map + mode);
    if (!outcome) GTEST_SKIP() << "no privilege to mount a folder read-only (unshare -m)";
    EXPECT_EQ(outcome->exit_code, 1) << outcome->output;
    EXPECT_TRUE(Contains(outcome->output, map + ": cannot write the map in the folder " + folder +
                                              " (Read-only file system)"))
        << outcome->output;
    EXPECT_EQ(MessageLines(outcome->output), 1) << outcome->output;
  }
}

// Before: a map whose -wal belongs to another map was refused but got a new 32 KB -shm.
TEST_F(OutputRuleTest, AMapRefusedForAForeignLogGetsNoFileBesideIt) {
  const std::string map = MakeMap();
  const std::string other = dir_.File("other.db");
  ASSERT_EQ(Memloop("run " + FirstImages(20) + kSettings + " --db " + other).exit_code, 0);
  WithALog(other, "DELETE FROM links; DELETE FROM locations",
           [&] { fs::copy_file(other + "-wal", map + "-wal"); });
  for (const std::string& use :
       {"inspect " + map, "run " + Images() + " --db " + map + " --resume"}) {
    const auto before = FolderState(dir_.path().string());
    const Outcome outcome = Memloop(use);
    EXPECT_EQ(outcome.exit_code, 1) << use << "\n" << outcome.output;
    EXPECT_FALSE(fs::exists(map + "-shm")) << use << "\n" << outcome.output;
    EXPECT_EQ(Differences(before, FolderState(dir_.path().string())), "") << use;
  }
}

// Before: --resume --out LONGER.csv cut another, longer run's CSV to this map's rows, exit 0.
TEST_F(OutputRuleTest, ResumeRefusesALongerRunsCsv) {
  const std::string whole = dir_.File("whole.csv");
  ASSERT_EQ(Memloop("run " + Images() + kSettings + " --out " + whole).exit_code, 0);
  const std::string images = FirstImages(30);
  const std::string map = dir_.File("short.db");
  ASSERT_EQ(Memloop("run " + images + kSettings + " --db " + map).exit_code, 0);
  ExpectRefusedUntouched("run " + images + " --db " + map + " --resume --out " + whole, 1,
                         whole + ": holds " + std::to_string(CsvRows(whole) - 30) +
                             " rows after image 29, the map's last: more than a run killed");
}

// Before: a map killed in its first fraction of a second was refused both by --resume ("start
// a new map instead") and by a plain run ("choose another --db path").
TEST_F(OutputRuleTest, AMapKilledBeforeItsFirstCheckpointResumesFromItsStart) {
  const std::string images = FirstImages(12);
  const std::string map = dir_.File("early.db");
  const pid_t child = fork();
  if (child == 0) {
    Options options;
    options.memory.time_limit_ms = 0;
    new Detector(options, map);  // the process dies before any image: no checkpoint
    _exit(0);
  }
  int status = 0;
  waitpid(child, &status, 0);
  ASSERT_TRUE(fs::exists(map));
  // A plain run refuses it, as any map, and leaves its files (SQLite's -shm index aside).
  const auto before = FolderState(dir_.path().string());
  const Outcome refused = Memloop("run " + images + " --db " + map);
  EXPECT_EQ(refused.exit_code, 1) << refused.output;
  EXPECT_TRUE(Contains(refused.output, "already holds a memloop map")) << refused.output;
  auto after = FolderState(dir_.path().string());
  after[map + "-shm"] = before.at(map + "-shm");
  EXPECT_EQ(Differences(before, after), "");
  const std::string csv = dir_.File("early.csv");
  const Outcome resumed = Memloop("run " + images + " --db " + map + " --resume --out " + csv);
  EXPECT_EQ(resumed.exit_code, 0) << resumed.output;
  EXPECT_TRUE(Contains(resumed.output, "12 processed")) << resumed.output;
  EXPECT_EQ(CsvRows(csv), 12);
}

TEST_F(OutputRuleTest, RealTimePriorityZeroIsOutOfRange) {
  ExpectRefusedUntouched("run " + Images() + " --realtime-priority 0", 1,
                         "real-time priority 0 is out of range (1-99)");
}

// Before: a second SIGINT ended the run with no line. The first is acknowledged at once; the
// run is paced at one image every 30 s, so the second arrives while it waits for the next image.
TEST_F(OutputRuleTest, ASecondSignalStopsAtOnceSayingSo) {
  const std::string csv = dir_.File("run.csv");
  const std::string log = dir_.File("log.txt");
  const pid_t child = Start({"run", Images(), "--pace", "0.033", "--db", dir_.File("map.db"),
                             "--out", csv, "--set", "memory.time_limit_ms=0"},
                            log);
  while (CsvRows(csv) < 1) std::this_thread::sleep_for(std::chrono::milliseconds(5));
  kill(child, SIGINT);
  while (!Contains(ReadFile(log), "a second signal stops at once")) {
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  kill(child, SIGINT);
  int status = 0;
  waitpid(child, &status, 0);
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 130);
  EXPECT_TRUE(Contains(ReadFile(log), "a second signal: stopping now")) << ReadFile(log);
  const Outcome resumed =
      Memloop("run " + Images() + " --db " + dir_.File("map.db") + " --resume --out " + csv);
  EXPECT_EQ(resumed.exit_code, 0) << resumed.output;
}

}  // namespace
}  // namespace memloop
