#include "kd_forest.h"

#include <algorithm>
#include <cassert>
#include <cmath>

namespace memloop {

KdForest::KdForest(int dim, const DictionaryOptions& options) : dim_(dim), options_(options) {}

void KdForest::Add(const std::vector<WordId>& ids, const cv::Mat& descriptors) {
  assert(descriptors.type() == CV_32F && descriptors.cols == dim_);
  assert(static_cast<int>(ids.size()) == descriptors.rows);
  if (ids.empty()) return;
  buffers_.emplace_back(ids.size() * dim_);
  std::vector<float>& buffer = buffers_.back();
  for (int row = 0; row < descriptors.rows; ++row) {
    std::copy_n(descriptors.ptr<float>(row), dim_, buffer.data() + row * dim_);
  }
  flann::Matrix<float> points(buffer.data(), ids.size(), dim_);
  const size_t first_point = next_point_;
  next_point_ += ids.size();
  if (index_) {
    index_->addPoints(points, /*rebuild_threshold=*/1.0f);  // <= 1: never rebuild by itself
  } else {
    flann::seed_random(options_.seed);
    index_ = std::make_unique<Index>(points, flann::KDTreeIndexParams(options_.kd_trees));
    index_->buildIndex();
    ++build_count_;
  }
  // FLANN names points by insertion order, never reusing a name.
  for (size_t i = 0; i < ids.size(); ++i) {
    point_of_word_[ids[i]] = first_point + i;
    word_of_point_[first_point + i] = ids[i];
  }
  changes_since_build_ += ids.size();
  if (changes_since_build_ > options_.rebuild_fraction * std::max<size_t>(size_at_build_, 1)) {
    Rebuild();
  }
}

void KdForest::Remove(WordId id) {
  const auto found = point_of_word_.find(id);
  if (found == point_of_word_.end()) return;
  index_->removePoint(found->second);
  word_of_point_.erase(found->second);
  point_of_word_.erase(found);
  ++changes_since_build_;
}

const float* KdForest::Descriptor(WordId id) const {
  const auto found = point_of_word_.find(id);
  return found == point_of_word_.end() ? nullptr : index_->getPoint(found->second);
}

void KdForest::Rebuild() {
  // Live points in word order, so the same history gives the same forest.
  std::vector<WordId> ids;
  ids.reserve(point_of_word_.size());
  for (const auto& entry : point_of_word_) ids.push_back(entry.first);
  std::sort(ids.begin(), ids.end());
  std::vector<float> buffer(ids.size() * dim_);
  for (size_t i = 0; i < ids.size(); ++i) {
    std::copy_n(Descriptor(ids[i]), dim_, buffer.data() + i * dim_);
  }
  index_.reset();
  buffers_.clear();
  point_of_word_.clear();
  word_of_point_.clear();
  size_at_build_ = ids.size();
  next_point_ = ids.size();
  changes_since_build_ = 0;
  if (ids.empty()) return;
  buffers_.push_back(std::move(buffer));
  flann::Matrix<float> points(buffers_.back().data(), ids.size(), dim_);
  flann::seed_random(options_.seed);
  index_ = std::make_unique<Index>(points, flann::KDTreeIndexParams(options_.kd_trees));
  index_->buildIndex();
  ++build_count_;
  for (size_t i = 0; i < ids.size(); ++i) {
    point_of_word_[ids[i]] = i;
    word_of_point_[i] = ids[i];
  }
}

std::vector<std::array<Neighbour, 2>> KdForest::Search(const cv::Mat& queries) const {
  assert(queries.type() == CV_32F && queries.cols == dim_);
  std::vector<std::array<Neighbour, 2>> result(queries.rows);
  const size_t k = std::min<size_t>(2, size());
  if (k == 0 || queries.rows == 0) return result;
  cv::Mat contiguous = queries.isContinuous() ? queries : queries.clone();
  flann::Matrix<float> query_matrix(contiguous.ptr<float>(), queries.rows, dim_);
  std::vector<size_t> indices(queries.rows * k);
  std::vector<float> squared(queries.rows * k);
  flann::Matrix<size_t> index_matrix(indices.data(), queries.rows, k);
  flann::Matrix<float> distance_matrix(squared.data(), queries.rows, k);
  flann::SearchParams params(options_.kd_checks);
  params.cores = 1;  // one thread: repeatable and predictable per-image time
  index_->knnSearch(query_matrix, index_matrix, distance_matrix, k, params);
  for (int row = 0; row < queries.rows; ++row) {
    for (size_t n = 0; n < k; ++n) {
      const auto word = word_of_point_.find(index_matrix[row][n]);
      if (word == word_of_point_.end()) continue;  // search found fewer than k
      result[row][n] = {word->second, std::sqrt(std::max(0.0f, distance_matrix[row][n]))};
    }
  }
  return result;
}

}  // namespace memloop
