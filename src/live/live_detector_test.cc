#include "memloop/live_detector.h"

#include <gtest/gtest.h>

#include <future>
#include <vector>

#include "memloop/errors.h"
#include "memloop/synthetic_route.h"
#include "short_route.h"
#include "temp_dir.h"

namespace memloop {
namespace {

Options Deterministic() {
  Options options;
  options.memory.time_limit_ms = 0;
  options.memory.max_wm_locations = 30;
  return options;
}

class LiveDetectorTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { route_ = new SyntheticRoute(testing::ShortRoute()); }
  static void TearDownTestSuite() { delete route_; }
  static inline SyntheticRoute* route_ = nullptr;
  testing::TempDir dir_;
};

// kQueue: every image, in order, with the results a Detector called image by image gives.
TEST_F(LiveDetectorTest, QueueProcessesEveryImageAsTheDetectorDoes) {
  const int count = route_->size();
  std::vector<Result> expected;
  {
    Detector detector(Deterministic(), dir_.File("direct.db"));
    for (int i = 0; i < count; ++i) expected.push_back(detector.Process(route_->Render(i), i));
  }
  std::vector<LiveResult> got;
  {
    LiveDetector live(Deterministic(), dir_.File("live.db"), MapMode::kNew, StreamPolicy::kQueue,
                      [&](const LiveResult& result) { got.push_back(result); });
    for (int i = 0; i < count; ++i) {
      ImageInfo info;
      info.timestamp = 100 + 0.1 * i;
      live.Push(route_->Render(i), info);
    }
    live.Save();  // waits for the images handed over before it
    EXPECT_EQ(ReadMapProgress(dir_.File("live.db")).last_image, count - 1);
    const LiveStatus status = live.Status();
    EXPECT_EQ(status.received, count);
    EXPECT_EQ(status.processed, count);
    EXPECT_EQ(status.dropped, 0);
  }
  ASSERT_EQ(got.size(), expected.size());
  int loop_closures = 0;
  for (int i = 0; i < count; ++i) {
    EXPECT_EQ(got[i].image.index, i);
    EXPECT_EQ(got[i].result.location_id, expected[i].location_id) << "image " << i;
    EXPECT_EQ(got[i].result.loop_closure_id, expected[i].loop_closure_id) << "image " << i;
    if (got[i].result.HasLoopClosure()) {
      ++loop_closures;
      const ImageIndex match = got[i].result.loop_closure_images.front();
      EXPECT_DOUBLE_EQ(got[i].match_timestamp, 100 + 0.1 * match);
      EXPECT_EQ(got[i].match_session, 0);
    }
  }
  EXPECT_GT(loop_closures, 0);
}

// kLatest: images that come while one is processed replace each other; the newest is processed
// next. The first image's callback holds the processing thread until five more were handed over.
TEST_F(LiveDetectorTest, LatestDropsTheImagesANewerOneReplacedAndCountsThem) {
  std::promise<void> entered, release;
  std::shared_future<void> released = release.get_future().share();
  std::vector<ImageIndex> processed;
  LiveDetector live(Deterministic(), dir_.File("live.db"), MapMode::kNew, StreamPolicy::kLatest,
                    [&](const LiveResult& result) {
                      processed.push_back(result.image.index);
                      if (processed.size() == 1) {
                        entered.set_value();
                        released.wait();
                      }
                    });
  live.Push(route_->Render(0), {});
  entered.get_future().wait();
  for (int i = 1; i <= 5; ++i) live.Push(route_->Render(i), {});
  EXPECT_EQ(live.Status().waiting, 1);
  EXPECT_EQ(live.Status().dropped, 4);
  release.set_value();
  live.Save();
  live.Stop();
  EXPECT_EQ(processed, (std::vector<ImageIndex>{0, 5}));
  const LiveStatus status = live.Status();
  EXPECT_EQ(status.received, 6);
  EXPECT_EQ(status.processed, 2);
  EXPECT_EQ(status.dropped, 4);
  // The map resumes after the last image processed; the next image is numbered after it.
  LiveDetector resumed(ReadMapOptions(dir_.File("live.db")), dir_.File("live.db"), MapMode::kResume,
                       StreamPolicy::kQueue, {});
  EXPECT_EQ(resumed.next_index(), 6);
}

TEST_F(LiveDetectorTest, RefusedAndPausedImagesAreCountedAndTheStreamGoesOn) {
  std::vector<std::string> errors;
  long long results = 0;
  LiveDetector live(
      Deterministic(), dir_.File("live.db"), MapMode::kNew, StreamPolicy::kQueue,
      [&](const LiveResult&) { ++results; },
      [&](const std::string& message, bool fatal) {
        EXPECT_FALSE(fatal);
        errors.push_back(message);
      });
  live.Push(route_->Render(0), {});
  live.Push(cv::Mat(), {});  // empty: refused by the detector
  live.SetPaused(true);
  live.Push(route_->Render(1), {});
  live.SetPaused(false);
  live.Push(route_->Render(2), {});
  live.Save();
  const LiveStatus status = live.Status();
  EXPECT_EQ(status.received, 4);
  EXPECT_EQ(status.processed, 2);
  EXPECT_EQ(status.refused, 1);
  EXPECT_EQ(status.dropped, 1);
  EXPECT_EQ(results, 2);
  ASSERT_EQ(errors.size(), 1u);
  EXPECT_TRUE(status.failure.empty());
}

// A detector failure stops the stream, says why, and Save() then refuses.
TEST_F(LiveDetectorTest, AFailingCallbackStopsTheStreamAndSaveSaysWhy) {
  std::string fatal_message;
  LiveDetector live(
      Deterministic(), dir_.File("live.db"), MapMode::kNew, StreamPolicy::kQueue,
      [](const LiveResult&) { throw Error("cannot publish"); },
      [&](const std::string& message, bool fatal) {
        if (fatal) fatal_message = message;
      });
  live.Push(route_->Render(0), {});
  EXPECT_THROW(live.Save(), Error);
  live.Stop();
  EXPECT_EQ(fatal_message, "cannot publish");
  EXPECT_EQ(live.Status().failure, "cannot publish");
}

}  // namespace
}  // namespace memloop
