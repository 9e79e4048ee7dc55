#include "vocabulary/dictionary.h"

#include <algorithm>
#include <cassert>

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

std::vector<WordId> Dictionary::Match(const cv::Mat& descriptors) const {
  CheckDescriptors(descriptors);
  std::vector<WordId> matches(descriptors.rows, kNoWord);
  const auto neighbours = index_->Search(descriptors);
  for (int row = 0; row < descriptors.rows; ++row) {
    const Neighbour& first = neighbours[row][0];
    const Neighbour& second = neighbours[row][1];
    if (first.word == kNoWord) continue;
    const bool passes_ratio =
        second.word == kNoWord || first.distance < options_.nndr_ratio * second.distance;
    if (passes_ratio) matches[row] = first.word;
  }
  return matches;
}

std::vector<WordId> Dictionary::Quantize(const cv::Mat& descriptors, int* new_word_count) {
  std::vector<WordId> words = Match(descriptors);
  std::vector<WordId> new_ids;
  cv::Mat new_descriptors;
  for (int row = 0; row < descriptors.rows; ++row) {
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
  }
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
