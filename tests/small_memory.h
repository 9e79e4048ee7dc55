// Helpers for unit tests: a Memory whose words are 2-D points, so that distances, ratio tests and
// similarities can be worked out by hand.
#pragma once

#include <cstring>
#include <utility>
#include <vector>

#include "detector/memory.h"

namespace memloop::testing {

inline DictionaryOptions SmallDictionaryOptions() {
  DictionaryOptions options;
  options.kd_checks = 1000;  // exact on these tiny sets
  return options;
}

// Adds words `ids` at points (id * 100, 0): far apart, so each point matches only its own word.
inline void AddWords(Dictionary& dictionary, const std::vector<WordId>& ids) {
  cv::Mat points(static_cast<int>(ids.size()), 2, CV_32F);
  for (size_t row = 0; row < ids.size(); ++row) {
    points.at<float>(static_cast<int>(row), 0) = static_cast<float>(ids[row] * 100);
    points.at<float>(static_cast<int>(row), 1) = 0;
  }
  dictionary.Add(ids, points);
}

inline Signature MakeSignature(const std::vector<WordId>& words) {
  Signature signature;
  signature.words = words;
  for (size_t i = 0; i < words.size(); ++i) {
    signature.keypoints.emplace_back(static_cast<float>(i), 2.0f * i, 3.0f, 45.0f, 0.5f, 1);
  }
  return signature;
}

// A location as LTM tests store it: linked to its neighbours id - 1 and id + 1, image `id`.
inline Location MakeLtmLocation(LocationId id, const std::vector<WordId>& words) {
  Location location;
  location.id = id;
  location.signature = MakeSignature(words);
  location.neighbours = {id - 1, id + 1};
  location.images = {static_cast<ImageIndex>(id)};
  return location;
}

// Adds locations with the given words to STM, each linked to the previous; returns their ids.
inline std::vector<LocationId> AddChain(Memory& memory,
                                        const std::vector<std::vector<WordId>>& signatures) {
  std::vector<LocationId> ids;
  LocationId previous = kNoLocation;
  for (const auto& words : signatures) {
    for (WordId word : words) {
      if (!memory.dictionary().Contains(word)) AddWords(memory.dictionary(), {word});
    }
    previous =
        memory.AddToStm(MakeSignature(words), static_cast<ImageIndex>(ids.size()), previous).id;
    ids.push_back(previous);
  }
  return ids;
}

// The bytes of float values, as LTM stores a float descriptor row.
inline std::vector<unsigned char> FloatBytes(const std::vector<float>& values) {
  std::vector<unsigned char> bytes(values.size() * sizeof(float));
  std::memcpy(bytes.data(), values.data(), bytes.size());
  return bytes;
}

}  // namespace memloop::testing
