#include "vocabulary/dictionary.h"

#include <algorithm>
#include <cassert>
#include <chrono>
#include <limits>
#include <opencv2/core.hpp>

#include "memloop/errors.h"

namespace memloop {

Dictionary::Dictionary(DescriptorKind kind, int descriptor_dim, const DictionaryOptions& options)
    : options_(options), index_(WordIndex::Create(kind, descriptor_dim, options)) {}

void Dictionary::CheckDescriptors(const cv::Mat& descriptors) const {
  if (descriptors.empty()) return;
  if (descriptors.type() != descriptor_cv_type() || descriptors.cols != descriptor_dim()) {
    const auto describe = [](int type, int cols) {
      return std::to_string(cols) + (type == CV_8U ? "-byte binary" : "-d float");
    };
    throw Error("descriptors of another kind: this map's words are " +
                describe(descriptor_cv_type(), descriptor_dim()) + " descriptors, these are " +
                describe(descriptors.type(), descriptors.cols) +
                " (one map holds one feature type: start a new map to change features.type)");
  }
}

std::vector<std::array<Neighbour, 2>> Dictionary::Nearest(const cv::Mat& descriptors,
                                                          const SearchOptions& search) const {
  CheckDescriptors(descriptors);
  return index_->Search(descriptors, search);
}

WordId Dictionary::MatchOf(const std::array<Neighbour, 2>& nearest) const {
  const Neighbour& first = nearest[0];
  const Neighbour& second = nearest[1];
  if (first.word == kNoWord) return kNoWord;
  const bool passes_ratio =
      second.word == kNoWord || first.distance < options_.nndr_ratio * second.distance;
  return passes_ratio ? first.word : kNoWord;
}

std::vector<WordId> Dictionary::Match(const cv::Mat& descriptors,
                                      const SearchOptions& search) const {
  const auto neighbours = Nearest(descriptors, search);
  std::vector<WordId> matches(neighbours.size(), kNoWord);
  for (size_t row = 0; row < neighbours.size(); ++row) matches[row] = MatchOf(neighbours[row]);
  return matches;
}

std::optional<std::vector<WordId>> Dictionary::MatchSince(
    const cv::Mat& descriptors, const std::vector<std::pair<float, float>>& found,
    long long mark) const {
  assert(static_cast<size_t>(descriptors.rows) == found.size());
  const long long remembered_from = join_count_ - static_cast<long long>(joined_.size());
  if (mark < remembered_from) return std::nullopt;
  std::vector<WordId> joined;
  cv::Mat joined_descriptors;
  for (auto word = joined_.begin() + (mark - remembered_from); word != joined_.end(); ++word) {
    if (!Contains(*word)) continue;  // left again
    joined.push_back(*word);
    joined_descriptors.push_back(Descriptor(*word));
  }
  std::vector<WordId> matches(found.size(), kNoWord);
  if (joined.empty() || descriptors.empty()) return matches;
  CheckDescriptors(descriptors);
  cv::Mat distances;
  cv::Mat nearest;
  const int k = std::min(2, static_cast<int>(joined.size()));
  cv::batchDistance(descriptors, joined_descriptors, distances, CV_32F, nearest,
                    descriptor_kind() == DescriptorKind::kBinary ? cv::NORM_HAMMING : cv::NORM_L2,
                    k);
  for (size_t row = 0; row < found.size(); ++row) {
    const auto [first, second] = found[row];  // the search's, among the words then
    const float joined_first = distances.at<float>(static_cast<int>(row), 0);
    if (!(joined_first < first)) continue;  // still the same nearest: still no match
    const float joined_second =
        k > 1 ? distances.at<float>(static_cast<int>(row), 1) : std::numeric_limits<float>::max();
    const float runner_up = std::min(first, joined_second);
    if (joined_first < options_.nndr_ratio * runner_up) {
      matches[row] = joined[nearest.at<int>(static_cast<int>(row), 0)];
    }
  }
  return matches;
}

std::vector<WordId> Dictionary::Quantize(const cv::Mat& descriptors, int* new_word_count,
                                         const SearchOptions& search, double* search_ms) {
  const auto start = std::chrono::steady_clock::now();
  std::vector<WordId> words = Match(descriptors, search);
  if (search_ms != nullptr) {
    *search_ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  }
  std::vector<WordId> new_ids;
  cv::Mat new_descriptors;
  for (int row = 0; row < static_cast<int>(words.size()); ++row) {
    if (words[row] != kNoWord) continue;
    words[row] = next_word_id_;
    new_ids.push_back(next_word_id_++);
    new_descriptors.push_back(descriptors.row(row));
  }
  Add(new_ids, new_descriptors);
  if (new_word_count != nullptr) *new_word_count = static_cast<int>(new_ids.size());
  return words;
}

void Dictionary::Add(const std::vector<WordId>& ids, const cv::Mat& descriptors) {
  if (ids.empty()) return;
  CheckDescriptors(descriptors);
  index_->Add(ids, descriptors);
  for (WordId id : ids) {
    assert(!Contains(id));
    words_[id];
    if (id >= next_word_id_) next_word_id_ = id + 1;
    joined_.push_back(id);
    ++join_count_;
  }
  while (joined_.size() > kJoinedRemembered) joined_.pop_front();
}

void Dictionary::Remove(WordId id) {
  assert(References(id).empty());
  index_->Remove(id);
  words_.erase(id);
  if (referenced_by_ltm_.Erase(id)) changed_mark_chunks_.insert(WordBitset::ChunkOf(id));
}

std::vector<WordId> Dictionary::Ids() const {
  std::vector<WordId> ids;
  ids.reserve(words_.size());
  for (const auto& entry : words_) ids.push_back(entry.first);
  std::sort(ids.begin(), ids.end());
  return ids;
}

cv::Mat Dictionary::Descriptor(WordId id) const { return index_->Descriptor(id); }

void Dictionary::AddReference(WordId id, LocationId location) {
  assert(Contains(id));
  ++words_.at(id).references[location];
}

bool Dictionary::RemoveReferences(WordId id, LocationId location) {
  Word& word = words_.at(id);
  word.references.erase(location);
  return word.references.empty();
}

const std::map<LocationId, int>& Dictionary::References(WordId id) const {
  static const std::map<LocationId, int> kNone;
  const auto found = words_.find(id);
  return found == words_.end() ? kNone : found->second.references;
}

void Dictionary::MarkReferencedByLtm(WordId id) {
  assert(words_.count(id));
  if (referenced_by_ltm_.Insert(id)) changed_mark_chunks_.insert(WordBitset::ChunkOf(id));
}

bool Dictionary::IsReferencedByLtm(WordId id) const { return referenced_by_ltm_.Contains(id); }

void Dictionary::Reload(const std::vector<WordId>& ids, const IndexHistory& history,
                        const std::vector<WordId>& referenced_by_ltm, WordId next_word_id) {
  index_->Replay(history, ids);
  words_.clear();
  referenced_by_ltm_.Clear();
  changed_mark_chunks_.clear();
  for (WordId id : ids) {
    if (id <= kNoWord || id >= next_word_id) {
      throw Error("word " + std::to_string(id) + " is out of the dictionary's id range");
    }
    words_[id];
  }
  for (WordId id : referenced_by_ltm) {
    const auto found = words_.find(id);
    if (found == words_.end()) {
      throw Error("word " + std::to_string(id) + " is marked for LTM but not in the dictionary");
    }
    referenced_by_ltm_.Insert(id);
  }
  next_word_id_ = next_word_id;
}

}  // namespace memloop
