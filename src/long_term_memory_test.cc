#include "long_term_memory.h"

#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include "small_memory.h"
#include "temp_dir.h"

namespace memloop {
namespace {

Location MakeLocation(LocationId id, std::vector<WordId> words) {
  Location location;
  location.id = id;
  location.signature = testing::MakeSignature(words);
  location.neighbours = {id - 1, id + 1};
  location.images = {id};
  return location;
}

TEST(LongTermMemoryTest, ReadsSeeQueuedWritesAndCommittedOnes) {
  testing::TempDir dir;
  LongTermMemory ltm(dir.File("map.db"));
  ltm.Store(MakeLocation(5, {1, 2}));
  ltm.StoreWord(2, (cv::Mat_<float>(1, 2) << 0.5f, 0.25f));
  EXPECT_TRUE(ltm.Contains(5));
  EXPECT_EQ(ltm.LinksOf(5), (std::vector<LocationId>{4, 6}));
  EXPECT_EQ(*ltm.LoadWord(2), testing::FloatBytes({0.5f, 0.25f}));
  ltm.Flush();
  EXPECT_EQ(*ltm.LoadWord(2), testing::FloatBytes({0.5f, 0.25f}));
  ltm.RedirectLocation(6, 9);  // 6 was merged into 9
  EXPECT_EQ(ltm.LinksOf(5), (std::vector<LocationId>{4, 9}));
  const auto location = ltm.Retrieve(5);
  ASSERT_TRUE(location.has_value());
  EXPECT_EQ(location->signature.words, (std::vector<WordId>{1, 2}));
  EXPECT_EQ(location->neighbours, (std::set<LocationId>{4, 9}));
  EXPECT_FALSE(ltm.Contains(5));  // back in WM
  EXPECT_FALSE(ltm.Retrieve(5).has_value());
}

// The map survives the process being killed: what was committed (Flush) is in the file.
TEST(LongTermMemoryTest, SurvivesKill9) {
  testing::TempDir dir;
  const std::string path = dir.File("map.db");
  const pid_t child = fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    LongTermMemory ltm(path);
    for (int id = 1; id <= 50; ++id) ltm.Store(MakeLocation(id, {id, id + 1000}));
    ltm.Flush();
    for (int id = 51; id <= 2000; ++id) ltm.Store(MakeLocation(id, {id}));  // maybe written
    raise(SIGKILL);
  }
  int status = 0;
  waitpid(child, &status, 0);
  ASSERT_TRUE(WIFSIGNALED(status));
  LtmDatabase database(path, LtmDatabase::Mode::kOpen);  // passes quick_check
  EXPECT_GE(database.CountLocations(), 50);
  EXPECT_EQ(database.ReadLocation(50)->signature.words, (std::vector<WordId>{50, 1050}));
}

}  // namespace
}  // namespace memloop
