// The history of a dictionary's index since its last full build, and what a replay
// (WordIndex::Replay) checks and looks up in it.
#pragma once

#include <opencv2/core.hpp>
#include <unordered_map>
#include <vector>

#include "memloop/types.h"

namespace memloop {

// What the index was given since its last full build, enough to rebuild it exactly: FLANN's trees
// depend on the order points came in (and on points removed since), not only on the live words.
// Resuming a map (checkpoint.h) stores it and replays it.
struct IndexHistory {
  int build_count = 0;
  size_t size_at_build = 0;
  size_t changes_since_build = 0;
  std::vector<size_t> batch_starts;  // first point of each Add since the build; [0] is the build
  size_t point_count = 0;            // points since the build, removed ones included
  size_t first_point = 0;            // point_words and descriptors start at this point
  std::vector<WordId> point_words;
  cv::Mat descriptors;  // one row per point from first_point
  // A full build running in the background (DictionaryOptions::rebuild_delay): the live words
  // when it started (sorted: its points; only in a complete history), point_count then, and the
  // insertions since.
  bool pending = false;
  std::vector<WordId> pending_words;
  size_t pending_point = 0;
  int pending_age = 0;
};

// Throws Error unless `history` is whole and consistent, for points of `dim` columns of OpenCV
// type `cv_type`: it starts at point 0, has a word and a descriptor for each point, batches that
// start in order within it, and a pending build within it (its words sorted).
void CheckIndexHistory(const IndexHistory& history, int dim, int cv_type);

// Each word's latest point in the history, and its latest before the pending build's snapshot
// (empty without a pending build): which point a replay keeps for a live word, and which
// descriptor the pending build was started from.
struct LatestPoints {
  std::unordered_map<WordId, size_t> overall;
  std::unordered_map<WordId, size_t> before_pending;
};
LatestPoints LatestPointsOf(const IndexHistory& history);

}  // namespace memloop
