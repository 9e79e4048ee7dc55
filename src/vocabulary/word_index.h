// The search structure behind the dictionary (paper III-A): the words' descriptors, updated
// incrementally, answering "which two words are nearest to this descriptor". Float descriptors
// (SURF, SIFT) use a randomized kd-tree forest with true L2 distances; binary ones (ORB) use
// locality-sensitive hashing with Hamming distances. Both are FLANN's (flann_word_index.cc).
#pragma once

#include <array>
#include <functional>
#include <memory>
#include <opencv2/core.hpp>
#include <vector>

#include "memloop/feature_extractor.h"
#include "memloop/options.h"
#include "memloop/types.h"
#include "vocabulary/index_history.h"

namespace memloop {

// Between chunks of a search: whether to search more rows, given the rows taken so far.
using SearchGate = std::function<bool(size_t rows_taken)>;

// How a search goes (WordIndex::Search); the default: every row, on the search's threads.
struct SearchOptions {
  // Rows are searched in chunks, taken in order while the gate says so (WorkTeam::Gate): the
  // answer then holds the first rows only, each the same as without a gate.
  SearchGate gate;
  // On the calling thread alone, without the search's other threads (a search beside another
  // one: searches only read the index).
  bool caller_only = false;
  // Leaves visited (FLANN "checks"); 0: DictionaryOptions::kd_checks.
  int checks = 0;
};

struct Neighbour {
  WordId word = kNoWord;
  float distance = 0;  // true L2 distance (not squared), or Hamming distance in bits
};

class WordIndex {
 public:
  // Rows per chunk of a search (its threads take chunks; a gate is asked between them): ~0.5 ms
  // of work at a few hundred thousand words, large enough that taking a chunk costs nothing
  // beside it.
  static constexpr size_t kSearchChunk = 16;

  virtual ~WordIndex() = default;
  // kDescriptorFloat: CV_32F rows of `dim` values; kBinary: CV_8U rows of `dim` bytes.
  static std::unique_ptr<WordIndex> Create(DescriptorKind kind, int dim,
                                           const DictionaryOptions& options);

  // Copies the rows of `descriptors` as points named `ids`. Points are added to the existing
  // index. When the points added and removed since the last build exceed rebuild_fraction of its
  // size then, a new index is built from the live words: in the background when rebuild_delay > 0,
  // replacing this one, brought up to date, rebuild_delay Adds later (with
  // rebuild_swap_when_ready, not waited for: at the first Add from then on at which it is built).
  virtual void Add(const std::vector<WordId>& ids, const cv::Mat& descriptors) = 0;
  virtual void Remove(WordId id) = 0;
  // With rebuild_swap_when_ready: how long (ms) an Add may wait for a background build that is
  // due but not done, asked at that moment (<= 0: not at all, the default).
  virtual void SetSwapWait(std::function<double()> budget_ms) { (void)budget_ms; }
  virtual bool Contains(WordId id) const = 0;
  // The word's descriptor as one row (a copy); empty when unknown.
  virtual cv::Mat Descriptor(WordId id) const = 0;
  virtual size_t size() const = 0;
  // The two nearest words of each row (kNoWord where fewer are found), as `options` say.
  virtual std::vector<std::array<Neighbour, 2>> Search(const cv::Mat& queries,
                                                       const SearchOptions& options = {}) const = 0;
  // Full builds so far.
  virtual int build_count() const = 0;
  // Adds at which a background build's swap was due but not done, and was not waited for (T_time
  // on): until it is done, searches use the old forest, where a run without T_time has the new.
  virtual int late_steps() const { return 0; }
  // The history since the last build, with the points from `from_point` on. Unless `complete`,
  // the points' descriptors and the pending build's words are left empty (PointDescriptor and
  // PendingWords give them): what a checkpoint needs at every image is small.
  virtual IndexHistory History(size_t from_point, bool complete = true) const = 0;
  // The words of the build running in the background (sorted), empty when none runs.
  virtual std::vector<WordId> PendingWords() const = 0;
  // The descriptor of point `point` of the history (removed points too), as one row (a copy).
  virtual cv::Mat PointDescriptor(size_t point) const = 0;
  // Rebuilds the index exactly as `history` (all points from 0) left it, with `live_words` (the
  // words not removed since) searchable. Throws Error when the history is inconsistent.
  virtual void Replay(const IndexHistory& history, const std::vector<WordId>& live_words) = 0;

  DescriptorKind kind() const { return kind_; }
  int dim() const { return dim_; }
  int cv_type() const { return kind_ == DescriptorKind::kFloat ? CV_32F : CV_8U; }

 protected:
  WordIndex(DescriptorKind kind, int dim) : kind_(kind), dim_(dim) {}

 private:
  DescriptorKind kind_;
  int dim_;
};

}  // namespace memloop
