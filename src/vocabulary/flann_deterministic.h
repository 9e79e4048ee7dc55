// FLANN, made repeatable. Debian's FLANN 1.9.2 (as upstream 1.9.2) shuffles the points before
// building each kd-tree with std::shuffle seeded from std::random_device, so two forests built from
// the same points differ, flann::seed_random cannot help, and two runs of the same images give
// different words. While FLANN's headers are read, random_device is renamed to minstd_rand0, a
// standard engine whose default seed is fixed: every build shuffles the same way, and the rest of
// FLANN's randomness (std::rand) is seeded by flann::seed_random. Include FLANN only through here,
// and build an index with BuildIndex.
// The LSH tables (binary words) keep their buckets in a hash map instead of FLANN's default
// std::map: the same buckets in the same order, so the same words, found without a tree walk per
// probed bucket. An ORB run of tum_fr1_rpy spent 85% of its time in those walks: 72 s of CPU
// (41 s on 2 cores) before, 53 s (31 s) after, with an identical CSV but for the times.
#pragma once

#include <flann/defines.h>
#include <flann/general.h>
#include <flann/util/serialization.h>

#include <memory>
#include <mutex>
#include <random>
#include <unordered_map>

// FLANN serializes std::map only; the hash map is written as the map is (its size, then pairs).
namespace flann::serialization {
template <typename K, typename V>
struct Serializer<std::unordered_map<K, V>> {
  template <typename InputArchive>
  static void load(InputArchive& archive, std::unordered_map<K, V>& map) {
    size_t size = 0;
    archive& size;
    for (size_t i = 0; i < size; ++i) {
      K key;
      V value;
      archive& key;
      archive& value;
      map[key] = std::move(value);
    }
  }
  template <typename OutputArchive>
  static void save(OutputArchive& archive, const std::unordered_map<K, V>& map) {
    archive& map.size();
    for (const auto& [key, value] : map) {
      archive& key;
      archive& value;
    }
  }
};
}  // namespace flann::serialization

#define random_device minstd_rand0
#define USE_UNORDERED_MAP 1
#include <flann/flann.hpp>
#undef random_device
#undef USE_UNORDERED_MAP

#include "memloop/options.h"

namespace memloop {

inline flann::IndexParams IndexParams(const flann::L2<float>&, const DictionaryOptions& options) {
  return flann::KDTreeIndexParams(options.kd_trees);
}
inline flann::IndexParams IndexParams(const flann::Hamming<unsigned char>&,
                                      const DictionaryOptions& options) {
  return flann::LshIndexParams(options.lsh_tables, options.lsh_key_bits, options.lsh_probe_level);
}

// A FLANN index built over `points` with the dictionary's seed. FLANN draws its splits from
// std::rand, which is process-wide: builds (in the background or not, of any index) take turns so
// that each draws an unbroken sequence from its seed.
template <typename Distance>
std::unique_ptr<flann::Index<Distance>> BuildIndex(
    const flann::Matrix<typename Distance::ElementType>& points, const DictionaryOptions& options) {
  static std::mutex build_mutex;
  const std::lock_guard<std::mutex> lock(build_mutex);
  flann::seed_random(options.seed);
  auto index = std::make_unique<flann::Index<Distance>>(points, IndexParams(Distance(), options));
  index->buildIndex();
  return index;
}

}  // namespace memloop
