// A randomized kd-tree forest (FLANN KDTreeIndex) over the words of the dictionary, updated
// incrementally: points are added to and removed from the existing trees, and the forest is
// rebuilt only when enough has changed since the last build (paper III-A; III-F notes that
// rebuilding the dictionary is the most expensive step).
#pragma once

#include <array>
#include <deque>
#include <memory>
#include <opencv2/core.hpp>
#include <unordered_map>
#include <vector>

#include "flann_deterministic.h"
#include "memloop/options.h"
#include "memloop/types.h"

namespace memloop {

struct Neighbour {
  WordId word = kNoWord;
  float distance = 0;  // true L2 distance (not squared)
};

class KdForest {
 public:
  KdForest(int dim, const DictionaryOptions& options);

  // Copies the rows of `descriptors` (CV_32F, dim columns) as points named `ids`.
  void Add(const std::vector<WordId>& ids, const cv::Mat& descriptors);
  void Remove(WordId id);
  bool Contains(WordId id) const { return point_of_word_.count(id) > 0; }
  const float* Descriptor(WordId id) const;
  size_t size() const { return point_of_word_.size(); }
  int dim() const { return dim_; }

  // The two nearest points of each row of `queries` (fewer when the forest holds fewer).
  std::vector<std::array<Neighbour, 2>> Search(const cv::Mat& queries) const;

  // Number of full builds so far (the benchmark and tests watch it).
  int build_count() const { return build_count_; }

 private:
  using Index = flann::Index<flann::L2<float>>;
  void Rebuild();

  int dim_;
  DictionaryOptions options_;
  std::unique_ptr<Index> index_;
  // FLANN keeps pointers into the points it is given: they live here until the next rebuild,
  // which compacts the live points into one new buffer.
  std::deque<std::vector<float>> buffers_;
  std::unordered_map<WordId, size_t> point_of_word_;
  std::unordered_map<size_t, WordId> word_of_point_;
  size_t next_point_ = 0;  // FLANN's name for the next point added
  size_t size_at_build_ = 0;
  size_t changes_since_build_ = 0;
  int build_count_ = 0;
};

}  // namespace memloop
