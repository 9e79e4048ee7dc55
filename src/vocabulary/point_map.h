// Which point of a FLANN index holds each live word, and which word each point holds: both as
// dense arrays, since word ids and points are consecutive integers (4 bytes per word id ever
// issued, ids are not reused, and per point since the last build). Listing the live words
// in id order (what a full build of the forest starts from) is then one pass over an array; with
// hash maps it was a sort, 55-70 ms inside an iteration at 600,000-900,000 words (issue 9).
#pragma once

#include <cassert>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "memloop/types.h"

namespace memloop {

class PointMap {
 public:
  static constexpr size_t kNoPoint = static_cast<size_t>(-1);

  // The live word's point, kNoPoint when `word` is not live.
  size_t PointOf(WordId word) const {
    if (word <= kNoWord || static_cast<size_t>(word) >= point_of_word_.size()) return kNoPoint;
    const uint32_t point = point_of_word_[word];
    return point == kNone ? kNoPoint : point;
  }
  // The word held by `point`, kNoWord when the point was removed or is unknown.
  WordId WordOf(size_t point) const {
    return point < word_of_point_.size() ? word_of_point_[point] : kNoWord;
  }
  bool Contains(WordId word) const { return PointOf(word) != kNoPoint; }
  size_t size() const { return live_; }

  // `word` is now at `point` (leaving the point it had); `point` holds no other live word.
  void Set(WordId word, size_t point) {
    Erase(word);
    assert(word > kNoWord && point < kNone && WordOf(point) == kNoWord);
    if (static_cast<size_t>(word) >= point_of_word_.size()) point_of_word_.resize(word + 1, kNone);
    if (point >= word_of_point_.size()) word_of_point_.resize(point + 1, kNoWord);
    point_of_word_[word] = static_cast<uint32_t>(point);
    word_of_point_[point] = word;
    ++live_;
  }

  // `word` is no longer live (nothing when it was not).
  void Erase(WordId word) {
    const size_t point = PointOf(word);
    if (point == kNoPoint) return;
    point_of_word_[word] = kNone;
    word_of_point_[point] = kNoWord;
    --live_;
  }

  void Clear() { *this = PointMap(); }
  // Room for word ids below `words` and points below `points`, so that Set does not reallocate.
  void Reserve(size_t words, size_t points) {
    point_of_word_.reserve(words);
    word_of_point_.reserve(points);
  }

  // Calls visit(word, point) for each live word, in increasing word id.
  template <typename Visit>
  void ForEachLive(Visit visit) const {
    for (size_t word = 1; word < point_of_word_.size(); ++word) {
      if (point_of_word_[word] != kNone) visit(static_cast<WordId>(word), point_of_word_[word]);
    }
  }

 private:
  static constexpr uint32_t kNone = UINT32_MAX;
  std::vector<uint32_t> point_of_word_;  // by word id
  std::vector<WordId> word_of_point_;    // by point
  size_t live_ = 0;
};

}  // namespace memloop
