// The incremental visual dictionary (paper III-A): the words of the locations in STM and WM, a
// kd-forest over their descriptors for quantization, and each word's references to the
// locations that contain it (the inverted index used by the likelihood, eq. 3).
#pragma once

#include <algorithm>
#include <array>
#include <deque>
#include <functional>
#include <map>
#include <opencv2/core.hpp>
#include <optional>
#include <set>
#include <unordered_map>
#include <vector>

#include "memloop/options.h"
#include "memloop/types.h"
#include "vocabulary/word_bitset.h"
#include "vocabulary/word_index.h"

namespace memloop {

class Dictionary {
 public:
  // Throws Error when `kind` and `descriptor_dim` are not a valid pair.
  Dictionary(DescriptorKind kind, int descriptor_dim, const DictionaryOptions& options);

  // For each row, the nearest word when it passes the nearest-neighbour distance ratio test
  // (d1 < nndr_ratio * d2, true distances), else kNoWord. A lone word passes. Throws Error when
  // the descriptors are not of the dictionary's kind and size (one map, one feature type).
  // With a gate (SearchOptions), only the first rows may be matched: the answer has one entry
  // per row matched.
  std::vector<WordId> Match(const cv::Mat& descriptors, const SearchOptions& search = {}) const;
  // The search behind Match: each row's two nearest words, with their distances.
  std::vector<std::array<Neighbour, 2>> Nearest(const cv::Mat& descriptors,
                                                const SearchOptions& search = {}) const;
  // Match's answer for one row of Nearest: the ratio test.
  WordId MatchOf(const std::array<Neighbour, 2>& nearest) const;

  // Words join the dictionary in order (new ones, and old ones added back): JoinMark() counts
  // them. For rows whose search (Nearest) was made at `mark`, with the nearest and second
  // distances it found (infinity for none), Match's answer now, counting the words that joined
  // since (compared with each row exhaustively; words that left since are not discounted). Nullopt
  // when the dictionary no longer remembers what joined at `mark` (kJoinedRemembered).
  long long JoinMark() const { return join_count_; }
  std::optional<std::vector<WordId>> MatchSince(const cv::Mat& descriptors,
                                                const std::vector<std::pair<float, float>>& found,
                                                long long mark) const;
  static constexpr size_t kJoinedRemembered = size_t{1} << 16;

  // Quantization of a new signature: Match(), then every row that matched nothing becomes a
  // new word. New words are added after all rows are matched, so rows of one image never match
  // each other. `new_word_count` receives how many words were created. With a gate in `search`,
  // the rows the search reached (the first ones); the answer has one word per row quantized.
  // `search_ms` receives the search's time (the rest is adding the new words to the forest).
  std::vector<WordId> Quantize(const cv::Mat& descriptors, int* new_word_count,
                               const SearchOptions& search = {}, double* search_ms = nullptr);

  // Adds words under given ids (words retrieved from LTM keep theirs).
  void Add(const std::vector<WordId>& ids, const cv::Mat& descriptors);
  // Removes a word; it must have no reference left.
  void Remove(WordId id);

  bool Contains(WordId id) const { return words_.count(id) > 0; }
  // Every word's id, sorted.
  std::vector<WordId> Ids() const;
  // The word's descriptor as a 1-row matrix (a copy).
  cv::Mat Descriptor(WordId id) const;
  size_t size() const { return words_.size(); }
  // WordIndex::SetSwapWait: how long a quantization may wait for a due background rebuild.
  void SetSwapWait(std::function<double()> budget_ms) { index_->SetSwapWait(std::move(budget_ms)); }
  int late_steps() const { return index_->late_steps(); }  // WordIndex::late_steps
  int descriptor_dim() const { return index_->dim(); }
  int search_threads() const { return std::max(1, options_.search_threads); }
  DescriptorKind descriptor_kind() const { return index_->kind(); }
  int descriptor_cv_type() const { return index_->cv_type(); }
  const WordIndex& index() const { return *index_; }

  // References: how many times each location's signature holds the word.
  void AddReference(WordId id, LocationId location);
  // Drops all references of `location` to the word. True when the word has none left.
  bool RemoveReferences(WordId id, LocationId location);
  // location -> occurrences; empty map for unknown words.
  const std::map<LocationId, int>& References(WordId id) const;

  // A word is marked when a location of LTM refers to it: when it leaves the dictionary it must
  // then be kept in LTM (paper III-F), otherwise it can be forgotten.
  void MarkReferencedByLtm(WordId id);
  bool IsReferencedByLtm(WordId id) const;

  WordId next_word_id() const { return next_word_id_; }
  // The marks as a bitset (a scan of every word at each checkpoint took a third of the run's time
  // at 140,000 words), stored by chunks; and the chunks whose marks changed since
  // ClearChangedMarks().
  const WordBitset& ltm_marks() const { return referenced_by_ltm_; }
  const std::set<size_t>& changed_mark_chunks() const { return changed_mark_chunks_; }
  void ClearChangedMarks() { changed_mark_chunks_.clear(); }

  // Resuming a map: the words `ids` (no references yet: Memory::Reload adds them), the index as
  // `history` left it, the LTM marks and the next id to give. Throws Error when they disagree.
  void Reload(const std::vector<WordId>& ids, const IndexHistory& history,
              const std::vector<WordId>& referenced_by_ltm, WordId next_word_id);

 private:
  struct Word {
    std::map<LocationId, int> references;
  };

  DictionaryOptions options_;
  void CheckDescriptors(const cv::Mat& descriptors) const;

  std::unique_ptr<WordIndex> index_;
  std::unordered_map<WordId, Word> words_;
  std::set<size_t> changed_mark_chunks_;
  WordBitset referenced_by_ltm_;  // marked words, a subset of words_
  WordId next_word_id_ = 1;
  long long join_count_ = 0;
  std::deque<WordId> joined_;  // the last kJoinedRemembered words to join, the oldest first
};

}  // namespace memloop
