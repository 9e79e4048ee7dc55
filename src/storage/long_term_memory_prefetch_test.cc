// LongTermMemory::Retrieve from rows read ahead (LtmReadAhead): the same answer as a read of the
// file with the queued writes, without reading the file when the rows can be brought up to date.
#include <gtest/gtest.h>

#include <limits>

#include "small_memory.h"
#include "storage/long_term_memory.h"
#include "storage/ltm_read_ahead.h"
#include "temp_dir.h"

namespace memloop {
namespace {

constexpr double kForever = std::numeric_limits<double>::infinity();

using testing::MakeLtmLocation;

// Location 5 (words 10 and 11, which left the dictionary; links 4 and 6) in the file, and its rows
// as the read-ahead thread read them then.
class PrefetchTest : public ::testing::Test {
 protected:
  explicit PrefetchTest(const LtmOptions& options = LtmOptions())
      : ltm_(dir_.File("map.db"), LtmDatabase::Mode::kCreate, options) {
    ltm_.Store(MakeLtmLocation(5, {10, 11}));
    ltm_.StoreWord(10, (cv::Mat_<float>(1, 2) << 1.f, 2.f));
    ltm_.StoreWord(11, (cv::Mat_<float>(1, 2) << 3.f, 4.f));
    ltm_.Flush();
    LtmReadAhead read_ahead(ltm_);
    rows_ = *read_ahead.WaitRead(5, kForever);
    ltm_.TakeFileReadMs();
  }

  testing::TempDir dir_;
  LongTermMemory ltm_;
  PrefetchedRows rows_;
};

class PrefetchWriterBehindTest : public PrefetchTest, public ::testing::WithParamInterface<bool> {};

// Writes since the read, committed (replayed from CommittedWrites) or still queued (the overlay).
TEST_P(PrefetchWriterBehindTest, RowsReadBeforeWritesComeBackUpToDateWithoutAFileRead) {
  ltm_.SetWriterHeld(GetParam());
  ltm_.ReplaceWord(10, 20);
  ltm_.StoreWord(20, (cv::Mat_<float>(1, 2) << 5.f, 6.f));
  ltm_.ReplaceWord(20, 30);  // 10 -> 20 -> 30
  ltm_.RedirectLocation(6, 7, {5, 7});
  ltm_.AddLink(5, 40, /*loop_closure=*/true);
  if (!GetParam()) ltm_.Flush();
  const std::optional<Location> expected = ltm_.Peek(5);
  ltm_.TakeFileReadMs();
  const std::optional<Location> location = ltm_.Retrieve(5, rows_);
  EXPECT_EQ(ltm_.TakeFileReadMs(), 0.0);
  ASSERT_TRUE(location && expected);
  EXPECT_EQ(location->signature.words, (std::vector<WordId>{30, 11}));
  EXPECT_EQ(location->signature.words, expected->signature.words);
  EXPECT_EQ(location->neighbours, (std::set<LocationId>{4, 7}));
  EXPECT_EQ(location->loop_closures, (std::set<LocationId>{40}));
  EXPECT_EQ(location->Links(), expected->Links());
  EXPECT_EQ(location->images, expected->images);
  EXPECT_FALSE(ltm_.Contains(5));
  // Its word 11, from the rows read: no file read either.
  EXPECT_EQ(*ltm_.LoadWord(11, &rows_), testing::FloatBytes({3.f, 4.f}));
  EXPECT_EQ(ltm_.TakeFileReadMs(), 0.0);
}

INSTANTIATE_TEST_SUITE_P(WriterBehindOrNot, PrefetchWriterBehindTest, ::testing::Bool());

// Retrieved and stored again since the read: the rows read are an older copy.
TEST_F(PrefetchTest, ALocationStoredAgainSinceTheReadIsReadAgain) {
  ASSERT_TRUE(ltm_.Retrieve(5));
  ltm_.Store(MakeLtmLocation(5, {12, 13}));
  EXPECT_EQ(ltm_.Retrieve(5, rows_)->signature.words, (std::vector<WordId>{12, 13}));  // queued
  ltm_.Store(MakeLtmLocation(5, {14}));
  ltm_.Flush();
  EXPECT_EQ(ltm_.Retrieve(5, rows_)->signature.words, (std::vector<WordId>{14}));  // committed
  EXPECT_GT(ltm_.TakeFileReadMs(), 0.0);
}

class PrefetchFewWritesKeptTest : public PrefetchTest {
 protected:
  PrefetchFewWritesKeptTest() : PrefetchTest(Options()) {}
  static LtmOptions Options() {
    LtmOptions options;
    options.max_replayed_writes = 2;
    return options;
  }
};

TEST_F(PrefetchFewWritesKeptTest, RowsOlderThanTheWritesKeptAreReadAgain) {
  for (LocationId to : {40, 41}) ltm_.AddLink(5, to, /*loop_closure=*/false);
  ltm_.Flush();
  EXPECT_TRUE(ltm_.Current(rows_));
  ltm_.AddLink(5, 42, /*loop_closure=*/false);
  ltm_.Flush();                       // the first of the three is no longer kept
  EXPECT_FALSE(ltm_.Current(rows_));  // retrieval has the read-ahead thread read them again
  const std::optional<Location> location = ltm_.Retrieve(5, rows_);
  EXPECT_GT(ltm_.TakeFileReadMs(), 0.0);
  ASSERT_TRUE(location);
  EXPECT_EQ(location->neighbours, (std::set<LocationId>{4, 6, 40, 41, 42}));
}

// Words of 2 floats, two kept after their commit: the fixture's 10 and 11 at first.
class PrefetchFewWordsKeptTest : public PrefetchTest {
 protected:
  PrefetchFewWordsKeptTest() : PrefetchTest(Options()) {}
  static LtmOptions Options() {
    LtmOptions options;
    options.recent_word_bytes = 2 * 2 * sizeof(float);
    return options;
  }
};

// Rows are current while every word stored since their read is kept: a word that left the
// dictionary after the read is then answered without reading the file.
TEST_F(PrefetchFewWordsKeptTest, RowsAreCurrentWhileTheWordsStoredSinceAreKept) {
  for (WordId word : {30, 31}) {
    ltm_.StoreWord(word, (cv::Mat_<float>(1, 2) << 1.f * word, 0.f));
    ltm_.Flush();  // 10, then 11 go: stored before the read, which has them
    EXPECT_TRUE(ltm_.Current(rows_));
  }
  ltm_.StoreWord(32, (cv::Mat_<float>(1, 2) << 32.f, 0.f));
  ltm_.Flush();  // 30 goes: stored after the read
  EXPECT_FALSE(ltm_.Current(rows_));
}

// Localization: nothing is written, every change stays in the overlay, which the rows get too.
TEST(PrefetchReadOnlyTest, RowsGetTheChangesKeptInMemory) {
  testing::TempDir dir;
  const std::string path = dir.File("map.db");
  {
    LongTermMemory ltm(path);
    ltm.Store(MakeLtmLocation(5, {10, 11}));
  }
  LongTermMemory ltm(path, LtmDatabase::Mode::kRead);
  LtmReadAhead read_ahead(ltm);
  const PrefetchedRows rows = *read_ahead.WaitRead(5, kForever);
  ltm.ReplaceWord(11, 15);
  ltm.TakeFileReadMs();
  EXPECT_EQ(ltm.Retrieve(5, rows)->signature.words, (std::vector<WordId>{10, 15}));
  EXPECT_EQ(ltm.TakeFileReadMs(), 0.0);
}

}  // namespace
}  // namespace memloop
