#include "vocabulary/index_history.h"

#include <gtest/gtest.h>

#include "memloop/errors.h"

namespace memloop {
namespace {

// Five points of 2 float columns: word 7 at points 0 and 3 (it left and came back), words 8, 9
// and 10 once; two batches, at points 0 and 3.
IndexHistory FivePoints() {
  IndexHistory history;
  history.point_count = 5;
  history.point_words = {7, 8, 9, 7, 10};
  history.batch_starts = {0, 3};
  history.descriptors = cv::Mat::zeros(5, 2, CV_32F);
  return history;
}

TEST(IndexHistoryTest, AWholeConsistentHistoryPasses) {
  EXPECT_NO_THROW(CheckIndexHistory(FivePoints(), 2, CV_32F));
  EXPECT_NO_THROW(CheckIndexHistory(IndexHistory(), 2, CV_32F));  // nothing added yet
}

TEST(IndexHistoryTest, EachInconsistencyIsRefused) {
  const auto refused = [](IndexHistory history, int dim = 2, int cv_type = CV_32F) {
    EXPECT_THROW(CheckIndexHistory(history, dim, cv_type), Error);
  };
  IndexHistory history = FivePoints();
  history.first_point = 3;  // not whole
  refused(history);
  history = FivePoints();
  history.point_words.pop_back();  // a point without its word
  refused(history);
  history = FivePoints();
  history.descriptors = cv::Mat::zeros(4, 2, CV_32F);  // a point without its descriptor
  refused(history);
  refused(FivePoints(), 3);         // another descriptor size
  refused(FivePoints(), 2, CV_8U);  // another descriptor type
  history = FivePoints();
  history.batch_starts = {1, 3};  // the first batch must be the build, at point 0
  refused(history);
  history.batch_starts = {0, 3, 3};  // batches in order, none empty
  refused(history);
  history.batch_starts = {0, 5};  // a batch past the last point
  refused(history);
  history.batch_starts = {};  // points without a batch
  refused(history);
  history = FivePoints();
  history.pending = true;
  history.pending_point = 6;  // a snapshot past the last point
  refused(history);
  history.pending_point = 3;
  history.pending_words = {9, 8};  // its words are sorted
  refused(history);
  history.pending_words = {8, 9};
  EXPECT_NO_THROW(CheckIndexHistory(history, 2, CV_32F));
}

TEST(IndexHistoryTest, LatestPointsAreEachWordsLastBeforeAndAfterTheSnapshot) {
  IndexHistory history = FivePoints();
  LatestPoints latest = LatestPointsOf(history);
  EXPECT_EQ(latest.overall, (std::unordered_map<WordId, size_t>{{7, 3}, {8, 1}, {9, 2}, {10, 4}}));
  EXPECT_TRUE(latest.before_pending.empty());  // no pending build

  history.pending = true;
  history.pending_point = 3;  // the snapshot saw points 0-2: word 7 at point 0
  latest = LatestPointsOf(history);
  EXPECT_EQ(latest.before_pending, (std::unordered_map<WordId, size_t>{{7, 0}, {8, 1}, {9, 2}}));
  EXPECT_EQ(latest.overall.at(7), 3u);
}

}  // namespace
}  // namespace memloop
