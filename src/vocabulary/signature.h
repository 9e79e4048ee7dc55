// A signature z: the visual words of an image with the keypoint each came from (paper III-A).
#pragma once

#include <cstdint>
#include <opencv2/core.hpp>
#include <utility>
#include <vector>

#include "memloop/types.h"
#include "vocabulary/word_index.h"

namespace memloop {

class Dictionary;
struct Features;

struct Signature {
  std::vector<WordId> words;            // one per keypoint; a word may repeat
  std::vector<cv::KeyPoint> keypoints;  // same order as words
  // The image these keypoints were seen in (it follows the signature when Rehearsal gives it to
  // a newer location); kNoImage when unknown (a map made before memloop recorded it).
  ImageIndex image = kNoImage;
  // That image's whole-image descriptor (features/whole_image_descriptor.h), empty without
  // features.whole_image; it follows the signature as the image does.
  std::vector<uint8_t> whole_image;

  int size() const { return static_cast<int>(words.size()); }
  // (word, occurrences), sorted by word.
  std::vector<std::pair<WordId, int>> Histogram() const;
};

// Quantizes the features into words of `dictionary`, creating words for descriptors that match
// none (paper III-A). `new_word_count` receives how many were created. With a gate in `search`
// (Dictionary::Quantize), the first features only: the signature then holds fewer keypoints.
// `search_ms` receives the kd-forest search's time.
Signature CreateSignature(const Features& features, Dictionary& dictionary, int* new_word_count,
                          const SearchOptions& search = {}, double* search_ms = nullptr);

// Localization: the words of `dictionary` the features match; a feature that matches none is
// dropped (with its keypoint) instead of becoming a new word. With a gate in `search`, of the
// first features only; `searched` (if given) receives how many were searched.
Signature MatchSignature(const Features& features, const Dictionary& dictionary,
                         const SearchOptions& search = {}, size_t* searched = nullptr);

// Keeps the first `count` features (the strongest: extractors sort them), with the rows of their
// rolled view.
void KeepFirstFeatures(Features& features, size_t count);

// N_pair: matched word pairs of two signatures. A word held m times by one and n times by the
// other makes min(m, n) pairs (the paper leaves repeated words open; this keeps s <= 1).
int CountWordPairs(const std::vector<std::pair<WordId, int>>& histogram_a,
                   const std::vector<std::pair<WordId, int>>& histogram_b);

// Eq. 1: s(z_t, z_c) = N_pair / max(N_zt, N_zc); 0 when both are empty.
double SimilarityFromPairs(int pairs, int size_t_words, int size_c_words);
double Similarity(const Signature& z_t, const Signature& z_c);

}  // namespace memloop
