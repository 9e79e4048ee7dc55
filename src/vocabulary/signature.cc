#include "vocabulary/signature.h"

#include <algorithm>

#include "memloop/feature_extractor.h"
#include "vocabulary/dictionary.h"

namespace memloop {

std::vector<std::pair<WordId, int>> Signature::Histogram() const {
  std::vector<WordId> sorted = words;
  std::sort(sorted.begin(), sorted.end());
  std::vector<std::pair<WordId, int>> histogram;
  for (WordId word : sorted) {
    if (!histogram.empty() && histogram.back().first == word) {
      ++histogram.back().second;
    } else {
      histogram.emplace_back(word, 1);
    }
  }
  return histogram;
}

Signature CreateSignature(const Features& features, Dictionary& dictionary, int* new_word_count,
                          const SearchOptions& search, double* search_ms) {
  Signature signature;
  signature.words = dictionary.Quantize(features.descriptors, new_word_count, search, search_ms);
  signature.keypoints.assign(features.keypoints.begin(),
                             features.keypoints.begin() + signature.words.size());
  return signature;
}

Signature MatchSignature(const Features& features, const Dictionary& dictionary,
                         const SearchOptions& search, size_t* searched) {
  Signature signature;
  const std::vector<WordId> words = dictionary.Match(features.descriptors, search);
  if (searched != nullptr) *searched = words.size();
  for (size_t row = 0; row < words.size(); ++row) {
    if (words[row] == kNoWord) continue;
    signature.words.push_back(words[row]);
    signature.keypoints.push_back(features.keypoints[row]);
  }
  return signature;
}

void KeepFirstFeatures(Features& features, size_t count) {
  if (count >= features.keypoints.size()) return;
  features.keypoints.resize(count);
  features.descriptors = features.descriptors.rowRange(0, static_cast<int>(count));
  if (!features.rolled_descriptors.empty()) {
    features.rolled_descriptors = features.rolled_descriptors.rowRange(0, static_cast<int>(count));
  }
}

int CountWordPairs(const std::vector<std::pair<WordId, int>>& histogram_a,
                   const std::vector<std::pair<WordId, int>>& histogram_b) {
  int pairs = 0;
  auto a = histogram_a.begin();
  auto b = histogram_b.begin();
  while (a != histogram_a.end() && b != histogram_b.end()) {
    if (a->first < b->first) {
      ++a;
    } else if (b->first < a->first) {
      ++b;
    } else {
      pairs += std::min(a->second, b->second);
      ++a;
      ++b;
    }
  }
  return pairs;
}

double SimilarityFromPairs(int pairs, int size_t_words, int size_c_words) {
  const int larger = std::max(size_t_words, size_c_words);  // eq. 1's two cases in one
  return larger == 0 ? 0.0 : static_cast<double>(pairs) / larger;
}

double Similarity(const Signature& z_t, const Signature& z_c) {
  return SimilarityFromPairs(CountWordPairs(z_t.Histogram(), z_c.Histogram()), z_t.size(),
                             z_c.size());
}

}  // namespace memloop
