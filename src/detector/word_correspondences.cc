#include "detector/word_correspondences.h"

#include <algorithm>
#include <unordered_map>
#include <utility>

namespace memloop {
namespace {

// Word -> keypoint index for the words a signature holds exactly once.
std::unordered_map<WordId, int> UniqueWords(const Signature& signature) {
  std::unordered_map<WordId, int> unique;
  std::unordered_map<WordId, int> count;
  for (int k = 0; k < signature.size(); ++k) {
    if (++count[signature.words[k]] == 1) unique[signature.words[k]] = k;
  }
  for (const auto& [word, n] : count) {
    if (n > 1) unique.erase(word);
  }
  return unique;
}

}  // namespace

WordCorrespondences UniqueWordCorrespondences(const Signature& a, const Signature& b) {
  WordCorrespondences correspondences;
  if (a.keypoints.size() != a.words.size() || b.keypoints.size() != b.words.size()) {
    return correspondences;
  }
  const std::unordered_map<WordId, int> in_b = UniqueWords(b);
  std::vector<std::pair<WordId, int>> in_a_sorted;
  for (const auto& entry : UniqueWords(a)) in_a_sorted.push_back(entry);
  std::sort(in_a_sorted.begin(), in_a_sorted.end());
  for (const auto& [word, k] : in_a_sorted) {
    const auto found = in_b.find(word);
    if (found == in_b.end()) continue;
    correspondences.in_a.push_back(a.keypoints[k].pt);
    correspondences.in_b.push_back(b.keypoints[found->second].pt);
  }
  return correspondences;
}

}  // namespace memloop
