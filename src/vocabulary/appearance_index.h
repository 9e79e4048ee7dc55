// Appearance retrieval's index (memloop, beyond the paper; docs/design.md, "Retrieval by
// appearance"). Retrieval (III-E) brings back only the neighbours of the highest hypothesis, which
// is in WM: a place whose whole neighbourhood left WM can never come back that way. This index
// finds the LTM locations that look like the current image instead.
//
// The dictionary's words cannot serve: those of LTM-only locations have left it, and a new image
// of an old place makes new words. So every location is also described over a small vocabulary
// that never changes: the dictionary's first `vocabulary_size` words, copied as they are created.
// A description is the set of vocabulary entries nearest to the location's features; an
// inverted index over the descriptions scores locations by the idf-weighted entries they share
// with the image. RAM: about 4 bytes per distinct entry of a location (~1 KB each).
#pragma once

#include <cstdint>
#include <future>
#include <memory>
#include <opencv2/core.hpp>
#include <unordered_map>
#include <vector>

#include "memloop/options.h"
#include "memloop/types.h"
#include "vocabulary/word_index.h"

namespace memloop {

using AppearanceEntry = uint32_t;
// Sorted, distinct vocabulary entries.
using Appearance = std::vector<AppearanceEntry>;

struct AppearanceMatch {
  LocationId id = kNoLocation;
  double score = 0;  // idf-weighted shared entries over sqrt(|query| |location|)
  // How far the best score stands above the scores of all candidates (untouched ones score 0):
  // (score - mean) / standard deviation. 0 when there is no candidate.
  double z = 0;
};

class AppearanceIndex {
 public:
  // `index_options` configures the search over the vocabulary (as the dictionary's).
  // `max_postings` bounds a search's work (Best); 0: every entry of the query is summed.
  AppearanceIndex(DescriptorKind kind, int descriptor_dim, int vocabulary_size,
                  const DictionaryOptions& index_options, size_t max_postings = 0);

  // New words of the dictionary, in creation order: the first `vocabulary_size` become the
  // vocabulary, which is then frozen. Returns how many rows joined it (the first ones).
  int CollectWords(const std::vector<WordId>& ids, const cv::Mat& descriptors);
  bool frozen() const { return frozen_; }
  int vocabulary_size() const { return vocabulary_size_; }

  // The description of features whose descriptor rows are `descriptors`, row i quantized by the
  // dictionary to `words[i]` (kNoWord: none). Once the vocabulary is frozen each row goes to its
  // nearest entry; before, only rows whose word is an entry count (an entry is its word). The
  // entries' search index is built in the background when the vocabulary freezes (32,768 entries
  // took 85-100 ms inside one iteration), and used for features whose newest word is
  // kSwitchWords past the vocabulary's last (waited for then, if not built yet), or that have
  // no words (localization): the same features get the same description however fast the build
  // and on a resumed map, whose word ids say the same.
  Appearance Describe(const std::vector<WordId>& words, const cv::Mat& descriptors) const;

  // Every location's description is kept (Add, replacing; Erase); only those entered are
  // searched (the detector enters the locations of LTM). Add throws Error for an entry out of the
  // vocabulary (a damaged map).
  void Add(LocationId id, Appearance appearance);
  void Erase(LocationId id);
  const Appearance* Find(LocationId id) const;
  size_t size() const { return appearances_.size(); }
  // Enter and Leave take O(entries of the location) amortized, whatever the number searched: a
  // location that leaves stays in the postings as a tombstone (skipped by Best, not counted in
  // the idf), revived if it enters again; a posting is compacted once its tombstones outnumber
  // its holders. Answers depend only on which locations are searched, not on that history.
  void Enter(LocationId id);
  void Leave(LocationId id);
  bool Searched(LocationId id) const {
    const auto slot = static_cast<size_t>(id);
    return slot / 64 < searched_bits_.size() && ((searched_bits_[slot / 64] >> (slot % 64)) & 1);
  }
  size_t searched_size() const { return searched_count_; }

  // The searched location that scores best against `query` (ties: the oldest), and how far it
  // stands out. Entries held by more than half the searched locations are ignored. With
  // `max_postings`, the query's rarest entries are summed first (fewest holders, then lowest
  // entry), and no more once their postings would pass it: the search's time stops growing with
  // LTM (bench/appearance_search_benchmark.cc), and the entries left out are the most common,
  // which tell places apart least.
  AppearanceMatch Best(const Appearance& query) const;
  // The score Best gives, or would give were it searched, the described location `id` against
  // `query` (0 when `id` is not described).
  double Score(const Appearance& query, LocationId id) const;

  // The vocabulary collected so far: its words and descriptor rows, in entry order.
  const std::vector<WordId>& vocabulary_words() const { return vocabulary_words_; }
  const cv::Mat& vocabulary() const { return vocabulary_; }
  // Resuming: the vocabulary as collected (frozen when complete), and no description. Throws
  // Error when the rows do not fit the words or the features.
  void Reload(const std::vector<WordId>& words, const cv::Mat& rows);

 private:
  // Stops collecting; the search index is built in the background (Reload waits for it).
  void Freeze();
  bool UseSearch(const std::vector<WordId>& words) const;
  void SetSearched(LocationId id, bool searched);
  // Whether `id`, not searched, is still in `entry`'s posting (a tombstone).
  bool Tombstone(LocationId id, AppearanceEntry entry) const;
  // Removes `id`'s tombstones from the postings of its description (before it changes).
  void Purge(LocationId id);
  // The entries of `query` Best sums (see there), with their idf over `extra` more searched
  // locations than there are (Score: one that is not searched, counted as if it were).
  std::vector<std::pair<AppearanceEntry, double>> SummedEntries(const Appearance& query,
                                                                size_t extra) const;
  // Calls visit(id, shared weight) for each location in the postings of `summed`'s entries, in
  // id order, its weight summed in `summed`'s order.
  template <typename Visit>
  void SumPostings(const std::vector<std::pair<AppearanceEntry, double>>& summed,
                   Visit&& visit) const;

  DescriptorKind kind_;
  int descriptor_dim_;
  int vocabulary_size_;
  DictionaryOptions index_options_;
  size_t max_postings_;
  std::vector<WordId> vocabulary_words_;
  cv::Mat vocabulary_;  // one row per entry
  std::unordered_map<WordId, AppearanceEntry> entry_of_word_;
  bool frozen_ = false;
  static constexpr WordId kSwitchWords = 20000;  // about 50-100 images of new words
  WordId switch_word_ = 0;
  mutable std::unique_ptr<WordIndex> search_;  // over vocabulary_, once built
  mutable std::future<std::unique_ptr<WordIndex>> building_;

  std::unordered_map<LocationId, Appearance> appearances_;
  std::vector<uint64_t> searched_bits_;  // by location id
  size_t searched_count_ = 0;
  // entry -> locations holding it, by id: the searched ones and tombstones of those that left
  std::vector<std::vector<LocationId>> postings_;
  std::vector<uint32_t> holders_;  // entry -> searched locations holding it
  // Where the tombstones are without a search: a location that left at Leave number t (1, 2, ...)
  // is still in an entry's posting unless that posting was compacted at t or later. 0: in none.
  uint64_t leaves_ = 0;
  std::vector<uint64_t> left_at_;             // by location id
  std::vector<uint64_t> compacted_at_;        // by entry
  mutable std::vector<double> block_scores_;  // SumPostings: a block of ids, zero between
  mutable std::vector<uint64_t> touched_;     // the block's ids with a score, one bit each
  std::vector<uint32_t> sizes_;               // by location id: its description's size
};

}  // namespace memloop
