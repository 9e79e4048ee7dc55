#include "storage/ltm_database.h"

#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iterator>

#include "memloop/errors.h"
#include "small_memory.h"
#include "storage/map_integrity.h"
#include "temp_dir.h"

namespace memloop {
namespace {

MapLoopClosure Loop(ImageIndex query, ImageIndex match, LocationId query_location,
                    LocationId match_location, double probability, LoopClosurePose pose = {}) {
  MapLoopClosure loop;
  loop.query_image = query;
  loop.match_image = match;
  loop.query_location = query_location;
  loop.match_location = match_location;
  loop.probability = probability;
  loop.pose = std::move(pose);
  return loop;
}

using testing::ReadBytes;

Location SampleLocation() {
  Location location;
  location.id = 12;
  location.signature = testing::MakeSignature({5, 9, 5, 40});
  location.weight = 3;
  location.neighbours = {11, 13};
  location.loop_closures = {2};
  location.images = {11, 10, 3};
  return location;
}

void ExpectSameLocation(const Location& a, const Location& b) {
  EXPECT_EQ(a.id, b.id);
  EXPECT_EQ(a.weight, b.weight);
  EXPECT_EQ(a.signature.words, b.signature.words);
  ASSERT_EQ(a.signature.keypoints.size(), b.signature.keypoints.size());
  for (size_t i = 0; i < a.signature.keypoints.size(); ++i) {
    EXPECT_EQ(a.signature.keypoints[i].pt, b.signature.keypoints[i].pt);
    EXPECT_EQ(a.signature.keypoints[i].size, b.signature.keypoints[i].size);
    EXPECT_EQ(a.signature.keypoints[i].angle, b.signature.keypoints[i].angle);
    EXPECT_EQ(a.signature.keypoints[i].octave, b.signature.keypoints[i].octave);
  }
  EXPECT_EQ(a.neighbours, b.neighbours);
  EXPECT_EQ(a.loop_closures, b.loop_closures);
  EXPECT_EQ(a.images, b.images);
}

TEST(LtmDatabaseTest, RoundTrip) {
  testing::TempDir dir;
  const std::string path = dir.File("map.db");
  {
    LtmDatabase database(path, LtmDatabase::Mode::kCreate);
    database.Begin();
    database.WriteLocation(SampleLocation());
    database.WriteWord(40, testing::FloatBytes({1.5f, -2.0f}));
    database.WriteLoopClosure(Loop(41, 3, 42, 4, 0.25));
    database.WriteInfo("param.memory.stm_size", "25");
    database.Commit();
  }
  LtmDatabase database(path, LtmDatabase::Mode::kOpen);
  ExpectSameLocation(*database.ReadLocation(12), SampleLocation());
  EXPECT_FALSE(database.ReadLocation(99).has_value());
  EXPECT_EQ(*database.ReadWord(40), testing::FloatBytes({1.5f, -2.0f}));
  std::vector<LocationId> links_of_12;  // a neighbour that is also a loop closure: one link
  for (const auto& [from, to] : database.ReadAllLinks()) {
    if (from == 12) links_of_12.push_back(to);
  }
  EXPECT_EQ(links_of_12, (std::vector<LocationId>{2, 11, 13}));
  const auto loops = database.ReadLoopClosures();
  ASSERT_EQ(loops.size(), 1u);
  EXPECT_EQ(loops[0].query_image, 41);
  EXPECT_EQ(loops[0].match_image, 3);
  EXPECT_EQ(database.ReadInfo("param.memory.stm_size"), "25");
}

// Each loop closure's pose as found when it was accepted: read back with it, a loop closure
// without one (after one with one: a cached statement keeps its last values) says why, and one
// of a map made without intrinsics reads as not estimated.
TEST(LtmDatabaseTest, LoopClosurePosesAreKeptWithTheirLoopClosure) {
  testing::TempDir dir;
  const std::string path = dir.File("map.db");
  LoopClosurePose posed;
  posed.estimated = true;
  posed.inliers = 37;
  posed.has_pose = true;
  posed.translation = {0.6, 0, -0.8};
  posed.quaternion = {0, 0.6, 0, 0.8};
  LoopClosurePose unposed;
  unposed.estimated = true;
  unposed.inliers = 3;
  unposed.reason = "3 inliers";
  {
    LtmDatabase database(path, LtmDatabase::Mode::kCreate);
    database.WriteLoopClosure(Loop(10, 2, 11, 3, 0.5, posed));
    database.WriteLoopClosure(Loop(12, 4, 13, 5, 0.4, unposed));
    database.WriteLoopClosure(Loop(14, 6, 15, 7, 0.3));  // intrinsics unknown: nothing kept
  }
  LtmDatabase database(path, LtmDatabase::Mode::kRead);
  const auto loops = database.ReadLoopClosures();
  ASSERT_EQ(loops.size(), 3u);
  EXPECT_TRUE(loops[0].pose.has_pose);
  EXPECT_EQ(loops[0].pose.inliers, 37);
  EXPECT_EQ(loops[0].pose.translation, posed.translation);
  EXPECT_EQ(loops[0].pose.quaternion, posed.quaternion);
  EXPECT_TRUE(loops[1].pose.estimated);
  EXPECT_FALSE(loops[1].pose.has_pose);
  EXPECT_EQ(loops[1].pose.reason, "3 inliers");
  EXPECT_EQ(loops[1].pose.translation, (std::array<double, 3>{}));
  EXPECT_FALSE(loops[2].pose.estimated);
  EXPECT_EQ(loops[2].query_image, 14);
}

// A location's whole-image descriptor (features.whole_image) is stored with it, read back on
// retrieval, replaced, removed with it by a redirection; `memloop inspect` counts them.
TEST(LtmDatabaseTest, WholeImageDescriptorsAreKeptWithTheirLocation) {
  testing::TempDir dir;
  const std::string path = dir.File("map.db");
  LtmDatabase database(path, LtmDatabase::Mode::kCreate);
  Location location = SampleLocation();
  location.signature.whole_image = {9, 0, 200};
  database.WriteLocation(location);
  Location other = SampleLocation();
  other.id = 13;  // none
  database.WriteLocation(other);
  EXPECT_EQ(database.ReadLocation(12)->signature.whole_image, location.signature.whole_image);
  EXPECT_TRUE(database.ReadLocation(13)->signature.whole_image.empty());
  EXPECT_EQ(database.CountWholeImages(), 1);
  location.signature.whole_image.clear();  // written again without one: it goes
  database.WriteLocation(location);
  EXPECT_EQ(database.CountWholeImages(), 0);
  location.signature.whole_image = {1, 2};
  database.WriteLocation(location);
  database.RedirectLocation(12, 13);
  EXPECT_EQ(database.CountWholeImages(), 0);
}

// Storing a location again leaves its words' rows alone when the map already holds exactly its
// signature (a retrieved location transferred back), and replaces them on any difference: a word,
// a keypoint, more or fewer words, none.
TEST(LtmDatabaseTest, ALocationStoredAgainHoldsExactlyItsLatestSignature) {
  testing::TempDir dir;
  LtmDatabase database(dir.File("map.db"), LtmDatabase::Mode::kCreate);
  Location location = SampleLocation();
  database.WriteLocation(location);
  location.weight = 7;  // the rest unchanged
  database.WriteLocation(location);
  ExpectSameLocation(*database.ReadLocation(12), location);
  location.signature.words[1] = 41;
  database.WriteLocation(location);
  ExpectSameLocation(*database.ReadLocation(12), location);
  location.signature.keypoints[2].angle += 0.5f;
  database.WriteLocation(location);
  ExpectSameLocation(*database.ReadLocation(12), location);
  location.signature = testing::MakeSignature({5, 9, 5, 40, 6});
  database.WriteLocation(location);
  ExpectSameLocation(*database.ReadLocation(12), location);
  location.signature = testing::MakeSignature({5, 9});
  database.WriteLocation(location);
  ExpectSameLocation(*database.ReadLocation(12), location);
  location.signature = Signature();
  database.WriteLocation(location);
  ExpectSameLocation(*database.ReadLocation(12), location);
  location.signature = testing::MakeSignature({3});
  database.WriteLocation(location);
  ExpectSameLocation(*database.ReadLocation(12), location);
}

TEST(LtmDatabaseTest, ReplaceWordChangesEveryReferenceAndDropsTheOldWord) {
  testing::TempDir dir;
  LtmDatabase database(dir.File("map.db"), LtmDatabase::Mode::kCreate);
  database.WriteLocation(SampleLocation());
  database.WriteWord(5, testing::FloatBytes({1, 2}));
  database.ReplaceWord(5, 77);
  EXPECT_EQ(database.ReadLocation(12)->signature.words, (std::vector<WordId>{77, 9, 77, 40}));
  EXPECT_FALSE(database.ReadWord(5).has_value());
}

TEST(LtmDatabaseTest, RedirectLocationMovesLinksToTheSurvivor) {
  testing::TempDir dir;
  LtmDatabase database(dir.File("map.db"), LtmDatabase::Mode::kCreate);
  database.WriteLocation(SampleLocation());  // links to 11, 13 and loop closure 2
  database.RedirectLocation(13, 20);
  database.RedirectLocation(2, 12);  // a link to itself is dropped
  const Location location = *database.ReadLocation(12);
  EXPECT_EQ(location.neighbours, (std::set<LocationId>{11, 20}));
  EXPECT_TRUE(location.loop_closures.empty());
  database.RedirectLocation(12, 30);
  EXPECT_FALSE(database.ReadLocation(12).has_value());
  EXPECT_EQ(database.CountLocations(), 0);
}

class RefusedDatabaseTest : public ::testing::Test {
 protected:
  // Opening `path` as a new map must fail with a message containing `reason`, and leave it as it
  // was, byte for byte.
  void ExpectRefused(const std::string& path, const std::string& reason,
                     LtmDatabase::Mode mode = LtmDatabase::Mode::kCreate) {
    const std::string before = ReadBytes(path);
    try {
      LtmDatabase database(path, mode);
      FAIL() << "accepted " << path;
    } catch (const DatabaseError& error) {
      EXPECT_NE(std::string(error.what()).find(path), std::string::npos) << error.what();
      EXPECT_NE(std::string(error.what()).find(reason), std::string::npos) << error.what();
    }
    EXPECT_EQ(ReadBytes(path), before);
  }
  testing::TempDir dir_;
};

TEST_F(RefusedDatabaseTest, NotSqlite) {
  const std::string path = dir_.File("notes.db");
  std::ofstream(path) << "these are my notes, not a database\n";
  ExpectRefused(path, "not a memloop map");
  ExpectRefused(path, "not a memloop map", LtmDatabase::Mode::kPeek);
}

// A further read-only connection (the read-ahead thread's): the map's identity is checked, its
// rows are read, and nothing can be written through it.
TEST_F(RefusedDatabaseTest, PeekReadsAndNeverWrites) {
  const std::string path = dir_.File("map.db");
  LtmDatabase owner(path, LtmDatabase::Mode::kCreate);
  owner.WriteLocation(SampleLocation());
  LtmDatabase peek(path, LtmDatabase::Mode::kPeek);
  ExpectSameLocation(*peek.ReadLocation(12), SampleLocation());
  EXPECT_THROW(peek.WriteWord(99, {1, 2, 3, 4}), DatabaseError);
  ExpectRefused(dir_.File("absent.db"), "no such file", LtmDatabase::Mode::kPeek);
}

TEST_F(RefusedDatabaseTest, AnotherApplicationsDatabase) {
  const std::string path = dir_.File("other.db");
  {
    SqliteConnection other(path, SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE);
    other.Execute("CREATE TABLE customers(name TEXT); INSERT INTO customers VALUES('ada');");
  }
  ExpectRefused(path, "not a memloop map");
  ExpectRefused(path, "not a memloop map", LtmDatabase::Mode::kPeek);
}

TEST_F(RefusedDatabaseTest, ExistingMapIsNotOverwritten) {
  const std::string path = dir_.File("map.db");
  {
    LtmDatabase database(path, LtmDatabase::Mode::kCreate);
    database.WriteLocation(SampleLocation());
  }
  ExpectRefused(path, "already holds a memloop map");
  EXPECT_EQ(LtmDatabase(path, LtmDatabase::Mode::kOpen).CountLocations(), 1);
}

TEST_F(RefusedDatabaseTest, NewerFormat) {
  const std::string path = dir_.File("future.db");
  { LtmDatabase database(path, LtmDatabase::Mode::kCreate); }
  {
    SqliteConnection raw(path, SQLITE_OPEN_READWRITE);
    raw.Execute("PRAGMA user_version=99; UPDATE info SET value='99' WHERE key='format_version';");
  }
  ExpectRefused(path, "newer", LtmDatabase::Mode::kOpen);
}

// A header whose version disagrees with the map's own record was damaged; upgrading would not help.
TEST_F(RefusedDatabaseTest, DamagedHeaderIsNotANewerFormat) {
  const std::string path = dir_.File("scribbled.db");
  { LtmDatabase database(path, LtmDatabase::Mode::kCreate); }
  {
    SqliteConnection raw(path, SQLITE_OPEN_READWRITE);
    raw.Execute("PRAGMA user_version=2131899478;");
  }
  ExpectRefused(path,
                "header is damaged (format version 2131899478 in the header, " +
                    std::to_string(LtmDatabase::kFormatVersion) + " in the map)",
                LtmDatabase::Mode::kOpen);
}

// A run killed before SQLite folded its log: the map is in the -wal file. Refusing it reads it
// through a read-only connection, so neither file changes (a read-write one would fold the log).
TEST_F(RefusedDatabaseTest, MapStillInItsLogIsRefusedWithItsBytesKept) {
  const std::string path = dir_.File("killed.db");
  const pid_t child = fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    LtmDatabase database(path, LtmDatabase::Mode::kCreate);
    database.WriteLocation(SampleLocation());
    _exit(0);  // as kill -9: no close, no fold
  }
  int status = 0;
  waitpid(child, &status, 0);
  ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0);
  const std::string log = ReadBytes(path + "-wal");
  ASSERT_FALSE(log.empty());
  ExpectRefused(path, "already holds a memloop map");
  EXPECT_EQ(ReadBytes(path + "-wal"), log);
  {
    LtmDatabase reader(path, LtmDatabase::Mode::kRead);
    EXPECT_EQ(reader.CountLocations(), 1);
  }
  EXPECT_EQ(ReadBytes(path + "-wal"), log);
}

TEST_F(RefusedDatabaseTest, NotAFile) {
  std::filesystem::create_directory(dir_.File("folder.db"));
  ExpectRefused(dir_.File("folder.db"), "is a folder; a map is a file");
  ExpectRefused("/dev/null", "is not a regular file");
  ExpectRefused(dir_.File("no/such/folder/map.db"), "the folder");
  ExpectRefused(dir_.File("absent.db"), "no such file", LtmDatabase::Mode::kOpen);
  EXPECT_FALSE(std::filesystem::exists(dir_.File("absent.db")));
}

TEST_F(RefusedDatabaseTest, Damaged) {
  const std::string path = dir_.File("damaged.db");
  {
    LtmDatabase database(path, LtmDatabase::Mode::kCreate);
    database.Begin();
    for (int id = 1; id <= 300; ++id) {
      Location location = SampleLocation();
      location.id = id;
      database.WriteLocation(location);
    }
    database.Commit();
    SqliteConnection raw(path, SQLITE_OPEN_READWRITE);
    raw.Execute("PRAGMA wal_checkpoint(TRUNCATE);");
  }
  // Scribble over the middle of the file, past the header page.
  std::string bytes = ReadBytes(path);
  ASSERT_GT(bytes.size(), 16384u);
  for (size_t i = 8192; i < 16384; ++i) bytes[i] = static_cast<char>(i * 31);
  std::ofstream(path, std::ios::binary | std::ios::trunc) << bytes;
  ExpectRefused(path, "damaged", LtmDatabase::Mode::kOpen);
}

// The check reads the whole file (~10 minutes at 63 GB): a file opened again unchanged is not
// read again; a file changed since, or written just before its check, is.
TEST_F(RefusedDatabaseTest, IntegrityCheckedOncePerUnchangedFile) {
  const std::string path = dir_.File("map.db");
  {
    LtmDatabase database(path, LtmDatabase::Mode::kCreate);
    for (int id = 1; id <= 300; ++id) {
      Location location = SampleLocation();
      location.id = id;
      database.WriteLocation(location);
    }
  }
  // Modification times set, not waited for: the verdicts do not depend on how fast this runs.
  const auto written = [](const std::string& map, time_t offset_s) {
    for (const std::string& file : {map, map + "-wal"}) {
      if (!std::filesystem::exists(file)) continue;
      const timespec at[2] = {{time(nullptr) + offset_s, 0}, {time(nullptr) + offset_s, 0}};
      ASSERT_EQ(utimensat(AT_FDCWD, file.c_str(), at, 0), 0);
    }
  };
  written(path, -3600);  // an hour ago: a map resumed later
  const long long before = MapIntegrityChecksRun();
  EXPECT_EQ(LtmDatabase(path, LtmDatabase::Mode::kRead).CountLocations(), 300);
  EXPECT_EQ(MapIntegrityChecksRun(), before + 1);
  EXPECT_EQ(LtmDatabase(path, LtmDatabase::Mode::kRead).CountLocations(), 300);
  EXPECT_EQ(MapIntegrityChecksRun(), before + 1);  // unchanged: not read again

  // Written at its check (here: later, so that it stays so): checked at every opening (a write
  // in the same clock tick keeps the time).
  const std::string fresh = dir_.File("fresh.db");
  { LtmDatabase database(fresh, LtmDatabase::Mode::kCreate); }
  written(fresh, 3600);
  LtmDatabase(fresh, LtmDatabase::Mode::kRead);
  LtmDatabase(fresh, LtmDatabase::Mode::kRead);
  EXPECT_EQ(MapIntegrityChecksRun(), before + 3);

  // Damaged since: checked again, and refused.
  std::string bytes = ReadBytes(path);
  ASSERT_GT(bytes.size(), 16384u);
  for (size_t i = 8192; i < 16384; ++i) bytes[i] = static_cast<char>(i * 31);
  std::ofstream(path, std::ios::binary | std::ios::trunc) << bytes;
  ExpectRefused(path, "damaged", LtmDatabase::Mode::kRead);
  EXPECT_EQ(MapIntegrityChecksRun(), before + 4);
}

}  // namespace
}  // namespace memloop
