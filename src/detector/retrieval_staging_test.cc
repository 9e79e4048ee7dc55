#include "detector/retrieval_staging.h"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <future>
#include <limits>
#include <mutex>
#include <thread>

#include "detector/retrieval.h"
#include "small_map.h"

namespace memloop {
namespace {

constexpr double kForever = std::numeric_limits<double>::infinity();

// A chain L1 .. L5 (words at id x 100, 0) whose L2, L3 ({30, 70}) and L4 ({40, 70}) are in LTM,
// their words gone from the dictionary, which holds words 1 (100) and 5 (500): words 30 and 70
// match neither (3000: 2500 vs 2900, 7000: 6500 vs 6900, over the 0.8 ratio). LTM is flushed so
// that a read-ahead thread sees them.
class RetrievalStagingTest : public ::testing::Test {
 protected:
  RetrievalStagingTest() {
    ids_ = map_.ChainWithMiddleInLtm({{1}, {2}, {30, 70}, {40, 70}, {5}});
    ltm_->Flush();
  }

  // A location staged as retrieval over iterations does it: its rows read ahead, its words
  // searched.
  RetrievalStaging::Staged& Stage(LocationId id) {
    std::optional<PrefetchedRows> rows = read_ahead_.WaitRead(id, kForever);
    EXPECT_TRUE(rows.has_value());
    RetrievalStaging::Staged& staged = staging_.Start(id, std::move(*rows));
    EXPECT_TRUE(SearchStagedWords(staged, memory_.dictionary(), *ltm_, StepDeadline(), 0));
    return staged;
  }

  // Staged retrieval of `target` (at most `max_retrieved`), with room for retrievals but none for
  // a chunk of search (a chunk expected to take 10 ms, 5 before the deadline).
  RetrievalOutcome RetrieveWithoutRoomToSearch(LocationId target, bool ahead_unsearched,
                                               bool newer_first = true, int recent_twins = -1,
                                               int max_retrieved = 2) {
    staging_.StartIteration(memory_.dictionary().JoinMark());
    StepCost chunk;
    chunk.Record(5);
    RetrievalTime time;
    time.location = StepDeadline([] { return 0.0; }, 1e9, &location_cost_);
    time.search_chunk = StepDeadline([] { return 35.0; }, 40, &chunk);
    time.read_ahead = &read_ahead_;
    time.staging = &staging_;
    time.ahead_unsearched = ahead_unsearched;
    time.newer_first = newer_first;
    time.recent_twins = recent_twins;
    return Retrieve(target, max_retrieved, 4, memory_, *ltm_, time);
  }

  // Three images' retrieval steps: word 300, a twin of word 30 (3000, 1), joins before the second;
  // 200, a twin of word 70 (7000, 1), and 201 (7100, 0) before the third, which asks for L3 with
  // no room to search, looking for twins `recent_twins` images back.
  RetrievalOutcome RetrieveAfterTwinsJoined(int recent_twins) {
    staging_.StartIteration(memory_.dictionary().JoinMark());
    memory_.dictionary().Add({300}, (cv::Mat_<float>(1, 2) << 3000, 1));
    staging_.StartIteration(memory_.dictionary().JoinMark());
    memory_.dictionary().Add({200, 201}, (cv::Mat_<float>(2, 2) << 7000, 1, 7100, 0));
    return RetrieveWithoutRoomToSearch(ids_[2], /*ahead_unsearched=*/false, /*newer_first=*/true,
                                       recent_twins, /*max_retrieved=*/1);
  }

  // Words added as the images' new words: no location of this map holds them.
  void RemoveWordsOfNoLocation(const std::vector<WordId>& words) {
    for (WordId word : words) memory_.dictionary().Remove(word);
  }

  // Retrieval with time to spare, staged.
  RetrievalOutcome RetrieveStaged(LocationId target, int max_retrieved = 1,
                                  bool ahead_unsearched = false) {
    RetrievalTime time;
    time.location = StepDeadline([] { return 0.0; }, 1e9, &location_cost_);
    time.search_chunk = StepDeadline([] { return 0.0; }, 1e9, &chunk_cost_);
    time.read_ahead = &read_ahead_;
    time.staging = &staging_;
    time.ahead_unsearched = ahead_unsearched;
    return Retrieve(target, max_retrieved, 4, memory_, *ltm_, time);
  }

  testing::SmallMap map_;
  Memory& memory_ = map_.memory;
  LongTermMemory* ltm_ = &map_.ltm;
  std::vector<LocationId> ids_;
  LtmReadAhead read_ahead_{*ltm_};
  RetrievalStaging staging_;
  StepCost location_cost_;
  StepCost chunk_cost_;
};

// The staged search found no twin for words 30 and 70. A twin of word 70 then joins (the next
// image's word beside 70's point): at the retrieval word 70 is replaced by it, as a search at that
// moment would, instead of coming back beside its twin (then neither would match the next images).
TEST_F(RetrievalStagingTest, ATwinThatJoinedAfterTheSearchIsFound) {
  RetrievalStaging::Staged& staged = Stage(ids_[2]);
  ASSERT_EQ(staged.matches.size(), 2u);
  EXPECT_EQ(staged.matches.at(70).match, kNoWord);
  EXPECT_FLOAT_EQ(staged.matches.at(70).nearest, 6500);  // word 5 at 500
  EXPECT_FLOAT_EQ(staged.matches.at(70).second, 6900);   // word 1 at 100
  memory_.dictionary().Add({200}, (cv::Mat_<float>(1, 2) << 7000, 1));
  const RetrievalOutcome outcome = RetrieveStaged(ids_[2]);
  ASSERT_EQ(outcome.retrieved, (std::vector<LocationId>{ids_[2]}));
  EXPECT_EQ(outcome.words_replaced, 1);
  EXPECT_EQ(outcome.words_added, 1);
  EXPECT_EQ(memory_.at(ids_[2]).signature.words, (std::vector<WordId>{30, 200}));
  EXPECT_EQ(ltm_->Peek(ids_[3])->signature.words, (std::vector<WordId>{40, 200}));  // LTM too
  EXPECT_EQ(staging_.Find(ids_[2]), nullptr);                                       // done with
  EXPECT_TRUE(map_.CheckConsistencyEmpty());
}

// An answer names a word that has left the dictionary since: the word is searched again.
TEST_F(RetrievalStagingTest, AnAnswerWhoseWordLeftIsSearchedAgain) {
  RetrievalStaging::Staged& staged = Stage(ids_[2]);
  memory_.dictionary().Add({200}, (cv::Mat_<float>(1, 2) << 7000, 0));
  staged.matches[70] = {200, 0, 100, memory_.dictionary().JoinMark()};
  memory_.dictionary().Remove(200);
  memory_.dictionary().Add({201}, (cv::Mat_<float>(1, 2) << 7001, 0));
  ASSERT_EQ(RetrieveStaged(ids_[2]).retrieved.size(), 1u);
  EXPECT_EQ(memory_.at(ids_[2]).signature.words, (std::vector<WordId>{30, 201}));
}

// Staged with plenty of time, a location comes back as the whole retrieval brings it
// (RetrievalTest: the same words replaced and added), in the same iteration.
TEST_F(RetrievalStagingTest, WithTimeToSpareStagingRetrievesInOneIteration) {
  memory_.dictionary().Add({200}, (cv::Mat_<float>(1, 2) << 7000, 0));
  staging_.StartIteration();
  const RetrievalOutcome outcome = RetrieveStaged(ids_[2]);
  EXPECT_EQ(outcome.retrieved, (std::vector<LocationId>{ids_[2]}));
  EXPECT_EQ(outcome.deferred, 0);
  EXPECT_EQ(memory_.at(ids_[2]).signature.words, (std::vector<WordId>{30, 200}));
  EXPECT_EQ(staging_.size(), 0u);
}

// Without room for one chunk, a location is staged (its rows kept) but not searched; it stays
// staged, counted as deferred, and a later iteration wanting it again finishes it.
TEST_F(RetrievalStagingTest, ALocationWithoutRoomStaysStagedForALaterIteration) {
  staging_.StartIteration();
  StepCost chunk;
  chunk.Record(5);  // expected 5 + 2 x 2.5 = 10 ms a chunk
  RetrievalTime time;
  time.location = StepDeadline([] { return 0.0; }, 1e9, &location_cost_);
  time.search_chunk = StepDeadline([] { return 35.0; }, 40, &chunk);  // 35 + 10 > 40
  time.read_ahead = &read_ahead_;
  time.staging = &staging_;
  const RetrievalOutcome late = Retrieve(ids_[2], 1, 4, memory_, *ltm_, time);
  EXPECT_TRUE(late.retrieved.empty());
  EXPECT_EQ(late.deferred, 1);
  ASSERT_NE(staging_.Find(ids_[2]), nullptr);
  EXPECT_TRUE(staging_.Find(ids_[2])->matches.empty());
  EXPECT_TRUE(ltm_->Contains(ids_[2]));
  staging_.StartIteration();
  EXPECT_EQ(RetrieveStaged(ids_[2]).retrieved, (std::vector<LocationId>{ids_[2]}));
}

// memory.retrieval_stage_deferred: L3 is asked for when no retrieval fits any more (the iteration
// at 10 ms of a 5 ms deadline). Its rows read ahead, it is staged and wanted all the same, and the
// next iteration carries it on (ContinueStaged) with time to spare. Off, it is not staged, and
// nothing is carried on.
TEST_F(RetrievalStagingTest, ALocationAskedForWithoutTimeIsStagedAndCarriedOn) {
  for (const bool stage_deferred : {false, true}) {  // off first: it leaves L3 in LTM
    SCOPED_TRACE(stage_deferred ? "staged when deferred" : "not staged");
    RetrievalStaging staging;
    LtmReadAhead read_ahead(*ltm_);
    read_ahead.Request({ids_[2]});
    while (read_ahead.rows_read() < 1) std::this_thread::yield();  // read, as a second image finds
    staging.StartIteration();
    RetrievalTime late;
    late.location = StepDeadline([] { return 10.0; }, 5, &location_cost_);
    late.read_ahead = &read_ahead;
    late.staging = &staging;
    late.stage_deferred = stage_deferred;
    const RetrievalOutcome deferred = Retrieve(ids_[2], 1, 4, memory_, *ltm_, late);
    EXPECT_TRUE(deferred.retrieved.empty());
    EXPECT_EQ(deferred.deferred, 1);
    EXPECT_EQ(staging.Find(ids_[2]) != nullptr, stage_deferred);
    staging.StartIteration();
    RetrievalTime next;
    next.location = StepDeadline([] { return 0.0; }, 1e9, &location_cost_);
    next.search_chunk = StepDeadline([] { return 0.0; }, 1e9, &chunk_cost_);
    next.read_ahead = &read_ahead;
    next.staging = &staging;
    const RetrievalOutcome carried = ContinueStaged(1, memory_, *ltm_, next);
    EXPECT_EQ(carried.retrieved,
              stage_deferred ? std::vector<LocationId>{ids_[2]} : std::vector<LocationId>{});
    EXPECT_EQ(ltm_->Contains(ids_[2]), !stage_deferred);
  }
}

// memory.retrieval_ahead_unsearched: asked for L3, the neighbour ahead of it (L4 when the robot
// goes the way the map was made) comes first, and with no room for a chunk of search it is not
// searched: L3 waits staged, unsearched, while L4 comes back at once, its words under their old
// ids (they match nothing in the dictionary, as a search would find).
TEST_F(RetrievalStagingTest, TheNeighbourAheadComesBackUnsearched) {
  const RetrievalOutcome outcome = RetrieveWithoutRoomToSearch(ids_[2], /*ahead_unsearched=*/true);
  EXPECT_EQ(outcome.retrieved, (std::vector<LocationId>{ids_[3]}));
  EXPECT_EQ(outcome.deferred, 1);
  ASSERT_NE(staging_.Find(ids_[2]), nullptr);
  EXPECT_TRUE(staging_.Find(ids_[2])->matches.empty());
  EXPECT_EQ(memory_.at(ids_[3]).signature.words, (std::vector<WordId>{40, 70}));
  EXPECT_TRUE(map_.CheckConsistencyEmpty());
}

// With room to search, the place ahead is searched as any other: a twin of word 70 already in the
// dictionary replaces it, and word 40 matches word 30, back with L3 (3000: 1000 against 3500 for
// word 5, under the 0.8 ratio), where unsearched both would have come back under their own ids.
TEST_F(RetrievalStagingTest, WithRoomThePlaceAheadIsSearched) {
  memory_.dictionary().Add({200}, (cv::Mat_<float>(1, 2) << 7000, 0));
  staging_.StartIteration();
  const RetrievalOutcome outcome = RetrieveStaged(ids_[2], 2, /*ahead_unsearched=*/true);
  EXPECT_EQ(outcome.retrieved, (std::vector<LocationId>{ids_[2], ids_[3]}));  // L4 before L2
  EXPECT_EQ(memory_.at(ids_[3]).signature.words, (std::vector<WordId>{30, 200}));
  EXPECT_TRUE(map_.CheckConsistencyEmpty());
}

// Going back along the route, the neighbour ahead is the older one: L2.
TEST_F(RetrievalStagingTest, GoingBackTheOlderNeighbourIsAhead) {
  const RetrievalOutcome outcome = RetrieveWithoutRoomToSearch(ids_[2], /*ahead_unsearched=*/true,
                                                               /*newer_first=*/false);
  EXPECT_EQ(outcome.retrieved, (std::vector<LocationId>{ids_[1]}));
  EXPECT_EQ(outcome.deferred, 1);
  EXPECT_TRUE(ltm_->Contains(ids_[3]));
  EXPECT_TRUE(map_.CheckConsistencyEmpty());
}

// Without the parameter, nothing is retrieved unsearched: both wait for room to search.
TEST_F(RetrievalStagingTest, WithoutTheParameterEveryStagedLocationIsSearched) {
  const RetrievalOutcome outcome = RetrieveWithoutRoomToSearch(ids_[2], /*ahead_unsearched=*/false);
  EXPECT_TRUE(outcome.retrieved.empty());
  EXPECT_EQ(outcome.deferred, 2);
}

// memory.retrieval_recent_twins = 1: without room to search, L3 comes back at once, its words
// compared with those that joined since the retrieval step one image before:
// word 70 is replaced by its twin 200 (1 against 100 for 201), word 30 matches neither (4000
// against 4100, over the 0.8 ratio), and its older twin 300 is not looked for: 30 comes back
// under its own id.
TEST_F(RetrievalStagingTest, WithoutRoomTheRecentTwinsAreFoundAtOnce) {
  const RetrievalOutcome outcome = RetrieveAfterTwinsJoined(/*recent_twins=*/1);
  EXPECT_EQ(outcome.retrieved, (std::vector<LocationId>{ids_[2]}));
  EXPECT_EQ(outcome.deferred, 0);
  EXPECT_EQ(memory_.at(ids_[2]).signature.words, (std::vector<WordId>{30, 200}));
  EXPECT_TRUE(memory_.dictionary().Contains(30));
  RemoveWordsOfNoLocation({201, 300});
  EXPECT_TRUE(map_.CheckConsistencyEmpty());
}

// Two images back, the twin 300 joined since: word 30 is replaced by it (1 against 4000).
TEST_F(RetrievalStagingTest, TwinsAreLookedForAsManyImagesBackAsTheParameterSays) {
  const RetrievalOutcome outcome = RetrieveAfterTwinsJoined(/*recent_twins=*/2);
  EXPECT_EQ(outcome.retrieved, (std::vector<LocationId>{ids_[2]}));
  EXPECT_EQ(memory_.at(ids_[2]).signature.words, (std::vector<WordId>{300, 200}));
  EXPECT_FALSE(memory_.dictionary().Contains(30));
  RemoveWordsOfNoLocation({201});
  EXPECT_TRUE(map_.CheckConsistencyEmpty());
}

// The join marks of the last iterations; the oldest kept when asked for more.
TEST(RetrievalStagingOrderTest, JoinMarksOfTheLastIterations) {
  RetrievalStaging staging;
  staging.StartIteration(10);
  staging.StartIteration(20);
  staging.StartIteration(30);
  EXPECT_EQ(staging.JoinMarkBefore(0), 30);
  EXPECT_EQ(staging.JoinMarkBefore(2), 10);
  EXPECT_EQ(staging.JoinMarkBefore(5), 10);
  for (size_t i = 0; i < RetrievalStaging::kMarksKept; ++i) staging.StartIteration(100);
  EXPECT_EQ(staging.JoinMarkBefore(RetrievalStaging::kMarksKept), 100);  // 30 is no longer kept
}

// A location wanted in one of the last kCarryOnFor iterations, not this one, is carried on.
TEST_F(RetrievalStagingTest, RecentlyWantedLocationsAreCarriedOn) {
  staging_.StartIteration();
  staging_.Want(Stage(ids_[2]), 0);
  for (long long i = 0; i < RetrievalStaging::kCarryOnFor; ++i) staging_.StartIteration();
  RetrievalTime time;
  time.location = StepDeadline([] { return 0.0; }, 1e9, &location_cost_);
  time.search_chunk = StepDeadline([] { return 0.0; }, 1e9, &chunk_cost_);
  time.read_ahead = &read_ahead_;
  time.staging = &staging_;
  EXPECT_EQ(ContinueStaged(2, memory_, *ltm_, time).retrieved, (std::vector<LocationId>{ids_[2]}));
  // One iteration later it would not have been.
  staging_.StartIteration();
  staging_.Want(Stage(ids_[3]), 0);
  for (long long i = 0; i <= RetrievalStaging::kCarryOnFor; ++i) staging_.StartIteration();
  EXPECT_TRUE(ContinueStaged(2, memory_, *ltm_, time).retrieved.empty());
  EXPECT_NE(staging_.Find(ids_[3]), nullptr);  // kept until forgotten
}

// The staged locations this iteration wanted come first, by priority then in the order wanted;
// one not wanted for kForgetAfter iterations is forgotten; at most kMaxStaged are kept.
TEST(RetrievalStagingOrderTest, WantedFirstForgottenLater) {
  RetrievalStaging staging;
  staging.StartIteration();
  staging.Start(1, {});
  staging.Start(2, {});
  staging.Start(3, {});
  staging.Want(*staging.Find(2), 1);
  staging.Want(*staging.Find(3), 0);
  staging.StartIteration();
  staging.Want(*staging.Find(1), 1);
  std::vector<LocationId> order;
  for (const auto& [id, staged] : staging.ByRecency()) order.push_back(id);
  EXPECT_EQ(order, (std::vector<LocationId>{1, 3, 2}));  // 1 now; then 3 (priority 0), 2
  for (long long i = 0; i < RetrievalStaging::kForgetAfter; ++i) staging.StartIteration();
  EXPECT_EQ(staging.size(), 1u);  // 2 and 3 were last wanted kForgetAfter + 1 iterations ago
  EXPECT_NE(staging.Find(1), nullptr);
  for (LocationId id = 10; id < 10 + static_cast<LocationId>(RetrievalStaging::kMaxStaged); ++id) {
    staging.Start(id, {});
  }
  EXPECT_EQ(staging.size(), RetrievalStaging::kMaxStaged);
  EXPECT_EQ(staging.Find(1), nullptr);  // the one wanted longest ago made room
}

// Beside an extraction, the staged words are searched on another thread: the answers are those of
// the same search on the detector's thread, and the search stops when asked.
TEST_F(RetrievalStagingTest, SearchBesideTheExtractionGivesTheSameAnswers) {
  RetrievalStaging::Staged& staged = Stage(ids_[2]);
  const WordMatches expected = staged.matches;
  staged.matches.clear();
  StagedWordSearch search;
  {
    auto running = search.Start(staging_, memory_.dictionary(), *ltm_);
    running.WaitUntilSearched();  // an extraction longer than the search
  }
  EXPECT_EQ(search.words_searched(), 2);
  ASSERT_EQ(staged.matches.size(), 2u);
  for (const auto& [word, answer] : expected) {
    EXPECT_EQ(staged.matches.at(word).match, answer.match);
    EXPECT_EQ(staged.matches.at(word).nearest, answer.nearest);
    EXPECT_EQ(staged.matches.at(word).second, answer.second);
  }
  // Nothing left to search: nothing is started.
  { const auto running = search.Start(staging_, memory_.dictionary(), *ltm_); }
  EXPECT_EQ(search.words_searched(), 2);
}

// A search its thread has not begun when the extraction ends is called off, not waited for: the
// thread is held before it can take it, and the image goes on. Once free, the thread takes the next
// search as usual.
TEST_F(RetrievalStagingTest, SearchNotBegunWhenTheExtractionEndsIsCalledOff) {
  RetrievalStaging::Staged& staged = Stage(ids_[2]);
  staged.matches.clear();
  std::promise<void> release;
  std::shared_future<void> released = release.get_future().share();
  StagedWordSearch search([released] { released.wait(); });
  // Were the image to wait for the held thread, only the failsafe would free it (after 30 s): the
  // test then fails instead of hanging.
  std::once_flag once;
  const auto free_the_thread = [&] { std::call_once(once, [&] { release.set_value(); }); };
  std::atomic<bool> freed_by_failsafe{false};
  std::thread failsafe([&] {
    if (released.wait_for(std::chrono::seconds(30)) == std::future_status::ready) return;
    freed_by_failsafe = true;
    free_the_thread();
  });
  { const auto running = search.Start(staging_, memory_.dictionary(), *ltm_); }
  EXPECT_FALSE(freed_by_failsafe) << "the image waited for a search not begun";
  EXPECT_EQ(search.words_searched(), 0);
  EXPECT_TRUE(staged.matches.empty());
  free_the_thread();
  failsafe.join();
  {
    auto running = search.Start(staging_, memory_.dictionary(), *ltm_);
    running.WaitUntilSearched();
  }
  EXPECT_EQ(search.words_searched(), 2);
  EXPECT_EQ(staged.matches.size(), 2u);
}

}  // namespace
}  // namespace memloop
