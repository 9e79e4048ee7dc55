#include "dictionary.h"

#include <cassert>

namespace memloop {

Dictionary::Dictionary(int descriptor_dim, const DictionaryOptions& options)
    : options_(options), forest_(descriptor_dim, options) {}

std::vector<WordId> Dictionary::Match(const cv::Mat& descriptors) const {
  std::vector<WordId> matches(descriptors.rows, kNoWord);
  const auto neighbours = forest_.Search(descriptors);
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
  forest_.Add(ids, descriptors);
  for (WordId id : ids) {
    assert(!Contains(id));
    words_[id];
    if (id >= next_word_id_) next_word_id_ = id + 1;
  }
}

void Dictionary::Remove(WordId id) {
  assert(References(id).empty());
  forest_.Remove(id);
  words_.erase(id);
}

cv::Mat Dictionary::Descriptor(WordId id) const {
  const float* data = forest_.Descriptor(id);
  if (data == nullptr) return {};
  return cv::Mat(1, forest_.dim(), CV_32F, const_cast<float*>(data)).clone();
}

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

void Dictionary::MarkReferencedByLtm(WordId id) { words_.at(id).referenced_by_ltm = true; }

bool Dictionary::IsReferencedByLtm(WordId id) const {
  const auto found = words_.find(id);
  return found != words_.end() && found->second.referenced_by_ltm;
}

}  // namespace memloop
