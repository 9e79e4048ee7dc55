// Retrieval by appearance over LTM as it grows to a million locations (issue 39): the search
// (AppearanceIndex::Best, exhaustive or bounded by memory.appearance_max_postings) and the
// index's upkeep when a location is retrieved and transferred again (Leave, Enter).
//
// A synthetic LTM: each location described by 193 distinct entries of the vocabulary (the median
// of bench/scale.sh's images), drawn with a mild skew (log-normal weights, sigma 0.65) so that,
// with 8,192 entries, a query walks ~7 postings per location, as on bench/scale.sh's map at
// 26,789 locations.
// A revisit query keeps half of one location's entries and draws the rest anew; `found` is the
// fraction of revisit queries whose best match is that location, `z` their median z.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <memory>
#include <opencv2/core.hpp>
#include <string>
#include <tuple>
#include <vector>

#include "storage/ltm_database.h"
#include "vocabulary/appearance_index.h"

namespace memloop {
namespace {

constexpr int kEntries = 193;
constexpr int kQueries = 64;

class SyntheticLtm {
 public:
  SyntheticLtm(int locations, size_t max_postings, int vocabulary)
      : index_(DescriptorKind::kFloat, 64, vocabulary, DictionaryOptions(), max_postings),
        rng_(11) {
    double total = 0;
    for (int entry = 0; entry < vocabulary; ++entry) {
      total += std::exp(0.65 * rng_.gaussian(1.0));
      cumulative_.push_back(total);
    }
    for (LocationId id = 1; id <= locations; ++id) {
      Appearance appearance = Describe();
      if (id <= kQueries) revisits_.push_back(Revisit(appearance));
      index_.Add(id, std::move(appearance));
      index_.Enter(id);
    }
  }

  const AppearanceIndex& index() const { return index_; }
  AppearanceIndex& index() { return index_; }
  // Revisit i is of location i + 1.
  const std::vector<Appearance>& revisits() const { return revisits_; }

 private:
  AppearanceEntry Draw() {
    const double at = rng_.uniform(0.0, cumulative_.back());
    return static_cast<AppearanceEntry>(
        std::lower_bound(cumulative_.begin(), cumulative_.end(), at) - cumulative_.begin());
  }
  void TopUp(Appearance& appearance) {
    while (static_cast<int>(appearance.size()) < kEntries) {
      while (static_cast<int>(appearance.size()) < kEntries + 8) appearance.push_back(Draw());
      std::sort(appearance.begin(), appearance.end());
      appearance.erase(std::unique(appearance.begin(), appearance.end()), appearance.end());
    }
    // Keep kEntries of them, not the lowest ones only.
    for (int i = static_cast<int>(appearance.size()) - 1; i > 0; --i) {
      std::swap(appearance[i], appearance[rng_.uniform(0, i + 1)]);
    }
    appearance.resize(kEntries);
    std::sort(appearance.begin(), appearance.end());
  }
  Appearance Describe() {
    Appearance appearance;
    TopUp(appearance);
    return appearance;
  }
  Appearance Revisit(const Appearance& seen) {
    Appearance revisit;
    for (AppearanceEntry entry : seen) {
      if (rng_.uniform(0, 2) == 0) revisit.push_back(entry);
    }
    TopUp(revisit);
    return revisit;
  }

  AppearanceIndex index_;
  cv::RNG rng_;
  std::vector<double> cumulative_;
  std::vector<Appearance> revisits_;
};

// Built once per (locations, max_postings) and kept for the repetitions; one at a time (a million
// locations hold ~2 GB).
SyntheticLtm& LtmOf(int locations, size_t max_postings, int vocabulary) {
  static std::tuple<int, size_t, int> key{-1, 0, 0};
  static std::unique_ptr<SyntheticLtm> ltm;
  if (!ltm || key != std::make_tuple(locations, max_postings, vocabulary)) {
    ltm.reset();
    ltm = std::make_unique<SyntheticLtm>(locations, max_postings, vocabulary);
    key = {locations, max_postings, vocabulary};
  }
  return *ltm;
}

// Args: LTM locations, memory.appearance_max_postings (0 = every entry),
// memory.appearance_vocabulary.
void BM_AppearanceBest(benchmark::State& state) {
  SyntheticLtm& ltm = LtmOf(static_cast<int>(state.range(0)), static_cast<size_t>(state.range(1)),
                            static_cast<int>(state.range(2)));
  const std::vector<Appearance>& queries = ltm.revisits();
  size_t count = 0;
  for (auto _ : state) benchmark::DoNotOptimize(ltm.index().Best(queries[count++ % kQueries]));
  int found = 0;
  std::vector<double> z;
  for (int i = 0; i < kQueries; ++i) {
    const AppearanceMatch match = ltm.index().Best(queries[i]);
    found += match.id == i + 1;
    z.push_back(match.z);
  }
  std::nth_element(z.begin(), z.begin() + kQueries / 2, z.end());
  state.counters["found"] = static_cast<double>(found) / kQueries;
  state.counters["z"] = z[kQueries / 2];
}
BENCHMARK(BM_AppearanceBest)
    ->ArgsProduct({{1000, 10000, 25000, 100000, 1000000}, {0, 40000}, {8192, 32768}})
    ->Unit(benchmark::kMillisecond);

// Real descriptions (issue 39): those of the map named by MEMLOOP_APPEARANCE_MAP (e.g.
// bench/scale.sh's time.db), the newest 300 as queries and the others copied under shifted ids
// until LTM holds the locations asked for (args: locations, memory.appearance_max_postings). Copies
// are exact: a query's best is one of its place's copies, so only the time says something here, and
// `z`. Skipped without the variable. On the 29,800-image map of `bench/scale.sh 2800` at a million
// locations: 0.35 ms bounded, 5.8 ms every entry.
void BM_AppearanceBestRealDescriptions(benchmark::State& state) {
  const char* map = std::getenv("MEMLOOP_APPEARANCE_MAP");
  if (map == nullptr) {
    state.SkipWithError("set MEMLOOP_APPEARANCE_MAP to a map file to search its descriptions");
    return;
  }
  constexpr size_t kRealQueries = 300;
  static std::string loaded_from;
  static std::vector<std::pair<LocationId, std::vector<uint32_t>>> rows;
  if (loaded_from != map) {
    rows = LtmDatabase(map, LtmDatabase::Mode::kRead).ReadAppearances();
    loaded_from = map;
  }
  if (rows.size() <= kRealQueries) {
    state.SkipWithError("the map holds too few descriptions");
    return;
  }
  const size_t described = rows.size() - kRealQueries;
  const auto locations = static_cast<size_t>(state.range(0));
  AppearanceIndex index(DescriptorKind::kFloat, 64, 32768, DictionaryOptions(),
                        static_cast<size_t>(state.range(1)));
  const LocationId shift = rows.back().first + 1;
  for (size_t added = 0; added < locations; ++added) {
    const auto& [id, entries] = rows[added % described];
    const LocationId copy_id = id + static_cast<LocationId>(added / described) * shift;
    index.Add(copy_id, Appearance(entries.begin(), entries.end()));
    index.Enter(copy_id);
  }
  size_t count = 0;
  for (auto _ : state) {
    const auto& entries = rows[described + count++ % kRealQueries].second;
    benchmark::DoNotOptimize(index.Best(Appearance(entries.begin(), entries.end())));
  }
  std::vector<double> z;
  for (size_t i = described; i < rows.size(); ++i) {
    z.push_back(index.Best(Appearance(rows[i].second.begin(), rows[i].second.end())).z);
  }
  std::nth_element(z.begin(), z.begin() + z.size() / 2, z.end());
  state.counters["z"] = z[z.size() / 2];
}
BENCHMARK(BM_AppearanceBestRealDescriptions)
    ->ArgsProduct({{25000, 1000000}, {0, 40000}})
    ->Unit(benchmark::kMillisecond);

// A location retrieved from LTM (Leave) and transferred back (Enter), as retrieval and transfer
// do to the index every few images.
void BM_AppearanceLeaveEnter(benchmark::State& state) {
  const int locations = static_cast<int>(state.range(0));
  SyntheticLtm& ltm = LtmOf(locations, 0, static_cast<int>(state.range(1)));
  cv::RNG rng(5);
  for (auto _ : state) {
    const LocationId id = rng.uniform(1, locations + 1);
    ltm.index().Leave(id);
    ltm.index().Enter(id);
  }
}
BENCHMARK(BM_AppearanceLeaveEnter)
    ->ArgsProduct({{1000, 25000, 1000000}, {8192, 32768}})
    ->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace memloop
