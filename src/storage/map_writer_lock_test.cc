#include "storage/map_writer_lock.h"

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <string>

#include "memloop/errors.h"
#include "memloop/map_info.h"
#include "temp_dir.h"

namespace memloop {
namespace {

// Whether another process can lock `map` to write it (a child process: flock locks are per open
// file, so this one would be refused by its own lock too, but the pid it names differs).
bool ChildCanLock(const std::string& map) {
  const pid_t child = fork();
  if (child == 0) {
    try {
      { MapWriterLock lock(map); }
      _exit(0);
    } catch (const DatabaseError&) {
      _exit(1);
    }
  }
  int status = 0;
  waitpid(child, &status, 0);
  return WIFEXITED(status) && WEXITSTATUS(status) == 0;
}

TEST(MapWriterLockTest, OneWriterAtATimeNamedByItsPidAndNothingLeftAfter) {
  testing::TempDir dir;
  const std::string map = dir.File("map.db");
  EXPECT_EQ(MapWriterProcess(map), 0);
  {
    MapWriterLock lock(map);
    EXPECT_EQ(MapWriterProcess(map), getpid());
    EXPECT_FALSE(ChildCanLock(map));
    try {
      MapWriterLock second(map);
      ADD_FAILURE() << "two writers";
    } catch (const DatabaseError& error) {
      EXPECT_EQ(std::string(error.what()),
                map + ": cannot write it: the map is being written by another process (pid " +
                    std::to_string(getpid()) +
                    "); it is sound: write it once that process has "
                    "ended");
    }
  }
  EXPECT_FALSE(std::filesystem::exists(MapLockPath(map)));
  EXPECT_EQ(MapWriterProcess(map), 0);
  EXPECT_TRUE(ChildCanLock(map));
  EXPECT_FALSE(std::filesystem::exists(MapLockPath(map)));
}

// A writer killed with -9 leaves its lock file, which holds nothing: the next writer takes it.
TEST(MapWriterLockTest, ALockFileLeftByAKilledWriterIsTakenOver) {
  testing::TempDir dir;
  const std::string map = dir.File("map.db");
  const pid_t child = fork();
  if (child == 0) {
    new MapWriterLock(map);  // never released: the process dies holding it
    _exit(0);
  }
  waitpid(child, nullptr, 0);
  ASSERT_TRUE(std::filesystem::exists(MapLockPath(map)));
  EXPECT_EQ(MapWriterProcess(map), 0);
  MapWriterLock lock(map);
  lock.Adopt();  // the map opened: the file now names this process
  EXPECT_EQ(MapWriterProcess(map), getpid());
}

TEST(MapWriterLockTest, AFolderThatCannotTakeTheLockIsNamed) {
  testing::TempDir dir;
  try {
    MapWriterLock lock(dir.File("missing/map.db"));
    ADD_FAILURE() << "locked in a missing folder";
  } catch (const DatabaseError& error) {
    EXPECT_EQ(std::string(error.what()), dir.File("missing/map.db") +
                                             ": cannot create the map: the folder " +
                                             dir.File("missing") + " does not exist");
  }
}

}  // namespace
}  // namespace memloop
