#include "vocabulary/word_index.h"

#include <gtest/gtest.h>

#include <bitset>
#include <chrono>
#include <thread>

#include "memloop/errors.h"

namespace memloop {
namespace {

cv::Mat RandomPoints(int rows, int dim, uint64_t seed) {
  cv::Mat points(rows, dim, CV_32F);
  cv::RNG(seed).fill(points, cv::RNG::UNIFORM, 0.0, 1.0);
  return points;
}

std::vector<WordId> Ids(int first, int count) {
  std::vector<WordId> ids;
  for (int i = 0; i < count; ++i) ids.push_back(first + i);
  return ids;
}

// Brute force: (nearest id, true distance) among the live points.
std::pair<WordId, float> Nearest(const cv::Mat& query, const cv::Mat& points,
                                 const std::vector<WordId>& ids, const std::set<WordId>& removed) {
  std::pair<WordId, float> best = {kNoWord, 1e30f};
  for (int row = 0; row < points.rows; ++row) {
    if (removed.count(ids[row])) continue;
    const float distance = static_cast<float>(cv::norm(query, points.row(row), cv::NORM_L2));
    if (distance < best.second) best = {ids[row], distance};
  }
  return best;
}

// Rebuilds inside the Add (delay 0) and in the background, used 2 Adds later.
class WordIndexRebuildTest : public ::testing::TestWithParam<int> {};

TEST_P(WordIndexRebuildTest, KdForestAgreesWithBruteForceThroughAddsRemovesAndRebuilds) {
  DictionaryOptions options;
  options.kd_checks = 4000;  // near exact
  options.rebuild_delay = GetParam();
  const auto forest_owner = WordIndex::Create(DescriptorKind::kFloat, 16, options);
  WordIndex& forest = *forest_owner;
  const cv::Mat points = RandomPoints(3000, 16, 1);
  const std::vector<WordId> ids = Ids(1, 3000);
  // Added in batches, as images are: the forest is extended and rebuilt along the way.
  for (int start = 0; start < 3000; start += 300) {
    forest.Add(std::vector<WordId>(ids.begin() + start, ids.begin() + start + 300),
               points.rowRange(start, start + 300));
  }
  std::set<WordId> removed;
  for (WordId id = 1; id <= 3000; id += 3) {
    forest.Remove(id);
    removed.insert(id);
  }
  EXPECT_EQ(forest.size(), 3000u - removed.size());
  EXPECT_GT(forest.build_count(), 1);

  const cv::Mat queries = RandomPoints(200, 16, 2);
  const auto found = forest.Search(queries);
  int agree = 0;
  for (int row = 0; row < queries.rows; ++row) {
    const auto expected = Nearest(queries.row(row), points, ids, removed);
    EXPECT_EQ(removed.count(found[row][0].word), 0u);
    EXPECT_LE(found[row][0].distance, found[row][1].distance);
    agree += found[row][0].word == expected.first;
    if (found[row][0].word == expected.first) {
      EXPECT_NEAR(found[row][0].distance, expected.second, 1e-4);  // true, not squared
    }
  }
  EXPECT_GE(agree, 196);  // approximate search: allow 2% misses
}

INSTANTIATE_TEST_SUITE_P(RebuildDelays, WordIndexRebuildTest, ::testing::Values(0, 2));

// 300 points, then batches of 100: the background build starts at the batch that crosses
// rebuild_fraction and is used `rebuild_delay` Adds later, not before, however fast it ran.
TEST(WordIndexTest, BackgroundRebuildIsUsedAtItsDelayWithTheWordsSinceItsSnapshot) {
  DictionaryOptions options;
  options.rebuild_delay = 3;
  auto index = WordIndex::Create(DescriptorKind::kFloat, 8, options);
  const cv::Mat points = RandomPoints(900, 8, 5);
  index->Add(Ids(1, 300), points.rowRange(0, 300));
  for (int batch = 0; batch < 3; ++batch) {  // 300 changes: not above 1.0 x 300 yet
    index->Add(Ids(301 + 100 * batch, 100), points.rowRange(300 + 100 * batch, 400 + 100 * batch));
  }
  index->Remove(2);  // 301 changes: the next Add starts the build
  index->Add(Ids(601, 100), points.rowRange(600, 700));
  IndexHistory history = index->History(0);
  EXPECT_TRUE(history.pending);
  EXPECT_EQ(history.pending_point, 700u);
  EXPECT_EQ(history.pending_words.size(), 699u);  // 700 words, 2 removed
  EXPECT_EQ(history.pending_age, 0);
  index->Remove(3);                        // removed after the snapshot
  index->Add({2}, points.rowRange(1, 2));  // back after the snapshot; age 1: the catch-up
                                           // adds it to the new forest in the background
  index->Add(Ids(701, 100), points.rowRange(700, 800));  // age 2: still the old forest
  EXPECT_EQ(index->build_count(), 1);
  index->Add(Ids(801, 100), points.rowRange(800, 900));  // age 3: the new one
  EXPECT_EQ(index->build_count(), 2);
  history = index->History(0);
  EXPECT_FALSE(history.pending);
  // Snapshot (699 words, word 3 removed since), word 2 (caught up at age 1), then 701-900 (added
  // at the swap), in the order they came.
  EXPECT_EQ(history.batch_starts, (std::vector<size_t>{0, 699, 700}));
  EXPECT_EQ(history.point_count, 699u + 201u);
  EXPECT_EQ(history.size_at_build, 699u);
  EXPECT_EQ(history.changes_since_build, 201u + 1u);  // and word 3's snapshot point removed
  EXPECT_EQ(history.point_words[699], 2);
  EXPECT_EQ(index->size(), 899u);  // 900 words, word 3 removed
  EXPECT_FALSE(index->Contains(3));
  const auto found = index->Search(points);
  for (int row = 0; row < points.rows; ++row) {
    if (row == 2) continue;
    EXPECT_EQ(found[row][0].word, row + 1);
    EXPECT_FLOAT_EQ(found[row][0].distance, 0.0f);
  }
  EXPECT_EQ(cv::norm(index->Descriptor(2), points.row(1), cv::NORM_L1), 0.0);
}

// A large snapshot waits longer: one insertion per 10,000 of its words when that is more than
// rebuild_delay (here 40,001 words: 4 insertions, not 1).
TEST(WordIndexTest, LargeSnapshotIsUsedLater) {
  DictionaryOptions options;
  options.rebuild_delay = 1;
  auto index = WordIndex::Create(DescriptorKind::kFloat, 2, options);
  index->Add(Ids(1, 20000), RandomPoints(20000, 2, 8));
  index->Add(Ids(20001, 20001), RandomPoints(20001, 2, 9));  // starts the build
  for (int insertion = 1; insertion <= 4; ++insertion) {
    EXPECT_EQ(index->build_count(), 1) << "insertion " << insertion;
    index->Add({50000 + insertion}, RandomPoints(1, 2, 10 + insertion));
  }
  EXPECT_EQ(index->build_count(), 2);
}

// With T_time on, the new forest is used at the first Add after it is built.
TEST(WordIndexTest, BackgroundRebuildIsNotWaitedForWithSwapWhenReady) {
  DictionaryOptions options;
  options.rebuild_delay = 2;
  options.rebuild_swap_when_ready = true;
  auto index = WordIndex::Create(DescriptorKind::kFloat, 8, options);
  index->Add(Ids(1, 200), RandomPoints(200, 8, 6));
  index->Add(Ids(201, 201), RandomPoints(201, 8, 7));  // starts the build
  WordId next = 1000;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::minutes(2);
  while (index->build_count() == 1 && std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
    index->Add({next}, RandomPoints(1, 8, next));
    ++next;
  }
  EXPECT_EQ(index->build_count(), 2);
  EXPECT_EQ(index->size(), 401u + (next - 1000));
}

// late_steps counts the Adds at which a due swap was not done: with T_time on, a swap later than
// its delay was late at each Add after it, a swap on time never; with T_time off the step is waited
// for, never late. (Whether a build is late depends on the machine; the verdict does not.)
TEST(WordIndexTest, LateStepsCountBuildsNotWaitedFor) {
  for (bool swap_when_ready : {false, true}) {
    DictionaryOptions options;
    options.rebuild_delay = 2;
    options.rebuild_swap_when_ready = swap_when_ready;
    auto index = WordIndex::Create(DescriptorKind::kFloat, 8, options);
    index->Add(Ids(1, 20000), RandomPoints(20000, 8, 6));
    index->Add(Ids(20001, 20001), RandomPoints(20001, 8, 7));  // starts a 40,001-word build
    WordId next = 50000;
    int adds = 0;
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::minutes(2);
    while (index->build_count() == 1 && std::chrono::steady_clock::now() < deadline) {
      index->Add({next}, RandomPoints(1, 8, next));
      std::this_thread::sleep_for(std::chrono::microseconds(200));
      ++next;
      ++adds;
    }
    ASSERT_EQ(index->build_count(), 2) << swap_when_ready;
    if (!swap_when_ready) {
      EXPECT_EQ(adds, 4);  // the delay for 40,001 words, waited for
      EXPECT_EQ(index->late_steps(), 0);
    } else {
      EXPECT_GE(adds, 4);
      EXPECT_EQ(index->late_steps(), adds - 4);
    }
  }
}

// With T_time on, points that come while the new forest catches up are caught up in more rounds
// (as many as the threads' speed makes): every live word is still found, at distance 0, and no
// removed one. The first 30,000 points come in batches larger than a swap adds itself, then one
// at a time, so that the build ends however slow the machine is.
TEST(WordIndexTest, CatchUpInRoundsKeepsEveryWordAndNoRemovedOne) {
  DictionaryOptions options;
  options.rebuild_delay = 1;  // late from the second Add on: the rounds' case
  options.rebuild_swap_when_ready = true;
  auto index = WordIndex::Create(DescriptorKind::kFloat, 8, options);
  cv::Mat points = RandomPoints(3000, 8, 11);
  index->Add(Ids(1, 3000), points);
  WordId next = 3001;
  WordId oldest = 1;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::minutes(2);
  while (index->build_count() < 2 && std::chrono::steady_clock::now() < deadline) {
    const int count = next <= 30000 ? 1500 : 1;  // 1,500: more than the 1,000 a swap adds itself
    const cv::Mat batch = RandomPoints(count, 8, next);
    index->Add(Ids(next, count), batch);
    points.push_back(batch);
    next += count;
    while (next - oldest > 3000) index->Remove(oldest++);
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  ASSERT_EQ(index->build_count(), 2);
  EXPECT_EQ(index->size(), static_cast<size_t>(next - oldest));
  const auto found = index->Search(points);
  for (WordId id = 1; id < next; ++id) {
    const auto& nearest = found[id - 1][0];
    if (id < oldest) {
      EXPECT_NE(nearest.word, id) << "removed word " << id << " was found";
    } else {
      EXPECT_EQ(nearest.word, id);
      EXPECT_EQ(nearest.distance, 0.0f);
    }
  }
}

TEST(WordIndexTest, KdForestFindsItsOwnPointsAfterRebuildAndKeepsDescriptors) {
  const auto forest_owner = WordIndex::Create(DescriptorKind::kFloat, 8, DictionaryOptions());
  WordIndex& forest = *forest_owner;
  const cv::Mat points = RandomPoints(500, 8, 3);
  forest.Add(Ids(100, 250), points.rowRange(0, 250));
  forest.Add(Ids(350, 250), points.rowRange(250, 500));  // doubles the size: rebuilt
  const auto found = forest.Search(points);
  for (int row = 0; row < points.rows; ++row) {
    EXPECT_EQ(found[row][0].word, 100 + row);
    EXPECT_FLOAT_EQ(found[row][0].distance, 0.0f);
  }
  EXPECT_EQ(forest.Descriptor(360).at<float>(0, 3), points.at<float>(260, 3));
  EXPECT_TRUE(forest.Descriptor(99).empty());
}

TEST(WordIndexTest, KdForestSameInputSameForest) {
  const cv::Mat points = RandomPoints(2000, 32, 4);
  const cv::Mat queries = RandomPoints(300, 32, 5);
  auto a_owner = WordIndex::Create(DescriptorKind::kFloat, 32, DictionaryOptions());
  auto b_owner = WordIndex::Create(DescriptorKind::kFloat, 32, DictionaryOptions());
  WordIndex& a = *a_owner;
  WordIndex& b = *b_owner;
  a.Add(Ids(1, 2000), points);
  b.Add(Ids(1, 2000), points);
  const auto found_a = a.Search(queries);
  const auto found_b = b.Search(queries);
  for (int row = 0; row < queries.rows; ++row) {
    EXPECT_EQ(found_a[row][0].word, found_b[row][0].word);
    EXPECT_EQ(found_a[row][1].word, found_b[row][1].word);
  }
}

TEST(WordIndexTest, KdForestEmptyAndSingleWord) {
  const auto forest_owner = WordIndex::Create(DescriptorKind::kFloat, 2, DictionaryOptions());
  WordIndex& forest = *forest_owner;
  const cv::Mat query = (cv::Mat_<float>(1, 2) << 1, 1);
  EXPECT_EQ(forest.Search(query)[0][0].word, kNoWord);
  forest.Add({7}, (cv::Mat_<float>(1, 2) << 4, 5));
  const auto found = forest.Search(query);
  EXPECT_EQ(found[0][0].word, 7);
  EXPECT_FLOAT_EQ(found[0][0].distance, 5.0f);  // 3-4-5
  EXPECT_EQ(found[0][1].word, kNoWord);
  forest.Remove(7);
  EXPECT_EQ(forest.Search(query)[0][0].word, kNoWord);
}

int Hamming(const cv::Mat& a, const cv::Mat& b) {
  return static_cast<int>(cv::norm(a, b, cv::NORM_HAMMING));
}

// Binary words (ORB): LSH with Hamming distances, against brute force.
TEST(WordIndexTest, LshFindsNearWordsByHammingDistance) {
  DictionaryOptions options;
  const auto index_owner = WordIndex::Create(DescriptorKind::kBinary, 32, options);
  WordIndex& index = *index_owner;
  cv::Mat words(2000, 32, CV_8U);
  cv::RNG(6).fill(words, cv::RNG::UNIFORM, 0, 256);
  index.Add(Ids(1, 1000), words.rowRange(0, 1000));
  index.Add(Ids(1001, 1000), words.rowRange(1000, 2000));
  for (WordId id = 1; id <= 2000; id += 4) index.Remove(id);
  EXPECT_EQ(index.size(), 1500u);
  // Queries: copies of live words with 6 of 256 bits flipped; their word is far the nearest.
  cv::Mat queries = words.rowRange(0, 200).clone();
  cv::RNG flips(7);
  for (int row = 0; row < queries.rows; ++row) {
    for (int n = 0; n < 6; ++n) {
      const int bit = flips.uniform(0, 256);
      queries.at<unsigned char>(row, bit / 8) ^= static_cast<unsigned char>(1 << (bit % 8));
    }
  }
  const auto found = index.Search(queries);
  int agree = 0;
  int live = 0;
  for (int row = 0; row < queries.rows; ++row) {
    const WordId own = row + 1;
    EXPECT_NE((found[row][0].word - 1) % 4, 0) << "a removed word was returned";
    if ((own - 1) % 4 == 0) continue;  // removed
    ++live;
    if (found[row][0].word == own) {
      ++agree;
      EXPECT_EQ(found[row][0].distance, Hamming(queries.row(row), words.row(own - 1)));
      // LSH may find a single candidate: the second is then kNoWord.
      if (found[row][1].word != kNoWord) {
        EXPECT_GE(found[row][1].distance, found[row][0].distance);
      }
    }
  }
  EXPECT_GE(agree, 0.95 * live);
  EXPECT_EQ(Hamming(index.Descriptor(1002), words.row(1001)), 0);
}

// Resume replays the index's history: FLANN's trees depend on the order points came in, so the
// replayed index must answer every (approximate) search exactly as the original, and go on alike.
cv::Mat Points(DescriptorKind kind, int rows, int dim, uint64_t seed) {
  if (kind == DescriptorKind::kFloat) return RandomPoints(rows, dim, seed);
  cv::Mat bytes(rows, dim, CV_8U);
  cv::RNG(seed).fill(bytes, cv::RNG::UNIFORM, 0, 256);
  return bytes;
}

void ExpectSameSearches(const WordIndex& a, const WordIndex& b, const cv::Mat& queries) {
  const auto found_a = a.Search(queries);
  const auto found_b = b.Search(queries);
  for (int row = 0; row < queries.rows; ++row) {
    for (int n = 0; n < 2; ++n) {
      ASSERT_EQ(found_a[row][n].word, found_b[row][n].word) << "query " << row;
      ASSERT_EQ(found_a[row][n].distance, found_b[row][n].distance) << "query " << row;
    }
  }
}

int DifferentSearches(const WordIndex& a, const WordIndex& b, const cv::Mat& queries) {
  const auto found_a = a.Search(queries);
  const auto found_b = b.Search(queries);
  int different = 0;
  for (int row = 0; row < queries.rows; ++row)
    different += found_a[row][0].word != found_b[row][0].word;
  return different;
}

class WordIndexReplayTest : public ::testing::TestWithParam<DescriptorKind> {};

TEST_P(WordIndexReplayTest, ReplayedHistoryGivesTheSameIndex) {
  const DescriptorKind kind = GetParam();
  const int dim = kind == DescriptorKind::kFloat ? 16 : 32;
  DictionaryOptions options;
  options.kd_checks = 4;           // approximate: results depend on the trees
  options.rebuild_fraction = 2.0;  // batches accumulate, then one rebuild below
  options.rebuild_delay = 3;
  auto original = WordIndex::Create(kind, dim, options);
  original->Add(Ids(1, 400), Points(kind, 400, dim, 11));
  original->Add(Ids(401, 300), Points(kind, 300, dim, 12));
  std::vector<WordId> live;
  for (WordId id = 1; id <= 700; ++id) {
    if (id % 7 == 0) {
      original->Remove(id);
    } else {
      live.push_back(id);
    }
  }
  original->Add({14, 28}, Points(kind, 2, dim, 13));  // removed words come back (retrieval)
  live.push_back(14);
  live.push_back(28);
  original->Add(Ids(701, 100), Points(kind, 100, dim, 14));
  for (WordId id = 701; id <= 800; ++id) live.push_back(id);
  EXPECT_EQ(original->build_count(), 1);

  auto replayed = WordIndex::Create(kind, dim, options);
  replayed->Replay(original->History(0), live);
  const cv::Mat queries = Points(kind, 300, dim, 15);
  EXPECT_EQ(replayed->size(), original->size());
  ExpectSameSearches(*original, *replayed, queries);
  // A forest built afresh from the live words answers differently: the test can tell.
  if (kind == DescriptorKind::kFloat) {
    auto fresh = WordIndex::Create(kind, dim, options);
    cv::Mat live_points;
    for (WordId id : live) live_points.push_back(original->Descriptor(id));
    fresh->Add(live, live_points);
    EXPECT_GT(DifferentSearches(*original, *fresh, queries), 0);
  }
  // Both go on alike, through the next rebuild (the counters came back too).
  for (int batch = 0; batch < 12; ++batch) {
    const cv::Mat more = Points(kind, 100, dim, 100 + batch);
    original->Add(Ids(1000 + batch * 100, 100), more);
    replayed->Add(Ids(1000 + batch * 100, 100), more);
  }
  EXPECT_EQ(replayed->build_count(), original->build_count());
  EXPECT_EQ(original->build_count(), 2);  // the test went through a rebuild
  ExpectSameSearches(*original, *replayed, queries);
}

// Few checks (so that a different forest gives different answers) and a background rebuild used
// 4 Adds after it starts.
DictionaryOptions RebuildAfterFourAdds() {
  DictionaryOptions options;
  options.kd_checks = 4;
  options.rebuild_delay = 4;
  return options;
}

// Checkpointed after the catch-up started (delay 4: at age 2), with a word added before it and
// removed after, and a word removed before the snapshot's use and added again: the replay starts
// the same catch-up (up to the same point) and swaps at the same Add, to the same forest.
TEST_P(WordIndexReplayTest, ReplayDuringTheCatchUpGoesOnAsTheOriginal) {
  const DescriptorKind kind = GetParam();
  const int dim = kind == DescriptorKind::kFloat ? 16 : 32;
  const DictionaryOptions options = RebuildAfterFourAdds();
  auto original = WordIndex::Create(kind, dim, options);
  original->Add(Ids(1, 300), Points(kind, 300, dim, 61));
  original->Add(Ids(301, 301), Points(kind, 301, dim, 62));  // starts the build
  original->Remove(5);
  original->Add(Ids(700, 50), Points(kind, 50, dim, 63));  // age 1
  original->Add(Ids(750, 20), Points(kind, 20, dim, 64));  // age 2: the catch-up starts
  original->Remove(710);                                   // caught up, then removed
  original->Add({5}, Points(kind, 1, dim, 65));            // age 3: back
  const IndexHistory history = original->History(0);
  ASSERT_TRUE(history.pending);
  ASSERT_EQ(history.pending_age, 3);
  std::vector<WordId> live;
  for (WordId id = 1; id <= 601; ++id) live.push_back(id);
  for (WordId id = 700; id < 770; ++id) {
    if (id != 710) live.push_back(id);
  }
  auto replayed = WordIndex::Create(kind, dim, options);
  replayed->Replay(history, live);
  const cv::Mat queries = Points(kind, 300, dim, 66);
  ExpectSameSearches(*original, *replayed, queries);
  for (int batch = 0; batch < 3; ++batch) {
    const cv::Mat more = Points(kind, 20, dim, 70 + batch);
    original->Add(Ids(800 + 20 * batch, 20), more);
    replayed->Add(Ids(800 + 20 * batch, 20), more);
  }
  EXPECT_EQ(original->build_count(), 2);
  EXPECT_EQ(replayed->build_count(), 2);
  ExpectSameSearches(*original, *replayed, queries);
  const IndexHistory after = original->History(0);
  EXPECT_EQ(after.batch_starts, replayed->History(0).batch_starts);
  EXPECT_EQ(after.point_words, replayed->History(0).point_words);
  EXPECT_FALSE(original->Contains(710));
  EXPECT_TRUE(original->Contains(5));
  // And a replay of the rebuilt index's own history gives it again.
  auto again = WordIndex::Create(kind, dim, options);
  std::vector<WordId> now = live;
  for (WordId id = 800; id < 860; ++id) now.push_back(id);
  again->Replay(after, now);
  ExpectSameSearches(*original, *again, queries);
}

// A map checkpointed while a rebuild runs in the background resumes with that build pending, and
// goes on exactly as the original (the new forest used at the same Add, from the same snapshot).
TEST_P(WordIndexReplayTest, ReplayDuringABackgroundRebuildGoesOnAsTheOriginal) {
  const DescriptorKind kind = GetParam();
  const int dim = kind == DescriptorKind::kFloat ? 16 : 32;
  const DictionaryOptions options = RebuildAfterFourAdds();
  auto original = WordIndex::Create(kind, dim, options);
  original->Add(Ids(1, 300), Points(kind, 300, dim, 41));
  original->Add(Ids(301, 301), Points(kind, 301, dim, 42));  // starts the build
  original->Remove(5);                                       // after the snapshot
  original->Add(Ids(700, 50), Points(kind, 50, dim, 43));
  const IndexHistory history = original->History(0);
  ASSERT_TRUE(history.pending);
  std::vector<WordId> live;
  for (WordId id = 1; id <= 601; ++id) {
    if (id != 5) live.push_back(id);
  }
  for (WordId id = 700; id < 750; ++id) live.push_back(id);
  auto replayed = WordIndex::Create(kind, dim, options);
  replayed->Replay(history, live);
  const cv::Mat queries = Points(kind, 300, dim, 44);
  ExpectSameSearches(*original, *replayed, queries);
  for (int batch = 0; batch < 4; ++batch) {
    const cv::Mat more = Points(kind, 20, dim, 50 + batch);
    original->Add(Ids(800 + 20 * batch, 20), more);
    replayed->Add(Ids(800 + 20 * batch, 20), more);
  }
  EXPECT_EQ(original->build_count(), 2);  // the pending build was used
  EXPECT_EQ(replayed->build_count(), 2);
  ExpectSameSearches(*original, *replayed, queries);
  if (kind == DescriptorKind::kFloat) {  // the swap changed the answers: the test can tell
    auto never_rebuilt = WordIndex::Create(kind, dim, options);
    IndexHistory no_pending = history;
    no_pending.pending = false;
    never_rebuilt->Replay(no_pending, live);
    for (int batch = 0; batch < 4; ++batch) {
      never_rebuilt->Add(Ids(800 + 20 * batch, 20), Points(kind, 20, dim, 50 + batch));
    }
    EXPECT_EQ(never_rebuilt->build_count(), 1);
    EXPECT_GT(DifferentSearches(*original, *never_rebuilt, queries), 0);
  }
}

// Between the catch-up and the swap, rounds catch up the points that came meanwhile, as many as
// the build thread's speed allows (a round starts when the last one has ended). Only where the
// batches split depends on it: the forest answers as a replay of the same points with everything
// after the snapshot in one batch, however many rounds there were.
TEST_P(WordIndexReplayTest, RoundsBeforeTheSwapGiveTheIndexOfOneCatchUp) {
  const DescriptorKind kind = GetParam();
  const int dim = kind == DescriptorKind::kFloat ? 16 : 32;
  DictionaryOptions options;
  options.kd_checks = 4;
  options.rebuild_delay = 12;
  auto original = WordIndex::Create(kind, dim, options);
  original->Add(Ids(1, 300), Points(kind, 300, dim, 81));
  original->Add(Ids(301, 301), Points(kind, 301, dim, 82));  // starts the build
  std::vector<WordId> live = Ids(1, 601);
  for (int age = 1; age <= 12; ++age) {
    const std::vector<WordId> ids = Ids(1000 + 150 * age, 150);
    original->Add(ids, Points(kind, 150, dim, 82 + age));
    live.insert(live.end(), ids.begin(), ids.end());
    std::this_thread::sleep_for(std::chrono::milliseconds(20));  // time for a round, if it runs
  }
  ASSERT_EQ(original->build_count(), 2);
  const IndexHistory history = original->History(0);
  RecordProperty("batches_after_the_snapshot", static_cast<int>(history.batch_starts.size()) - 1);
  IndexHistory one_catch_up = history;
  one_catch_up.batch_starts = {0, history.size_at_build};
  auto replayed = WordIndex::Create(kind, dim, options);
  replayed->Replay(one_catch_up, live);
  EXPECT_EQ(history.size_at_build, 601u);
  EXPECT_EQ(replayed->size(), original->size());
  ExpectSameSearches(*original, *replayed, Points(kind, 300, dim, 99));
}

TEST_P(WordIndexReplayTest, HistoryFromAPointHoldsOnlyTheLaterPoints) {
  const DescriptorKind kind = GetParam();
  auto index = WordIndex::Create(kind, 32, DictionaryOptions());
  const cv::Mat points = Points(kind, 30, 32, 21);
  index->Add(Ids(1, 20), points.rowRange(0, 20));
  index->Add(Ids(21, 10), points.rowRange(20, 30));
  const IndexHistory history = index->History(25);
  EXPECT_EQ(history.point_count, 30u);
  EXPECT_EQ(history.first_point, 25u);
  EXPECT_EQ(history.batch_starts, (std::vector<size_t>{0, 20}));
  EXPECT_EQ(history.point_words, (std::vector<WordId>{26, 27, 28, 29, 30}));
  EXPECT_EQ(cv::norm(history.descriptors, points.rowRange(25, 30), cv::NORM_L1), 0.0);
}

TEST_P(WordIndexReplayTest, InconsistentHistoryIsRefused) {
  const DescriptorKind kind = GetParam();
  auto index = WordIndex::Create(kind, 32, DictionaryOptions());
  index->Add(Ids(1, 10), Points(kind, 10, 32, 31));
  IndexHistory history = index->History(0);
  auto other = WordIndex::Create(kind, 32, DictionaryOptions());
  EXPECT_THROW(other->Replay(history, {11}), Error);  // a live word the history never had
  history.batch_starts = {3};
  EXPECT_THROW(other->Replay(history, {1}), Error);  // the first batch must start at point 0
  history = index->History(0);
  history.point_words.pop_back();
  EXPECT_THROW(other->Replay(history, {1}), Error);
}

// Searches shared between threads give each query the answer one thread gives (issue 9: an
// image's descriptors and a retrieved location's words are searched in chunks by
// dictionary.search_threads threads). Approximate searches, after removals: the answers depend on
// which leaves each query's own search visits, so a query answered from another's rows shows.
TEST_P(WordIndexReplayTest, SearchThreadsGiveTheSameAnswers) {
  const DescriptorKind kind = GetParam();
  const int dim = kind == DescriptorKind::kFloat ? 16 : 32;
  std::vector<std::unique_ptr<WordIndex>> indexes;
  for (int threads : {1, 2, 3}) {
    DictionaryOptions options;
    options.kd_checks = 4;
    options.search_threads = threads;
    indexes.push_back(WordIndex::Create(kind, dim, options));
    indexes.back()->Add(Ids(1, 500), Points(kind, 500, dim, 21));
    for (WordId id = 1; id <= 500; id += 5) indexes.back()->Remove(id);
  }
  const cv::Mat queries = Points(kind, 300, dim, 22);  // 19 chunks of 16 queries
  ExpectSameSearches(*indexes[0], *indexes[1], queries);
  ExpectSameSearches(*indexes[0], *indexes[2], queries);
  // Each row's answer is its own query's, at the chunks' edges too: searched alone, the same.
  const auto shared = indexes[1]->Search(queries);
  for (int row : {0, 15, 16, 17, 31, 32, 299}) {
    const auto alone = indexes[1]->Search(queries.rowRange(row, row + 1));
    EXPECT_EQ(shared[row][0].word, alone[0][0].word) << "query " << row;
    EXPECT_EQ(shared[row][1].word, alone[0][1].word) << "query " << row;
  }
}

INSTANTIATE_TEST_SUITE_P(FloatAndBinary, WordIndexReplayTest,
                         ::testing::Values(DescriptorKind::kFloat, DescriptorKind::kBinary));

}  // namespace
}  // namespace memloop
