#include "storage/long_term_memory.h"

#include <dirent.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <fstream>
#include <functional>
#include <sstream>
#include <string>
#include <thread>

#include "memloop/errors.h"
#include "memloop/realtime.h"
#include "small_memory.h"
#include "temp_dir.h"

namespace memloop {
namespace {

using testing::MakeLtmLocation;

// The real-time priority (/proc's rt_priority: 0 under SCHED_OTHER) of this process' thread named
// `name`; -1 if there is none.
int RealTimePriorityOfThread(const std::string& name) {
  DIR* tasks = opendir("/proc/self/task");
  if (tasks == nullptr) return -1;
  int priority = -1;
  while (dirent* task = readdir(tasks)) {
    const std::string folder = std::string("/proc/self/task/") + task->d_name;
    std::string comm;
    std::getline(std::ifstream(folder + "/comm"), comm);
    if (comm != name) continue;
    std::string stat;
    std::getline(std::ifstream(folder + "/stat"), stat);
    std::istringstream fields(stat.substr(stat.rfind(')') + 2));  // from field 3 on
    std::string field;
    for (int k = 3; k <= 40 && fields >> field; ++k) {
      if (k == 40) priority = std::stoi(field);
    }
  }
  closedir(tasks);
  return priority;
}

// Under a real-time caller (memloop/realtime.h) the writer steps below its priority: it must not
// take a core from the per-image threads, nor wait behind other programs.
TEST(LongTermMemoryTest, WriterStepsBelowTheCallersRealTimePriority) {
#ifndef __linux__
  GTEST_SKIP() << "real-time priority: Linux only";
#endif
  testing::TempDir dir;
  bool allowed = false;
  int writer_priority = -1;
  std::thread caller([&] {
    try {
      SetThisThreadsRealTimePriority(3);
    } catch (const Error&) {
      return;
    }
    allowed = true;
    LongTermMemory ltm(dir.File("map.db"));
    ltm.Store(MakeLtmLocation(5, {1, 2}));
    ltm.Flush();  // the writer has run
    writer_priority = RealTimePriorityOfThread("memloop-writer");
  });
  caller.join();
  if (!allowed) GTEST_SKIP() << "this process may not use SCHED_FIFO (not root, no CAP_SYS_NICE)";
  EXPECT_EQ(writer_priority, 2);
}

TEST(LongTermMemoryTest, ReadsSeeQueuedWritesAndCommittedOnes) {
  testing::TempDir dir;
  LongTermMemory ltm(dir.File("map.db"));
  ltm.Store(MakeLtmLocation(5, {1, 2}));
  ltm.StoreWord(2, (cv::Mat_<float>(1, 2) << 0.5f, 0.25f));
  EXPECT_TRUE(ltm.Contains(5));
  EXPECT_EQ(ltm.LinksOf(5), (std::vector<LocationId>{4, 6}));
  EXPECT_EQ(*ltm.LoadWord(2), testing::FloatBytes({0.5f, 0.25f}));
  ltm.Flush();
  EXPECT_EQ(*ltm.LoadWord(2), testing::FloatBytes({0.5f, 0.25f}));
  ltm.RedirectLocation(6, 9, {5, 7});  // 6 (in memory) was merged into 9
  EXPECT_EQ(ltm.LinksOf(5), (std::vector<LocationId>{4, 9}));
  const auto location = ltm.Retrieve(5);
  ASSERT_TRUE(location.has_value());
  EXPECT_EQ(location->signature.words, (std::vector<WordId>{1, 2}));
  EXPECT_EQ(location->neighbours, (std::set<LocationId>{4, 9}));
  EXPECT_FALSE(ltm.Contains(5));  // back in WM
  EXPECT_FALSE(ltm.Retrieve(5).has_value());
}

// Localization's LTM: what leaves WM is kept in memory, read back as if written; the file stays.
TEST(LongTermMemoryTest, ReadOnlyKeepsWritesInMemory) {
  testing::TempDir dir;
  const std::string path = dir.File("map.db");
  {
    LongTermMemory ltm(path);
    ltm.Store(MakeLtmLocation(5, {1, 2}));
    ltm.StoreWord(2, (cv::Mat_<float>(1, 2) << 0.5f, 0.25f));
  }
  const std::string before = testing::ReadBytes(path);
  {
    LongTermMemory ltm(path, LtmDatabase::Mode::kRead);
    ASSERT_TRUE(ltm.Retrieve(5).has_value());  // into WM
    EXPECT_FALSE(ltm.Contains(5));
    ltm.Store(MakeLtmLocation(5, {1, 3}));  // back to LTM, with word 2 re-matched to word 3
    ltm.Store(MakeLtmLocation(7, {3}));     // a location the file never held
    ltm.StoreWord(3, (cv::Mat_<float>(1, 2) << 1.0f, 2.0f));
    ltm.ReplaceWord(3, 4);
    ltm.Flush();
    EXPECT_EQ(ltm.Peek(5)->signature.words, (std::vector<WordId>{1, 4}));
    EXPECT_EQ(ltm.Retrieve(7)->signature.words, (std::vector<WordId>{4}));
    EXPECT_EQ(*ltm.LoadWord(2), testing::FloatBytes({0.5f, 0.25f}));  // from the file
    EXPECT_FALSE(ltm.LoadWord(3).has_value());                        // renamed
    EXPECT_EQ(ltm.pending_bytes(), 0u);                               // nothing queued for a writer
  }
  EXPECT_EQ(testing::ReadBytes(path), before);
  LongTermMemory reopened(path, LtmDatabase::Mode::kRead);
  EXPECT_EQ(reopened.Peek(5)->signature.words, (std::vector<WordId>{1, 2}));
  EXPECT_FALSE(reopened.Contains(7));
}

// The map survives the process being killed: what was committed (Flush) is in the file.
// Runs `body` in a child process that is then killed with SIGKILL, wherever its writer is.
// True when the child died of that signal.
bool KilledAfter(const std::function<void()>& body) {
  const pid_t child = fork();
  if (child < 0) return false;
  if (child == 0) {
    body();
    raise(SIGKILL);
  }
  int status = 0;
  waitpid(child, &status, 0);
  return WIFSIGNALED(status) && WTERMSIG(status) == SIGKILL;
}

TEST(LongTermMemoryTest, SurvivesKill9) {
  testing::TempDir dir;
  const std::string path = dir.File("map.db");
  ASSERT_TRUE(KilledAfter([&] {
    LongTermMemory ltm(path);
    for (int id = 1; id <= 50; ++id) ltm.Store(MakeLtmLocation(id, {id, id + 1000}));
    ltm.Flush();
    for (int id = 51; id <= 2000; ++id) ltm.Store(MakeLtmLocation(id, {id}));  // maybe written
  }));
  LtmDatabase database(path, LtmDatabase::Mode::kOpen);  // passes quick_check
  EXPECT_GE(database.CountLocations(), 50);
  EXPECT_EQ(database.ReadLocation(50)->signature.words, (std::vector<WordId>{50, 1050}));
}

}  // namespace
}  // namespace memloop

namespace memloop {
namespace {

// Queued renames and redirections chain (A->S then S->S2): reads give the end of the chain
// whether the writer is behind (held) or has committed, and the same answer in both cases.
class LongTermMemoryChainTest : public ::testing::TestWithParam<bool> {};

TEST_P(LongTermMemoryChainTest, RenamesAndRedirectionsResolveToTheirEnd) {
  const bool writer_behind = GetParam();
  testing::TempDir dir;
  LongTermMemory ltm(dir.File("map.db"));
  ltm.SetWriterHeld(writer_behind);
  const auto sync = [&] {
    if (!writer_behind) ltm.Flush();
  };
  ltm.Store(MakeLtmLocation(5, {10, 11}));  // links 4 and 6
  ltm.StoreWord(10, (cv::Mat_<float>(1, 2) << 1.f, 2.f));
  sync();
  ltm.ReplaceWord(10, 20);  // word 10 re-matched to 20 ...
  sync();
  ltm.StoreWord(20, (cv::Mat_<float>(1, 2) << 3.f, 4.f));  // ... which left the dictionary ...
  sync();
  ltm.ReplaceWord(20, 30);  // ... and was re-matched to 30
  sync();
  ltm.RedirectLocation(6, 7, {5, 7});  // 6 merged into 7, then 7 into 8
  sync();
  ltm.RedirectLocation(7, 8, {5, 8});
  sync();
  EXPECT_FALSE(ltm.LoadWord(10).has_value());
  EXPECT_FALSE(ltm.LoadWord(20).has_value());
  EXPECT_EQ(ltm.LinksOf(5), (std::vector<LocationId>{4, 8}));
  const auto location = ltm.Retrieve(5);
  ASSERT_TRUE(location.has_value());
  EXPECT_EQ(location->signature.words, (std::vector<WordId>{30, 11}));
  EXPECT_EQ(location->neighbours, (std::set<LocationId>{4, 8}));
  ltm.SetWriterHeld(false);
  ltm.Flush();
  LtmDatabase database(dir.File("map.db"), LtmDatabase::Mode::kOpen);
  EXPECT_EQ(database.ReadLocation(5)->signature.words, (std::vector<WordId>{30, 11}));
  EXPECT_EQ(database.ReadLocation(5)->Links(), (std::vector<LocationId>{4, 8}));
}

INSTANTIATE_TEST_SUITE_P(WriterBehindOrNot, LongTermMemoryChainTest, ::testing::Bool());

TEST(LongTermMemoryTest, AddedLinksAreReadBeforeAndAfterCommit) {
  testing::TempDir dir;
  LongTermMemory ltm(dir.File("map.db"));
  ltm.SetWriterHeld(true);
  ltm.Store(MakeLtmLocation(5, {1}));
  ltm.AddLink(5, 40, /*loop_closure=*/true);
  EXPECT_EQ(ltm.Peek(5)->loop_closures, (std::set<LocationId>{40}));
  ltm.SetWriterHeld(false);
  ltm.Flush();
  EXPECT_EQ(ltm.Peek(5)->loop_closures, (std::set<LocationId>{40}));
  EXPECT_EQ(ltm.LinksOf(5), (std::vector<LocationId>{4, 6, 40}));
}

// LTM's link graph is held in memory (LinksOf); it must say what a read of the file with the
// queued writes says, through stores, added links, redirections and retrievals, and be loaded
// from the file when the map is opened again.
TEST(LongTermMemoryTest, LinkGraphInMemoryAgreesWithTheFile) {
  testing::TempDir dir;
  const std::string path = dir.File("map.db");
  const auto agrees = [](LongTermMemory& ltm, LocationId id) {
    return ltm.LinksOf(id) == ltm.Peek(id)->Links();
  };
  {
    LongTermMemory ltm(path);
    ltm.SetWriterHeld(true);
    for (LocationId id : {5, 6, 7}) ltm.Store(MakeLtmLocation(id, {1}));
    ltm.RedirectLocation(8, 9, {7, 9});  // 8 (in memory) merged into 9: LTM's 7 links to 9 now
    EXPECT_EQ(ltm.LinksOf(7), (std::vector<LocationId>{6, 9}));
    ltm.AddLink(5, 9, /*loop_closure=*/true);
    EXPECT_EQ(ltm.LinksOf(5), (std::vector<LocationId>{4, 6, 9}));
    ltm.AddLink(5, 6, /*loop_closure=*/true);  // a neighbour already: one link
    ltm.RedirectLocation(6, 5, {});            // 6 (in LTM) merged into 5: no link of 5 to itself
    EXPECT_EQ(ltm.LinksOf(5), (std::vector<LocationId>{4, 9}));
    EXPECT_EQ(ltm.LinksOf(7), (std::vector<LocationId>{5, 9}));
    EXPECT_TRUE(ltm.LinksOf(6).empty());
    for (LocationId id : {5, 7}) EXPECT_TRUE(agrees(ltm, id)) << id;
    ASSERT_TRUE(ltm.Retrieve(7).has_value());
    EXPECT_TRUE(ltm.LinksOf(7).empty());  // back in WM
    ltm.SetWriterHeld(false);
    ltm.Flush();
    EXPECT_TRUE(agrees(ltm, 5));
  }
  LongTermMemory reopened(path, LtmDatabase::Mode::kOpen);
  EXPECT_EQ(reopened.LinksOf(5), (std::vector<LocationId>{4, 9}));
  EXPECT_EQ(reopened.LinksOf(7), (std::vector<LocationId>{5, 9}));  // its rows stayed in the file
  reopened.Exclude(7);                                              // resuming: 7 is in memory
  EXPECT_TRUE(reopened.LinksOf(7).empty());
}

// Back-pressure: a held writer is made to commit once the queue is full, so RAM stays bounded.
TEST(LongTermMemoryTest, QueueIsBoundedEvenWhenTheWriterIsHeld) {
  testing::TempDir dir;
  LtmOptions options;
  options.max_pending_bytes = 64 * 1024;
  LongTermMemory ltm(dir.File("map.db"), LtmDatabase::Mode::kCreate, options);
  ltm.SetWriterHeld(true);
  size_t most = 0;
  for (int id = 1; id <= 300; ++id) {
    ltm.Store(MakeLtmLocation(id, std::vector<WordId>(50, id)));
    most = std::max(most, ltm.pending_bytes());
  }
  EXPECT_LE(most, options.max_pending_bytes);
  EXPECT_GT(most, options.max_pending_bytes / 2);  // it did fill up before committing
  EXPECT_EQ(ltm.Peek(300)->signature.words.size(), 50u);
  EXPECT_GT(ltm.TakeWriterWaitMs(), 0.0);  // the stores waited for commits
  EXPECT_EQ(ltm.TakeWriterWaitMs(), 0.0);  // taken
}

// With room in the queue nothing waits, however far behind the writer is.
TEST(LongTermMemoryTest, NoWaitForTheWriterWhileTheQueueHasRoom) {
  testing::TempDir dir;
  LongTermMemory ltm(dir.File("map.db"), LtmDatabase::Mode::kCreate, LtmOptions());
  ltm.SetWriterHeld(true);
  for (int id = 1; id <= 300; ++id) ltm.Store(MakeLtmLocation(id, std::vector<WordId>(50, id)));
  EXPECT_EQ(ltm.TakeWriterWaitMs(), 0.0);
  ltm.SetWriterHeld(false);
}

// Only reads that reach the map file count as file reads: a location or word still queued is read
// from memory.
TEST(LongTermMemoryTest, FileReadTimeCountsOnlyReadsOfTheFile) {
  testing::TempDir dir;
  LongTermMemory ltm(dir.File("map.db"), LtmDatabase::Mode::kCreate, LtmOptions());
  ltm.SetWriterHeld(true);
  ltm.Store(MakeLtmLocation(1, {7, 8}));
  ltm.StoreWord(7, cv::Mat(1, 4, CV_32F, cv::Scalar(1)));
  ASSERT_TRUE(ltm.Peek(1));
  ASSERT_TRUE(ltm.LoadWord(7));
  EXPECT_EQ(ltm.TakeFileReadMs(), 0.0);  // both from the overlay
  ltm.SetWriterHeld(false);
  ltm.Flush();
  ASSERT_TRUE(ltm.Peek(1));
  EXPECT_GT(ltm.TakeFileReadMs(), 0.0);
  EXPECT_EQ(ltm.TakeFileReadMs(), 0.0);  // taken
  ASSERT_TRUE(ltm.LoadWord(7));
  EXPECT_EQ(ltm.TakeFileReadMs(), 0.0);  // a word stored lately: kept after its commit
  ASSERT_FALSE(ltm.LoadWord(9));
  EXPECT_GT(ltm.TakeFileReadMs(), 0.0);
}

// Words stored lately are answered from memory after their commit, as the file would answer: a
// renamed word is gone, and beyond the bound the oldest are read from the file again.
TEST(LongTermMemoryTest, WordsStoredLatelyAreKeptAfterTheirCommit) {
  testing::TempDir dir;
  LtmOptions options;
  options.recent_word_bytes = 2 * 4 * sizeof(float);  // two words of 4 floats
  LongTermMemory ltm(dir.File("map.db"), LtmDatabase::Mode::kCreate, options);
  const auto store = [&ltm](WordId word) {
    ltm.StoreWord(word, cv::Mat(1, 4, CV_32F, cv::Scalar(word)));
  };
  ltm.Store(MakeLtmLocation(1, {7, 9}));
  store(7);
  store(9);
  ltm.Flush();
  ltm.TakeFileReadMs();
  EXPECT_EQ(*ltm.LoadWord(7), testing::FloatBytes({7, 7, 7, 7}));
  EXPECT_EQ(*ltm.LoadWord(9), testing::FloatBytes({9, 9, 9, 9}));
  EXPECT_EQ(ltm.TakeFileReadMs(), 0.0);
  ltm.ReplaceWord(9, 20);
  ltm.Flush();
  EXPECT_FALSE(ltm.LoadWord(9));  // renamed: not kept, and gone from the file too
  store(10);
  store(11);
  ltm.Flush();  // 7, the oldest, goes
  ltm.TakeFileReadMs();
  EXPECT_EQ(*ltm.LoadWord(10), testing::FloatBytes({10, 10, 10, 10}));
  EXPECT_EQ(*ltm.LoadWord(11), testing::FloatBytes({11, 11, 11, 11}));
  EXPECT_EQ(ltm.TakeFileReadMs(), 0.0);
  EXPECT_EQ(*ltm.LoadWord(7), testing::FloatBytes({7, 7, 7, 7}));
  EXPECT_GT(ltm.TakeFileReadMs(), 0.0);
}

// A full disk (emulated with SQLite's page limit) stops the run at the next call, not at Close.
TEST(LongTermMemoryTest, WriterFailureIsReportedAtTheNextCall) {
  testing::TempDir dir;
  LtmOptions options;
  options.max_page_count = 12;
  options.max_pending_bytes = 16 * 1024;  // the queue fills soon: the failure must come back
  LongTermMemory ltm(dir.File("map.db"), LtmDatabase::Mode::kCreate, options);
  bool failed = false;
  for (int id = 1; id <= 2000 && !failed; ++id) {
    try {
      ltm.Store(MakeLtmLocation(id, std::vector<WordId>(100, id)));
    } catch (const DatabaseError& error) {
      failed = true;
      EXPECT_NE(std::string(error.what()).find("writing the map failed"), std::string::npos);
      EXPECT_NE(std::string(error.what()).find("full"), std::string::npos) << error.what();
    }
  }
  EXPECT_TRUE(failed);
  EXPECT_THROW(ltm.CheckWriter(), DatabaseError);
  EXPECT_THROW(ltm.Flush(), DatabaseError);
  EXPECT_LE(ltm.pending_bytes(), options.max_pending_bytes);
}

// From the first checkpoint on, a transaction ends at a checkpoint: writes after the last one
// are not committed (a map file always holds one consistent moment of the run).
CheckpointData StateCheckpoint(int value) {
  CheckpointData checkpoint;
  checkpoint.state.emplace_back("test",
                                std::vector<unsigned char>{static_cast<unsigned char>(value)});
  return checkpoint;
}

TEST(LongTermMemoryTest, CommitsOnlyWholeCheckpoints) {
  testing::TempDir dir;
  const std::string path = dir.File("map.db");
  {
    LongTermMemory ltm(path);
    ltm.Store(MakeLtmLocation(1, {1}));
    ltm.Checkpoint(StateCheckpoint(1));
    ltm.Store(MakeLtmLocation(2, {2}));
    ltm.Flush();                           // up to the checkpoint
    EXPECT_TRUE(ltm.Peek(2).has_value());  // read through the queue
  }                                        // location 2 is dropped: no checkpoint after it
  LtmDatabase database(path, LtmDatabase::Mode::kOpen);
  EXPECT_TRUE(database.ReadLocation(1).has_value());
  EXPECT_FALSE(database.ReadLocation(2).has_value());
  EXPECT_EQ(*database.ReadState("test"), std::vector<unsigned char>{1});
}

TEST(LongTermMemoryTest, KilledWriterLeavesTheFileAtACheckpoint) {
  testing::TempDir dir;
  const std::string path = dir.File("map.db");
  ASSERT_TRUE(KilledAfter([&] {
    LongTermMemory ltm(path);
    for (int id = 1; id <= 200; ++id) {
      ltm.Store(MakeLtmLocation(id, std::vector<WordId>(40, id)));
      ltm.Checkpoint(StateCheckpoint(id));
      if (id % 2) ltm.Store(MakeLtmLocation(1000 + id, {id}));  // after the checkpoint
    }
  }));
  LtmDatabase database(path, LtmDatabase::Mode::kOpen);
  const auto state = database.ReadState("test");
  ASSERT_TRUE(state.has_value());
  const int last = (*state)[0];
  EXPECT_GE(last, 199);  // at most one checkpoint in flight: the one before the last committed
  for (int id = 1; id <= 200; ++id) {
    EXPECT_EQ(database.ReadLocation(id).has_value(), id <= last) << id;
    EXPECT_EQ(database.ReadLocation(1000 + id).has_value(), id < last && id % 2) << id;
  }
}

// Closing: the caller writes, in one transaction with what was still queued, committed at the
// next checkpoint; nothing is held in a queue meanwhile, and reads see the writes.
TEST(LongTermMemoryTest, DirectWritesCommitAtTheNextCheckpoint) {
  testing::TempDir dir;
  const std::string path = dir.File("map.db");
  {
    LongTermMemory ltm(path);
    ltm.Store(MakeLtmLocation(1, {1}));
    ltm.Checkpoint(StateCheckpoint(1));
    ltm.Store(MakeLtmLocation(2, {2}));  // queued after the checkpoint
    ltm.WriteDirectly();
    ltm.Store(MakeLtmLocation(3, {3}));
    ltm.StoreWord(3, (cv::Mat_<float>(1, 2) << 0.5f, 0.25f));
    ltm.ReplaceWord(2, 3);
    EXPECT_EQ(ltm.pending_bytes(), 0u);
    EXPECT_FALSE(ltm.CheckpointInFlight());
    EXPECT_EQ(ltm.Peek(2)->signature.words, std::vector<WordId>{3});
    EXPECT_EQ(ltm.LinksOf(3), (std::vector<LocationId>{2, 4}));
    EXPECT_EQ(*ltm.LoadWord(3), testing::FloatBytes({0.5f, 0.25f}));
    ltm.Checkpoint(StateCheckpoint(2));
    ltm.Store(MakeLtmLocation(4, {4}));  // after the last checkpoint: dropped
    ltm.Flush();
  }
  LtmDatabase database(path, LtmDatabase::Mode::kOpen);
  for (LocationId id : {1, 2, 3}) EXPECT_TRUE(database.ReadLocation(id).has_value()) << id;
  EXPECT_FALSE(database.ReadLocation(4).has_value());
  EXPECT_EQ(database.ReadLocation(2)->signature.words, std::vector<WordId>{3});
  EXPECT_EQ(*database.ReadState("test"), std::vector<unsigned char>{2});
}

// Without checkpoints every write is kept, queued or direct.
TEST(LongTermMemoryTest, DirectWritesWithoutCheckpointsAreKept) {
  testing::TempDir dir;
  const std::string path = dir.File("map.db");
  {
    LongTermMemory ltm(path);
    ltm.Store(MakeLtmLocation(1, {1}));
    ltm.WriteDirectly();
    ltm.Store(MakeLtmLocation(2, {2}));
  }
  LtmDatabase database(path, LtmDatabase::Mode::kOpen);
  EXPECT_TRUE(database.ReadLocation(1).has_value());
  EXPECT_TRUE(database.ReadLocation(2).has_value());
}

// A full disk during a close: the error names the map, later calls fail too, and the file keeps
// its last checkpoint.
TEST(LongTermMemoryTest, DirectWriteFailureKeepsTheLastCheckpoint) {
  testing::TempDir dir;
  const std::string path = dir.File("map.db");
  LtmOptions options;
  options.max_page_count = 12;
  {
    LongTermMemory ltm(path, LtmDatabase::Mode::kCreate, options);
    ltm.Store(MakeLtmLocation(1, {1}));
    ltm.Checkpoint(StateCheckpoint(1));
    ltm.WriteDirectly();
    bool failed = false;
    for (int id = 2; id <= 2000 && !failed; ++id) {
      try {
        ltm.Store(MakeLtmLocation(id, std::vector<WordId>(100, id)));
      } catch (const DatabaseError& error) {
        failed = true;
        EXPECT_NE(std::string(error.what()).find(path), std::string::npos);
        EXPECT_NE(std::string(error.what()).find("writing the map failed"), std::string::npos);
      }
    }
    EXPECT_TRUE(failed);
    EXPECT_THROW(ltm.CheckWriter(), DatabaseError);
    EXPECT_THROW(ltm.Checkpoint(StateCheckpoint(2)), DatabaseError);
  }
  LtmDatabase database(path, LtmDatabase::Mode::kOpen);
  EXPECT_TRUE(database.ReadLocation(1).has_value());
  EXPECT_FALSE(database.ReadLocation(2).has_value());
  EXPECT_EQ(*database.ReadState("test"), std::vector<unsigned char>{1});
}

}  // namespace
}  // namespace memloop
