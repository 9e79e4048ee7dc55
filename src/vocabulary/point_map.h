// Which point of a FLANN index holds each live word, and which word each point holds. Word ids
// and points are consecutive integers, so both are arrays: listing the live words in id order
// (what a full build of the forest starts from) is then one pass; with hash maps it was a sort,
// 55-70 ms inside an iteration at 600,000-900,000 words (issue 9). The word -> point array is
// kept by pages of kPageSize ids, each allocated while it holds a live word: ids are not reused
// and a long run issues ~160 an image (31.9 million over 200,000 images), so one flat array grew
// with the run's length, 4 bytes an id ever issued (issue 39: 128 MB at 200,000 images, twice
// that while a rebuild's map exists beside it); a page costs 1 KB while it holds a live word,
// and 8 bytes for every kPageSize ids ever issued.
#pragma once

#include <array>
#include <cassert>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include "memloop/types.h"

namespace memloop {

class PointMap {
 public:
  static constexpr size_t kNoPoint = static_cast<size_t>(-1);

  // The live word's point, kNoPoint when `word` is not live.
  size_t PointOf(WordId word) const {
    if (word <= kNoWord) return kNoPoint;
    const size_t page = static_cast<size_t>(word) / kPageSize;
    if (page >= pages_.size() || pages_[page] == nullptr) return kNoPoint;
    const uint32_t point = pages_[page]->points[static_cast<size_t>(word) % kPageSize];
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
    const size_t page = static_cast<size_t>(word) / kPageSize;
    if (page >= pages_.size()) pages_.resize(page + 1);
    if (pages_[page] == nullptr) pages_[page] = std::make_unique<Page>();
    if (point >= word_of_point_.size()) word_of_point_.resize(point + 1, kNoWord);
    pages_[page]->points[static_cast<size_t>(word) % kPageSize] = static_cast<uint32_t>(point);
    ++pages_[page]->live;
    word_of_point_[point] = word;
    ++live_;
  }

  // `word` is no longer live (nothing when it was not). Its page goes with its last live word.
  void Erase(WordId word) {
    const size_t point = PointOf(word);
    if (point == kNoPoint) return;
    std::unique_ptr<Page>& page = pages_[static_cast<size_t>(word) / kPageSize];
    page->points[static_cast<size_t>(word) % kPageSize] = kNone;
    if (--page->live == 0) page.reset();
    word_of_point_[point] = kNoWord;
    --live_;
  }

  void Clear() { *this = PointMap(); }
  // Room for word ids below `words` and points below `points`, so that Set does not reallocate
  // its arrays (a page for a word id not yet held is still allocated).
  void Reserve(size_t words, size_t points) {
    pages_.reserve((words + kPageSize - 1) / kPageSize);
    word_of_point_.reserve(points);
  }
  // Pages allocated (tests: memory follows the live words, not the ids issued).
  size_t pages() const {
    size_t count = 0;
    for (const auto& page : pages_) count += page != nullptr;
    return count;
  }

  // Calls visit(word, point) for each live word, in increasing word id.
  template <typename Visit>
  void ForEachLive(Visit visit) const {
    for (size_t page = 0; page < pages_.size(); ++page) {
      if (pages_[page] == nullptr) continue;
      const auto& points = pages_[page]->points;
      for (size_t offset = 0; offset < kPageSize; ++offset) {
        if (points[offset] != kNone) {
          visit(static_cast<WordId>(page * kPageSize + offset), size_t{points[offset]});
        }
      }
    }
  }

  static constexpr size_t kPageSize = 256;

 private:
  static constexpr uint32_t kNone = UINT32_MAX;
  struct Page {
    Page() { points.fill(kNone); }
    std::array<uint32_t, kPageSize> points;  // by word id % kPageSize
    size_t live = 0;
  };
  std::vector<std::unique_ptr<Page>> pages_;  // by word id / kPageSize; null: no live word
  std::vector<WordId> word_of_point_;         // by point
  size_t live_ = 0;
};

}  // namespace memloop
