#include "detector/checkpoint.h"

#include <gtest/gtest.h>

#include <cstring>
#include <map>
#include <set>

#include "memloop/errors.h"
#include "small_memory.h"
#include "temp_dir.h"

namespace memloop {
namespace {

using testing::AddChain;
using testing::SmallDictionaryOptions;

Location SampleLocation() {
  Location location;
  location.id = 7;
  location.weight = 3;
  location.signature = testing::MakeSignature({4, 9, 4});
  location.neighbours = {6, 8};
  location.loop_closures = {2};
  location.images = {7, 12};
  location.signature.image = 12;  // its keypoints are image 12's (Rehearsal)
  return location;
}

TEST(CheckpointTest, LocationsRoundTripExactly) {
  const Location location = SampleLocation();
  const Location decoded = DecodeLocation(EncodeLocation(location));
  EXPECT_EQ(decoded.id, 7);
  EXPECT_EQ(decoded.weight, 3);
  EXPECT_EQ(decoded.signature.words, location.signature.words);
  ASSERT_EQ(decoded.signature.keypoints.size(), 3u);
  EXPECT_EQ(decoded.signature.keypoints[2].pt, location.signature.keypoints[2].pt);
  EXPECT_EQ(decoded.signature.keypoints[2].octave, 1);
  EXPECT_EQ(decoded.neighbours, location.neighbours);
  EXPECT_EQ(decoded.loop_closures, location.loop_closures);
  EXPECT_EQ(decoded.images, location.images);
  EXPECT_EQ(decoded.signature.image, 12);
  // A checkpoint written before the signature's image was kept: the same, the image unknown.
  std::vector<unsigned char> older = EncodeLocation(location);
  older.resize(older.size() - sizeof(int32_t));
  EXPECT_EQ(DecodeLocation(older).signature.image, kNoImage);
  EXPECT_EQ(DecodeLocation(older).signature.words, location.signature.words);
}

// features.whole_image: the descriptor follows the image at the end; without one, the bytes are
// those of format 5 (what a map made before the channel holds).
TEST(CheckpointTest, WholeImageDescriptorRoundTripsAndIsOptional) {
  Location location = SampleLocation();
  const std::vector<unsigned char> without = EncodeLocation(location);
  EXPECT_TRUE(DecodeLocation(without).signature.whole_image.empty());
  location.signature.whole_image = {0, 17, 255, 3};
  const std::vector<unsigned char> with = EncodeLocation(location);
  EXPECT_EQ(with.size(), without.size() + sizeof(uint64_t) + 4);
  EXPECT_EQ(DecodeLocation(with).signature.whole_image, location.signature.whole_image);
  EXPECT_EQ(DecodeLocation(with).signature.image, 12);
  std::vector<unsigned char> cut = with;
  cut.pop_back();
  EXPECT_THROW(DecodeLocation(cut), Error);
}

TEST(CheckpointTest, DamagedLocationBytesAreRefused) {
  std::vector<unsigned char> bytes = EncodeLocation(SampleLocation());
  std::vector<unsigned char> cut(bytes.begin(), bytes.end() - 3);
  EXPECT_THROW(DecodeLocation(cut), Error);
  bytes.push_back(0);
  EXPECT_THROW(DecodeLocation(bytes), Error);
  // A count far larger than the bytes left is refused before anything is allocated.
  std::vector<unsigned char> huge = EncodeLocation(SampleLocation());
  huge[15] = 0x7f;  // the image count's most significant byte
  EXPECT_THROW(DecodeLocation(huge), Error);
}

class CheckpointWriterTest : public ::testing::Test {
 protected:
  CheckpointWriterTest()
      : memory_(DescriptorKind::kFloat, 2, Options()), filter_(FilterOptions()) {}

  static DictionaryOptions Options() {
    DictionaryOptions options = SmallDictionaryOptions();
    options.rebuild_fraction = 100;  // points stay in the order they came
    return options;
  }

  CheckpointData Next() {
    return writer_.Next(memory_, filter_, past_matches_, counters_, kept_last_);
  }

  Memory memory_;
  BayesFilter filter_;
  std::vector<PastMatch> past_matches_;
  DetectorCounters counters_;
  RecentRetrievals kept_last_{10};
  CheckpointWriter writer_;
};

TEST_F(CheckpointWriterTest, WritesEverythingFirstThenOnlyWhatChanged) {
  AddChain(memory_, {{1, 2}, {2, 3}, {4}});  // words 1-4, one Add each
  CheckpointData first = Next();
  EXPECT_TRUE(first.full);
  EXPECT_EQ(first.locations.size(), 3u);
  EXPECT_EQ(first.index_words, (std::vector<WordId>{1, 2, 3, 4}));
  EXPECT_EQ(first.index_descriptors.size(), 4u);
  EXPECT_EQ(first.state.size(), 8u);  // counters, stm, index (and pending build), filter, past
                                      // matches, retrieved locations kept last, the previous
                                      // hypothesis value; no LTM mark yet, so no chunk of them

  const CheckpointData unchanged = Next();
  EXPECT_FALSE(unchanged.full);
  EXPECT_TRUE(unchanged.locations.empty());
  EXPECT_TRUE(unchanged.removed_locations.empty());
  EXPECT_TRUE(unchanged.index_words.empty());
  EXPECT_TRUE(unchanged.index_descriptors.empty());
  EXPECT_TRUE(unchanged.state.empty());

  memory_.at(2).weight = 5;
  AddChain(memory_, {{5}});  // location 4 with a new word: one new index point
  counters_.last_image = 3;
  const CheckpointData changed = Next();
  ASSERT_EQ(changed.locations.size(), 2u);  // 2 (weight) and 4 (new, a chain of its own)
  EXPECT_EQ(changed.locations[0].first, 2);
  EXPECT_EQ(changed.locations[1].first, 4);
  EXPECT_FALSE(changed.reset_index);
  EXPECT_EQ(changed.first_index_point, 4);
  EXPECT_EQ(changed.index_words, (std::vector<WordId>{5}));
  ASSERT_EQ(changed.index_descriptors.size(), 1u);
  EXPECT_EQ(changed.index_descriptors[0].first, 5);
  EXPECT_EQ(changed.state.size(), 3u);  // counters, stm, index

  std::vector<WordId> orphans;
  memory_.MoveStmOverflowToWm(0);
  memory_.Release(1, &orphans);
  const CheckpointData removed = Next();
  EXPECT_EQ(removed.removed_locations, (std::vector<LocationId>{1}));
}

// The checkpoint looks only at the locations Memory lists as changed. After every one of 300
// random changes (new locations, weights, links, merges, transfers, retrievals), the file's
// locations, each checkpoint applied in turn, must be memory's, each encoded as it is now.
TEST_F(CheckpointWriterTest, FileHoldsExactlyMemorysLocationsAfterRandomChanges) {
  std::map<LocationId, std::vector<unsigned char>> file;
  const auto apply = [&](const CheckpointData& checkpoint) {
    if (checkpoint.full) file.clear();
    for (const auto& [id, bytes] : checkpoint.locations) file[id] = bytes;
    for (LocationId id : checkpoint.removed_locations) ASSERT_EQ(file.erase(id), 1u) << id;
  };
  std::map<LocationId, Location> ltm;
  cv::RNG rng(5);
  LocationId previous = kNoLocation;
  WordId next_word = 1;
  for (int step = 0; step < 300; ++step) {
    const std::vector<LocationId> wm(memory_.working_memory().begin(),
                                     memory_.working_memory().end());
    const auto any_wm = [&] { return wm[rng.uniform(0, static_cast<int>(wm.size()))]; };
    switch (wm.size() < 3 ? 0 : rng.uniform(0, 6)) {
      case 0: {  // a new location, its own word
        testing::AddWords(memory_.dictionary(), {next_word});
        previous = memory_.AddToStm(testing::MakeSignature({next_word++}), step, previous).id;
        memory_.MoveStmOverflowToWm(2);
        break;
      }
      case 1:
        memory_.at(any_wm()).weight += 1;
        break;
      case 2: {
        const LocationId a = any_wm(), b = any_wm();
        if (a != b) memory_.AddLinksOf(a, b, /*link_together=*/true);
        break;
      }
      case 3: {
        const LocationId a = any_wm(), b = any_wm();
        if (a != b) memory_.Absorb(a, b);
        break;
      }
      case 4: {
        const LocationId id = any_wm();
        std::vector<WordId> orphans;
        ltm[id] = memory_.Release(id, &orphans);
        break;
      }
      case 5:
        if (!ltm.empty()) {
          memory_.Restore(ltm.begin()->second);
          ltm.erase(ltm.begin());
        }
        break;
    }
    if (step % 3 == 0) {  // not at every step: changes pile up between checkpoints too
      apply(Next());
      memory_.ClearChanged();
      std::map<LocationId, std::vector<unsigned char>> expected;
      for (const auto& [id, location] : memory_.locations())
        expected[id] = EncodeLocation(location);
      ASSERT_EQ(file, expected) << "after step " << step;
    }
  }
}

// LTM's marks on words go by chunks of 4,096 word ids, and a chunk is written again only when
// one of its marks changed (issue 9: the whole list was written at every image).
TEST_F(CheckpointWriterTest, LtmMarksAreWrittenOnlyWhenTheirChunkChanged) {
  const auto marks_keys = [](const CheckpointData& checkpoint) {
    std::vector<std::string> keys;
    for (const auto& [key, value] : checkpoint.state) {
      if (key.rfind("word_marks.", 0) == 0) keys.push_back(key);
    }
    return keys;
  };
  AddChain(memory_, {{1, 2}, {2, 3}, {4}});
  memory_.dictionary().MarkReferencedByLtm(2);
  EXPECT_EQ(marks_keys(Next()), (std::vector<std::string>{"word_marks.0"}));  // the first: all
  // Next does not clear what changed (the detector does, once the checkpoint is queued).
  EXPECT_EQ(marks_keys(Next()), (std::vector<std::string>{"word_marks.0"}));
  memory_.ClearChanged();
  EXPECT_TRUE(marks_keys(Next()).empty());
  memory_.dictionary().MarkReferencedByLtm(2);  // already marked: nothing changed
  EXPECT_TRUE(marks_keys(Next()).empty());
  memory_.dictionary().MarkReferencedByLtm(3);
  const CheckpointData marked = Next();
  ASSERT_EQ(marks_keys(marked), (std::vector<std::string>{"word_marks.0"}));
  memory_.ClearChanged();
  EXPECT_TRUE(marks_keys(Next()).empty());
  // Word 9,000 is in chunk 2 (ids 8,192-12,287): only that chunk is written.
  testing::AddWords(memory_.dictionary(), {9000});
  memory_.dictionary().MarkReferencedByLtm(9000);
  EXPECT_EQ(marks_keys(Next()), (std::vector<std::string>{"word_marks.2"}));
}

// A map of format 5 holds the marks by chunks of 65,536 ids under the keys ltm_marks.N: they are
// read as such, and the first checkpoint of the session (a full one) replaces them.
TEST_F(CheckpointWriterTest, MarksOfAFormatFiveMapAreReadAndReplaced) {
  testing::TempDir dir;
  LtmDatabase database(dir.File("map.db"), LtmDatabase::Mode::kCreate);
  AddChain(memory_, {{1, 2}});
  testing::AddWords(memory_.dictionary(), {5000, 70000});
  CheckpointData checkpoint = Next();  // no marks yet: no chunk of them
  // Format 5's bytes, by hand: a count of 64-bit blocks, then the blocks. Word 5,000 is block 78,
  // bit 8 of chunk 0; word 70,000 (65,536 + 4,464) block 69, bit 48 of chunk 1.
  const auto chunk = [](size_t block, int bit) {
    std::vector<uint64_t> blocks(block + 1, 0);
    blocks[block] = uint64_t{1} << bit;
    std::vector<unsigned char> bytes(sizeof(uint64_t) * (blocks.size() + 1));
    const uint64_t count = blocks.size();
    std::memcpy(bytes.data(), &count, sizeof(count));
    std::memcpy(bytes.data() + sizeof(count), blocks.data(), sizeof(uint64_t) * blocks.size());
    return bytes;
  };
  checkpoint.state.emplace_back("ltm_marks.0", chunk(78, 8));
  checkpoint.state.emplace_back("ltm_marks.1", chunk(69, 48));
  database.WriteCheckpoint(checkpoint);

  Memory reloaded(DescriptorKind::kFloat, 2, Options());
  EXPECT_EQ(ReadCheckpoint(database, reloaded.dictionary()).words_referenced_by_ltm,
            (std::vector<WordId>{5000, 70000}));

  memory_.dictionary().MarkReferencedByLtm(5000);
  memory_.dictionary().MarkReferencedByLtm(70000);
  database.WriteCheckpoint(CheckpointWriter().Next(memory_, filter_, past_matches_, counters_));
  EXPECT_FALSE(database.ReadState("ltm_marks.0"));
  EXPECT_FALSE(database.ReadState("ltm_marks.1"));
  EXPECT_TRUE(database.ReadState("word_marks.1"));   // 5,000 / 4,096
  EXPECT_TRUE(database.ReadState("word_marks.17"));  // 70,000 / 4,096
  EXPECT_EQ(ReadCheckpoint(database, reloaded.dictionary()).words_referenced_by_ltm,
            (std::vector<WordId>{5000, 70000}));
}

TEST_F(CheckpointWriterTest, WhatIsWrittenReadsBackAsTheSameState) {
  testing::TempDir dir;
  LtmDatabase database(dir.File("map.db"), LtmDatabase::Mode::kCreate);
  AddChain(memory_, {{1, 2}, {2, 3}, {4}, {1, 4}});
  memory_.MoveStmOverflowToWm(2);
  memory_.dictionary().MarkReferencedByLtm(3);
  filter_.Reload({{1, 0.25}, {2, 0.5}}, 0.25);
  past_matches_ = {{1, 4}};
  counters_ = {11, 12, 4, 0.125};
  kept_last_.Retrieved({2}, 9);
  database.WriteCheckpoint(Next());
  kept_last_.Retrieved({1}, 12);
  memory_.ClearChanged();
  memory_.at(3).weight = 2;
  memory_.dictionary().MarkReferencedByLtm(1);
  database.WriteCheckpoint(Next());

  Memory reloaded_memory(DescriptorKind::kFloat, 2, Options());
  const ResumeState state = ReadCheckpoint(database, reloaded_memory.dictionary());
  EXPECT_EQ(state.counters.last_image, 11);
  EXPECT_EQ(state.counters.images_processed, 12);
  EXPECT_EQ(state.counters.newest_location, 4);
  EXPECT_EQ(state.counters.previous_hypothesis_value, 0.125);
  EXPECT_EQ(state.next_location_id, 5);
  EXPECT_EQ(state.next_word_id, 5);
  EXPECT_EQ(state.stm, (std::deque<LocationId>{3, 4}));
  EXPECT_EQ(state.words, (std::vector<WordId>{1, 2, 3, 4}));
  EXPECT_EQ(state.words_referenced_by_ltm, (std::vector<WordId>{1, 3}));
  ASSERT_EQ(state.locations.size(), 4u);
  EXPECT_EQ(state.locations.at(3).weight, 2);
  EXPECT_EQ(state.locations.at(4).signature.words, (std::vector<WordId>{1, 4}));
  EXPECT_EQ(state.posterior, (IdMap<double>{{1, 0.25}, {2, 0.5}}));
  EXPECT_EQ(state.virtual_place, 0.25);
  ASSERT_EQ(state.past_matches.size(), 1u);
  EXPECT_EQ(state.past_matches[0].matcher, 4);
  EXPECT_EQ(state.kept_last, (std::map<LocationId, long long>{{1, 12}, {2, 9}}));
  EXPECT_EQ(state.index.point_count, 4u);
  EXPECT_EQ(state.index.point_words, (std::vector<WordId>{1, 2, 3, 4}));

  // The reloaded dictionary finds the words where the original does.
  reloaded_memory.dictionary().Reload(state.words, state.index, state.words_referenced_by_ltm,
                                      state.next_word_id);
  reloaded_memory.Reload(state.locations, state.stm, state.next_location_id);
  const cv::Mat probe = (cv::Mat_<float>(2, 2) << 301, 0, 99, 0);
  EXPECT_EQ(reloaded_memory.dictionary().Match(probe), memory_.dictionary().Match(probe));
  EXPECT_EQ(reloaded_memory.dictionary().References(4), memory_.dictionary().References(4));
  EXPECT_EQ(reloaded_memory.working_memory(), memory_.working_memory());
}

// After a rebuild every point is written again, but a word's descriptor only once (issue 9: a
// rebuild at 160,000 words rewrote 40 MB inside the iteration).
TEST(CheckpointIndexTest, RebuildRewritesPointsButNotTheDescriptorsTheFileHolds) {
  DictionaryOptions options = SmallDictionaryOptions();
  options.rebuild_fraction = 1.0;
  options.rebuild_delay = 0;  // rebuilt inside the Add that crosses the fraction
  Memory memory(DescriptorKind::kFloat, 2, options);
  BayesFilter filter{FilterOptions()};
  CheckpointWriter writer;
  testing::TempDir dir;
  LtmDatabase database(dir.File("map.db"), LtmDatabase::Mode::kCreate);
  AddChain(memory, {{1, 2}, {3}});                // builds: {1}, then 2 and 3 added one by one
  testing::AddWords(memory.dictionary(), {100});  // a word no location holds
  const int builds = memory.dictionary().index().build_count();
  database.WriteCheckpoint(writer.Next(memory, filter, {}, {}));
  memory.dictionary().Remove(100);  // its descriptor is deleted after the rebuild
  WordId word = 4;
  while (memory.dictionary().index().build_count() == builds) AddChain(memory, {{word++}});
  const CheckpointData rebuilt = writer.Next(memory, filter, {}, {});
  ASSERT_TRUE(rebuilt.reset_index);
  EXPECT_EQ(rebuilt.first_index_point, 0);
  EXPECT_EQ(rebuilt.index_words.size(), memory.dictionary().size());
  for (const auto& [word, descriptor] : rebuilt.index_descriptors) {  // only the new words'
    EXPECT_GT(word, 3);
    EXPECT_FALSE(descriptor.empty());
  }
  EXPECT_EQ(rebuilt.index_descriptors.size(), memory.dictionary().size() - 3);
  EXPECT_EQ(rebuilt.forgotten_descriptors, (std::vector<WordId>{100}));
  database.WriteCheckpoint(rebuilt);
  Memory reloaded(DescriptorKind::kFloat, 2, options);
  const ResumeState state = ReadCheckpoint(database, reloaded.dictionary());
  EXPECT_TRUE(state.index.point_words.end() ==
              std::find(state.index.point_words.begin(), state.index.point_words.end(), 100));
  ASSERT_EQ(state.index.point_words.size(), memory.dictionary().size());
  for (size_t point = 0; point < state.index.point_words.size(); ++point) {
    const cv::Mat expected = memory.dictionary().Descriptor(state.index.point_words[point]);
    EXPECT_EQ(cv::norm(state.index.descriptors.row(static_cast<int>(point)), expected, cv::NORM_L1),
              0.0)
        << "point " << point;
  }
}

// A background build's snapshot words are written once; its age, which changes at every
// insertion, apart. Read back, the checkpoint holds both.
TEST(CheckpointIndexTest, PendingBuildWordsAreWrittenOncePerBuild) {
  DictionaryOptions options = SmallDictionaryOptions();
  options.rebuild_fraction = 1.0;
  options.rebuild_delay = 100;  // the build stays pending through the test
  Memory memory(DescriptorKind::kFloat, 2, options);
  BayesFilter filter{FilterOptions()};
  CheckpointWriter writer;
  testing::TempDir dir;
  LtmDatabase database(dir.File("map.db"), LtmDatabase::Mode::kCreate);
  AddChain(memory, {{1}, {2}, {3}});  // 1 built, 2 added (1 change), 3 added (2 > 1): pending
  ASSERT_TRUE(memory.dictionary().index().History(0).pending);
  const auto keys = [](const CheckpointData& checkpoint) {
    std::set<std::string> written;
    for (const auto& [key, value] : checkpoint.state) written.insert(key);
    return written;
  };
  const CheckpointData first = writer.Next(memory, filter, {}, {});
  EXPECT_TRUE(keys(first).count("index_pending_words"));
  database.WriteCheckpoint(first);
  AddChain(memory, {{4}});  // one more insertion: the age changes, the words do not
  const CheckpointData second = writer.Next(memory, filter, {}, {});
  EXPECT_TRUE(keys(second).count("index_pending"));
  EXPECT_FALSE(keys(second).count("index_pending_words"));
  database.WriteCheckpoint(second);
  Memory reloaded(DescriptorKind::kFloat, 2, options);
  const ResumeState state = ReadCheckpoint(database, reloaded.dictionary());
  EXPECT_TRUE(state.index.pending);
  EXPECT_EQ(state.index.pending_age, 1);
  EXPECT_EQ(state.index.pending_words, memory.dictionary().index().PendingWords());
}

TEST_F(CheckpointWriterTest, MapWithoutCheckpointOrWithADamagedOneIsRefused) {
  // Why `map` cannot be resumed (empty when it can).
  const auto refusal = [this](LtmDatabase& map) -> std::string {
    try {
      ReadCheckpoint(map, memory_.dictionary());
      return "";
    } catch (const DatabaseError& error) {
      return error.what();
    }
  };
  testing::TempDir dir;
  LtmDatabase database(dir.File("map.db"), LtmDatabase::Mode::kCreate);
  EXPECT_NE(refusal(database).find("no resume checkpoint"), std::string::npos) << refusal(database);
  AddChain(memory_, {{1, 2}});
  CheckpointData checkpoint = Next();
  checkpoint.locations[0].second.resize(5);  // a truncated location
  database.WriteCheckpoint(checkpoint);
  EXPECT_NE(refusal(database).find("damaged"), std::string::npos) << refusal(database);

  // A chunk of LTM marks cut short.
  LtmDatabase marked(dir.File("marked.db"), LtmDatabase::Mode::kCreate);
  memory_.dictionary().MarkReferencedByLtm(1);
  CheckpointData with_marks = CheckpointWriter().Next(memory_, filter_, past_matches_, counters_);
  bool cut = false;
  for (auto& [key, value] : with_marks.state) {
    if (key != "word_marks.0") continue;
    value.resize(value.size() - 3);
    cut = true;
  }
  ASSERT_TRUE(cut);
  marked.WriteCheckpoint(with_marks);
  EXPECT_NE(refusal(marked).find("damaged"), std::string::npos) << refusal(marked);
}

}  // namespace
}  // namespace memloop
