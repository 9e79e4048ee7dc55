#include "vocabulary/appearance_index.h"

#include <gtest/gtest.h>

#include <cmath>

#include "memloop/errors.h"

namespace memloop {
namespace {

// One-hot 4-dimensional float rows: row k is the unit vector of axis k (scaled).
cv::Mat Rows(const std::vector<int>& axes, float scale = 1.0f) {
  cv::Mat rows = cv::Mat::zeros(static_cast<int>(axes.size()), 4, CV_32F);
  for (size_t row = 0; row < axes.size(); ++row)
    rows.at<float>(static_cast<int>(row), axes[row]) = scale;
  return rows;
}

AppearanceIndex MakeIndex(int vocabulary_size) {
  return AppearanceIndex(DescriptorKind::kFloat, 4, vocabulary_size, DictionaryOptions{});
}

TEST(AppearanceIndexTest, VocabularyIsTheFirstWordsAndThenFrozen) {
  AppearanceIndex index = MakeIndex(4);
  EXPECT_EQ(index.CollectWords({10, 11, 12}, Rows({0, 1, 2})), 3);
  EXPECT_FALSE(index.frozen());
  // Before the freeze only words of the vocabulary describe: 11 -> entry 1, 12 -> entry 2.
  EXPECT_EQ(index.Describe({12, 99, 11, 11}, Rows({2, 3, 1, 1})), (Appearance{1, 2}));
  // Only the first of the next words joins: the vocabulary is then full.
  EXPECT_EQ(index.CollectWords({13, 14}, Rows({3, 0})), 1);
  EXPECT_TRUE(index.frozen());
  EXPECT_EQ(index.vocabulary_words(), (std::vector<WordId>{10, 11, 12, 13}));
  EXPECT_EQ(index.CollectWords({15}, Rows({0})), 0);
  // Frozen: each row goes to its nearest entry, whatever its word, for features without words
  // (localization) or whose newest word is 20,000 past the vocabulary's last (13): the search
  // index is built in the background meanwhile, and until then entries are words, as before.
  EXPECT_EQ(index.Describe({kNoWord, kNoWord, kNoWord}, Rows({3, 0, 3}, 0.9f)), (Appearance{0, 3}));
  EXPECT_EQ(index.Describe({12, 20012}, Rows({0, 1})), (Appearance{2}));
  EXPECT_EQ(index.Describe({12, 20013}, Rows({0, 1})), (Appearance{0, 1}));
}

// Four locations over four entries, all searched: A {0,1}, B {1,2}, C {2,3}, D {3}.
class AppearanceSearchTest : public ::testing::Test {
 protected:
  void SetUp() override {
    index_.CollectWords({1, 2, 3, 4}, Rows({0, 1, 2, 3}));
    index_.Add(kA, {0, 1});
    index_.Add(kB, {1, 2});
    index_.Add(kC, {2, 3});
    index_.Add(kD, {3});
    for (LocationId id : {kA, kB, kC, kD}) index_.Enter(id);
  }
  static constexpr LocationId kA = 1, kB = 2, kC = 3, kD = 4;
  AppearanceIndex index_ = MakeIndex(4);
};

TEST_F(AppearanceSearchTest, ScoresByIdfOverTheDescriptionsSizes) {
  // Query {0, 1}: entry 0 is held by A only (idf ln 4), entry 1 by A and B (ln 2, half of the 4
  // searched locations: still counted). A: (ln 4 + ln 2) / sqrt(2 * 2) = ln 8 / 2; B: ln 2 / 2;
  // C and D: 0.
  const AppearanceMatch match = index_.Best({0, 1});
  const double a = std::log(8.0) / 2, b = std::log(2.0) / 2;
  EXPECT_EQ(match.id, kA);
  EXPECT_DOUBLE_EQ(match.score, a);
  const double mean = (a + b) / 4;
  const double deviation = std::sqrt((a * a + b * b) / 4 - mean * mean);
  EXPECT_NEAR(match.z, (a - mean) / deviation, 1e-12);  // 1.633
}

TEST_F(AppearanceSearchTest, ScoresOneLocationAsBestDoes) {
  // Query {0, 1} as above: A ln 8 / 2, B ln 2 / 2, C and D share nothing.
  EXPECT_DOUBLE_EQ(index_.Score({0, 1}, kA), std::log(8.0) / 2);
  EXPECT_DOUBLE_EQ(index_.Score({0, 1}, kB), std::log(2.0) / 2);
  EXPECT_EQ(index_.Score({0, 1}, kC), 0);
  // Query {1, 3}: C holds entry 3 (C and D: ln 2) over sqrt(2 * 2).
  EXPECT_DOUBLE_EQ(index_.Score({1, 3}, kC), std::log(2.0) / 2);
  EXPECT_EQ(index_.Score({}, kA), 0);
  EXPECT_EQ(index_.Score({0, 1}, 99), 0);  // not described
  // A not searched: scored as if it were (4 searched again): entry 1 held by B
  // and A (ln 2), entry 0 by A alone (ln 4); B's entry 1 now by B alone of 3 (ln 3).
  index_.Leave(kA);
  EXPECT_DOUBLE_EQ(index_.Score({0, 1}, kA), std::log(8.0) / 2);
  EXPECT_DOUBLE_EQ(index_.Score({0, 1}, kB), std::log(3.0) / 2);
}

TEST_F(AppearanceSearchTest, OnlySearchedLocationsAnswer) {
  index_.Leave(kA);
  EXPECT_FALSE(index_.Searched(kA));
  EXPECT_NE(index_.Find(kA), nullptr);  // still described
  // Three searched: entry 1 held by B only now (ln 3), entry 0 by nobody.
  const AppearanceMatch match = index_.Best({0, 1});
  EXPECT_EQ(match.id, kB);
  EXPECT_DOUBLE_EQ(match.score, std::log(3.0) / 2);
  index_.Enter(kA);
  EXPECT_EQ(index_.Best({0, 1}).id, kA);
  index_.Erase(kA);
  EXPECT_EQ(index_.Find(kA), nullptr);
  EXPECT_EQ(index_.searched_size(), 3u);
}

TEST_F(AppearanceSearchTest, CommonEntriesAreIgnoredAndTiesGoToTheOldest) {
  // Entry 3 is held by C and D, half of the 4 searched: kept.
  EXPECT_EQ(index_.Best({3}).id, kD);  // D: ln 2 / sqrt(1), C: ln 2 / sqrt(2)
  EXPECT_EQ(index_.Best({2}).id, kB);  // B and C: ln 2 / sqrt(2) each: the oldest
  index_.Leave(kA);
  EXPECT_EQ(index_.Best({3}).id, kNoLocation);  // 2 of the 3 searched hold it
}

// A bounded search (max_postings) sums the rarest entries first. Postings: entry 0 {A} (1),
// 1 {A, B} (2), 2 {B, C} (2), 3 {C, D} (2). Query {0, 1, 2}, 5 postings in all, idf ln 4, ln 2
// and ln 2, over sqrt(3 * 2) for A, B and C (descriptions of 2).
TEST(AppearanceIndexTest, BoundedSearchSumsTheRarestEntriesFirst) {
  const auto make = [](size_t max_postings) {
    AppearanceIndex index(DescriptorKind::kFloat, 4, 4, DictionaryOptions{}, max_postings);
    index.CollectWords({1, 2, 3, 4}, Rows({0, 1, 2, 3}));
    const std::vector<Appearance> descriptions = {{0, 1}, {1, 2}, {2, 3}, {3}};
    for (LocationId id = 1; id <= 4; ++id) {
      index.Add(id, descriptions[id - 1]);
      index.Enter(id);
    }
    return index;
  };
  const Appearance query = {0, 1, 2};
  const double root6 = std::sqrt(6.0);
  // 5 postings within 5 (and 0, no bound): every entry. A (ln 4 + ln 2), B (ln 2 + ln 2), C ln 2.
  for (size_t bound : {size_t{0}, size_t{5}}) {
    const AppearanceIndex all = make(bound);
    EXPECT_DOUBLE_EQ(all.Score(query, 2), std::log(4.0) / root6) << bound;
    EXPECT_DOUBLE_EQ(all.Score(query, 3), std::log(2.0) / root6) << bound;
  }
  // 3: entry 0 (1 posting), then entry 1 (3 in all; it ties with entry 2 at 2 holders and comes
  // first); entry 2 would make 5. C shares nothing summed.
  const AppearanceIndex three = make(3);
  const double a = std::log(8.0) / root6, b = std::log(2.0) / root6;
  EXPECT_DOUBLE_EQ(three.Score(query, 1), a);
  EXPECT_DOUBLE_EQ(three.Score(query, 2), b);
  EXPECT_EQ(three.Score(query, 3), 0);
  const AppearanceMatch match = three.Best(query);
  EXPECT_EQ(match.id, 1);
  EXPECT_DOUBLE_EQ(match.score, a);
  const double mean = (a + b) / 4;
  EXPECT_NEAR(match.z, (a - mean) / std::sqrt((a * a + b * b) / 4 - mean * mean), 1e-12);
  // 2: entry 0 alone; only A scores.
  const AppearanceIndex two = make(2);
  EXPECT_DOUBLE_EQ(two.Best(query).score, std::log(4.0) / root6);
  EXPECT_EQ(two.Score(query, 2), 0);
}

TEST_F(AppearanceSearchTest, NothingToFindGivesNoLocation) {
  EXPECT_EQ(index_.Best({}).id, kNoLocation);
  AppearanceIndex empty = MakeIndex(4);
  EXPECT_EQ(empty.Best({0}).id, kNoLocation);
  EXPECT_EQ(empty.Best({0}).z, 0);
}

// Best sums the postings a block of ids at a time, in id order; whatever the postings count and
// however the ids fall across blocks, it must give what scoring every searched location one by
// one gives. 2,000 locations of 20 entries out of 512, ids 97 apart (seven blocks of 32,768),
// entered in a shuffled order and some left and entered again (postings kept sorted): the
// touched ids found by their bits. With ids 1 apart, a 40- or 200-entry query's postings are many
// against the ids, and the block's scores are walked instead.
TEST(AppearanceIndexTest, BestIsTheBestOfEveryLocationsScoreWhateverThePostingsCount) {
  for (const LocationId step : {1, 97}) {
    SCOPED_TRACE(step);
    constexpr int kVocabulary = 512;
    AppearanceIndex index = MakeIndex(kVocabulary);
    cv::RNG rng(3);
    const auto describe = [&](int entries) {
      Appearance appearance;
      for (int i = 0; i < entries; ++i) appearance.push_back(rng.uniform(0, kVocabulary));
      std::sort(appearance.begin(), appearance.end());
      appearance.erase(std::unique(appearance.begin(), appearance.end()), appearance.end());
      return appearance;
    };
    std::vector<LocationId> ids;
    for (LocationId k = 0; k < 2000; ++k) ids.push_back(1 + step * k);
    for (int i = static_cast<int>(ids.size()) - 1; i > 0; --i) {
      std::swap(ids[i], ids[rng.uniform(0, i + 1)]);
    }
    std::vector<LocationId> searched;
    for (LocationId id : ids) {
      index.Add(id, describe(20));
      if (id % 7 != 0) {  // some described but not searched: they must not answer
        index.Enter(id);
        searched.push_back(id);
      }
    }
    for (size_t i = 0; i < searched.size(); i += 5) {
      index.Leave(searched[i]);
      index.Enter(searched[i]);
    }
    for (int entries : {1, 2, 40, 200}) {
      const Appearance query = describe(entries);
      AppearanceMatch expected;
      double sum = 0, sum_squares = 0;
      for (LocationId id : searched) {
        const double score = index.Score(query, id);
        sum += score;
        sum_squares += score * score;
        // ties: the oldest, as Best (searched is in the shuffled order)
        if (score > expected.score || (score == expected.score && score > 0 && id < expected.id)) {
          expected = {id, score, 0};
        }
      }
      const double mean = sum / static_cast<double>(searched.size());
      const double deviation =
          std::sqrt(sum_squares / static_cast<double>(searched.size()) - mean * mean);
      const AppearanceMatch match = index.Best(query);
      ASSERT_GT(expected.score, 0) << entries;
      EXPECT_EQ(match.id, expected.id) << entries;
      EXPECT_DOUBLE_EQ(match.score, expected.score) << entries;
      EXPECT_NEAR(match.z, (expected.score - mean) / deviation, 1e-9) << entries;
      EXPECT_EQ(index.Best(query).id, match.id) << entries;  // the scores were reset
    }
  }
}

// Locations that leave stay in the postings as tombstones: after much coming and going (some
// described anew or erased while out), every answer is that of an index that only ever held the
// locations searched at the end, entered once in id order (as a resumed map enters them).
TEST(AppearanceIndexTest, ComingAndGoingChangesNoAnswer) {
  for (const size_t bound : {size_t{0}, size_t{300}}) {
    SCOPED_TRACE(bound);
    constexpr int kVocabulary = 64;
    const auto make = [&] {
      return AppearanceIndex(DescriptorKind::kFloat, 4, kVocabulary, DictionaryOptions{}, bound);
    };
    AppearanceIndex churned = make();
    AppearanceIndex fresh = make();
    cv::RNG rng(11);
    const auto describe = [&] {
      Appearance appearance;
      for (int i = 0; i < 12; ++i) appearance.push_back(rng.uniform(0, kVocabulary));
      std::sort(appearance.begin(), appearance.end());
      appearance.erase(std::unique(appearance.begin(), appearance.end()), appearance.end());
      return appearance;
    };
    constexpr LocationId kLocations = 400;
    for (LocationId id = 1; id <= kLocations; ++id) {
      churned.Add(id, describe());
      churned.Enter(id);
    }
    // Most leave, few come back: the postings are compacted (tombstones outnumber holders), and
    // locations come back to postings that were compacted after they left and to others not.
    for (int round = 0; round < 6; ++round) {
      for (LocationId id = 1; id <= kLocations; ++id) {
        if (rng.uniform(0, 8) != 0) churned.Leave(id);
      }
      for (LocationId id = 1; id <= kLocations; ++id) {
        if (rng.uniform(0, 8) == 0) churned.Enter(id);
      }
    }
    for (LocationId id = 1; id <= kLocations; id += 9) {
      if (!churned.Searched(id)) churned.Add(id, describe());  // described anew while out
    }
    for (LocationId id = 5; id <= kLocations; id += 31) churned.Erase(id);
    for (LocationId id = 1; id <= kLocations; id += 13) churned.Enter(id);
    for (LocationId id = 1; id <= kLocations; ++id) {
      if (churned.Find(id) != nullptr) fresh.Add(id, *churned.Find(id));
      if (churned.Searched(id)) fresh.Enter(id);
    }
    ASSERT_GT(fresh.searched_size(), 50u);
    ASSERT_LT(fresh.searched_size(), 300u);
    EXPECT_EQ(churned.searched_size(), fresh.searched_size());
    for (int query = 0; query < 20; ++query) {
      const Appearance description = describe();
      const AppearanceMatch expected = fresh.Best(description);
      const AppearanceMatch match = churned.Best(description);
      ASSERT_NE(expected.id, kNoLocation);
      EXPECT_EQ(match.id, expected.id) << query;
      EXPECT_EQ(match.score, expected.score) << query;
      EXPECT_EQ(match.z, expected.z) << query;
      EXPECT_EQ(churned.Score(description, 7), fresh.Score(description, 7)) << query;
    }
  }
}

// The vocabulary's rows are made once: cv::Mat::push_back grows by half and copied every row so
// far each time (at ~20,000 rows, 28 ms inside one iteration; issue 37), and the freeze's build
// shares them instead of copying them.
TEST(AppearanceIndexTest, VocabularyRowsAreNeverCopied) {
  AppearanceIndex index = MakeIndex(4);
  ASSERT_EQ(index.CollectWords({10}, Rows({0})), 1);
  const uchar* rows = index.vocabulary().data;
  EXPECT_EQ(index.CollectWords({11, 12}, Rows({1, 2})), 2);
  EXPECT_EQ(index.vocabulary().data, rows);
  EXPECT_EQ(index.CollectWords({13}, Rows({3})), 1);
  EXPECT_TRUE(index.frozen());
  EXPECT_EQ(index.vocabulary().data, rows);
  EXPECT_EQ(index.vocabulary().rows, 4);
  EXPECT_EQ(index.vocabulary().at<float>(3, 3), 1.0f);
  // The build's index answers from the same rows.
  EXPECT_EQ(index.Describe({kNoWord, kNoWord}, Rows({3, 1}, 0.9f)), (Appearance{1, 3}));
}

TEST(AppearanceIndexTest, RefusesWhatADamagedMapWouldGive) {
  AppearanceIndex index = MakeIndex(4);
  EXPECT_THROW(index.Add(1, {4}), Error);  // entry out of the vocabulary
  EXPECT_THROW(index.Reload({1, 2}, Rows({0})), Error);
  EXPECT_THROW(index.Reload({1, 2, 3, 4, 5}, Rows({0, 1, 2, 3, 0})), Error);  // too many
  EXPECT_THROW(index.Reload({1, 1}, Rows({0, 1})), Error);                    // a repeated word
  index.Reload({1, 2, 3, 4}, Rows({0, 1, 2, 3}));
  EXPECT_TRUE(index.frozen());
  EXPECT_EQ(index.Describe({kNoWord}, Rows({2})), (Appearance{2}));
}

}  // namespace
}  // namespace memloop
