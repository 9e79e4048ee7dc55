// Kernels of the per-image cycle, one thread: feature extraction, quantization into the
// dictionary, the likelihood over WM and the Bayes filter update. Run: bench/run_bench.sh, or
// ./build/bench/memloop_benchmarks --benchmark_repetitions=5 --benchmark_report_aggregates_only.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <opencv2/core/utility.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "detector/bayes_filter.h"
#include "detector/likelihood.h"
#include "detector/memory.h"
#include "detector/neighbourhood_cache.h"
#include "detector/view_roll.h"
#include "memloop/feature_extractor.h"
#include "memloop/image_sequence.h"
#include "memloop/synthetic_route.h"
#include "storage/long_term_memory.h"
#include "vocabulary/dictionary.h"

namespace memloop {
namespace {

cv::Mat RandomDescriptors(int rows, uint64_t seed, int dim = 128) {
  cv::Mat descriptors(rows, dim, CV_32F);
  cv::RNG(seed).fill(descriptors, cv::RNG::UNIFORM, 0.0, 1.0);
  return descriptors;
}

cv::Mat RouteImage(int width, int height, int frame) {
  SyntheticRouteOptions options;
  options.image_width = width;
  options.image_height = height;
  return SyntheticRoute(options).RenderGray(frame);
}

// Detect + describe, one thread, over a set of 512x384 images (cycled): the shared real images
// when present (MEMLOOP_IMAGES or ../shared/datasets/rtabmap_samples/images), generated ones
// otherwise. Counter "keypoints": mean per image.
const std::vector<cv::Mat>& BenchImages(bool real) {
  static const std::vector<cv::Mat> generated = [] {
    std::vector<cv::Mat> images;
    for (int frame = 0; frame < 10; ++frame) images.push_back(RouteImage(512, 384, frame * 7));
    return images;
  }();
  static const std::vector<cv::Mat> shared = [] {
    std::vector<cv::Mat> images;
    const char* folder = std::getenv("MEMLOOP_IMAGES");
    const std::string path = folder ? folder : "../shared/datasets/rtabmap_samples/images";
    if (!std::filesystem::is_directory(path)) return images;
    for (const std::string& name : ListFolder(path)) {
      images.push_back(cv::imread(path + "/" + name, cv::IMREAD_GRAYSCALE));
    }
    return images;
  }();
  return real ? shared : generated;
}

// Args: 0 generated / 1 real images; backend; SURF Hessian threshold.
void Extract(benchmark::State& state, const std::string& backend, bool real, double threshold) {
  cv::setNumThreads(1);
  const auto& images = BenchImages(real);
  if (images.empty()) {
    state.SkipWithError("no real images (../shared absent)");
    return;
  }
  FeatureOptions options;
  options.type = backend;
  options.surf_hessian_threshold = threshold;
  const auto extractor = FeatureExtractor::Create(options);
  size_t keypoints = 0;
  size_t count = 0;
  for (auto _ : state) {
    keypoints += extractor->Extract(images[count++ % images.size()]).keypoints.size();
  }
  state.counters["keypoints"] = static_cast<double>(keypoints) / count;
}
BENCHMARK_CAPTURE(Extract, sift_generated, std::string("sift"), false, 0)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(Extract, surf_generated, std::string("surf"), false, 50)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(Extract, orb_generated, std::string("orb"), false, 0)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(Extract, sift_real, std::string("sift"), true, 0)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(Extract, orb_real, std::string("orb"), true, 0)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(Extract, surf_real_h400, std::string("surf"), true, 400)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(Extract, surf_real_h50, std::string("surf"), true, 50)
    ->Unit(benchmark::kMillisecond);

// Matching one image's 400 descriptors against a dictionary of N words, searched by T threads
// (dictionary.search_threads, the caller's included).
void BM_DictionaryMatch(benchmark::State& state) {
  DictionaryOptions options;
  options.search_threads = static_cast<int>(state.range(1));
  Dictionary dictionary(DescriptorKind::kFloat, 128, options);
  std::vector<WordId> ids;
  for (int i = 1; i <= state.range(0); ++i) ids.push_back(i);
  dictionary.Add(ids, RandomDescriptors(static_cast<int>(ids.size()), 1));
  const cv::Mat queries = RandomDescriptors(400, 2);
  for (auto _ : state) benchmark::DoNotOptimize(dictionary.Match(queries));
}
BENCHMARK(BM_DictionaryMatch)
    ->ArgsProduct({{10000, 50000, 100000}, {1, 2}})
    ->UseRealTime()
    ->Unit(benchmark::kMillisecond);

// Matching 400 SURF-sized (64-d) descriptors, one thread, against N live words of which a share
// (arg 2, percent) were added after the last build and a like number removed since: how the search
// grows with the dictionary (issue 9's 1,000-2,000 block has ~200,000 words, the end 400,000).
void BM_DictionaryMatchGrowth(benchmark::State& state) {
  constexpr int kDim = 64;
  DictionaryOptions options;
  options.search_threads = 1;
  options.rebuild_fraction = 100;  // no rebuild: the removed points stay in the trees
  Dictionary dictionary(DescriptorKind::kFloat, kDim, options);
  const int live = static_cast<int>(state.range(0));
  const int churn = live * static_cast<int>(state.range(1)) / 100;
  std::vector<WordId> ids;
  for (int i = 1; i <= live; ++i) ids.push_back(i);
  dictionary.Add(ids, RandomDescriptors(live, 1, kDim));
  if (churn > 0) {
    std::vector<WordId> added;
    for (int i = 1; i <= churn; ++i) added.push_back(live + i);
    dictionary.Add(added, RandomDescriptors(churn, 5, kDim));
    for (int i = 1; i <= churn; ++i) dictionary.Remove(i);
  }
  const cv::Mat queries = RandomDescriptors(400, 2, kDim);
  for (auto _ : state) benchmark::DoNotOptimize(dictionary.Match(queries));
}
BENCHMARK(BM_DictionaryMatchGrowth)
    ->ArgsProduct({{100000, 200000, 400000}, {0, 25}})
    ->UseRealTime()
    ->Unit(benchmark::kMillisecond);

// Adding 400 words and removing 400 others: the incremental update of the forest.
void BM_DictionaryAddRemove(benchmark::State& state) {
  Dictionary dictionary(DescriptorKind::kFloat, 128, DictionaryOptions());
  std::vector<WordId> ids;
  for (int i = 1; i <= state.range(0); ++i) ids.push_back(i);
  dictionary.Add(ids, RandomDescriptors(static_cast<int>(ids.size()), 1));
  const cv::Mat batch = RandomDescriptors(400, 3);
  WordId next = static_cast<WordId>(ids.size()) + 1;
  WordId oldest = 1;
  for (auto _ : state) {
    std::vector<WordId> added;
    for (int i = 0; i < 400; ++i) added.push_back(next++);
    dictionary.Add(added, batch);
    for (int i = 0; i < 400; ++i) dictionary.Remove(oldest++);
  }
}
BENCHMARK(BM_DictionaryAddRemove)->Arg(10000)->Arg(50000)->Unit(benchmark::kMillisecond);

// One full cycle of the forest's background rebuild at N words, 64-d (SURF), as under T_time
// (rebuild_swap_when_ready): per step 200 words added and 200 removed, until a build has started
// and been swapped in. The counters are the step times: the start and the swap must not pause the
// step that does them (issue 9).
void BM_DictionaryBuildCycle(benchmark::State& state) {
  constexpr int kDim = 64;
  constexpr int kPerStep = 200;
  DictionaryOptions options;
  options.rebuild_swap_when_ready = true;
  for (auto _ : state) {
    state.PauseTiming();
    Dictionary dictionary(DescriptorKind::kFloat, kDim, options);
    std::vector<WordId> ids;
    for (int i = 1; i <= state.range(0); ++i) ids.push_back(i);
    dictionary.Add(ids, RandomDescriptors(static_cast<int>(ids.size()), 1, kDim));
    const cv::Mat batch = RandomDescriptors(kPerStep, 3, kDim);
    WordId next = static_cast<WordId>(ids.size()) + 1;
    WordId oldest = 1;
    state.ResumeTiming();
    std::vector<double> step_ms;
    const int builds = dictionary.index().build_count();
    while (dictionary.index().build_count() < builds + 1) {
      const auto start = std::chrono::steady_clock::now();
      std::vector<WordId> added;
      for (int i = 0; i < kPerStep; ++i) added.push_back(next++);
      dictionary.Add(added, batch);
      for (int i = 0; i < kPerStep; ++i) dictionary.Remove(oldest++);
      step_ms.push_back(
          std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
              .count());
    }
    std::sort(step_ms.begin(), step_ms.end());
    state.counters["steps"] = static_cast<double>(step_ms.size());
    state.counters["median_step_ms"] = step_ms[step_ms.size() / 2];
    state.counters["max_step_ms"] = step_ms.back();
  }
}
BENCHMARK(BM_DictionaryBuildCycle)
    ->Arg(100000)
    ->Arg(400000)
    ->Iterations(1)
    ->Unit(benchmark::kMillisecond);

// Eq. 3-4 from N scores, and eq. 2 over a chain of N locations.
void BM_LikelihoodAndFilter(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  IdMap<double> scores;
  Neighbourhoods neighbourhoods;
  for (int id = 1; id <= n; ++id) {
    scores[id] = (id % 7) * 0.02;
    for (int d = -4; d <= 4; ++d) {
      if (id + d >= 1 && id + d <= n) neighbourhoods[id].emplace_back(id + d, std::abs(d));
    }
  }
  BayesFilter filter{FilterOptions()};
  for (auto _ : state) {
    const Likelihood likelihood = ComputeLikelihood(scores);
    filter.Update(likelihood, neighbourhoods);
  }
}
BENCHMARK(BM_LikelihoodAndFilter)->Arg(100)->Arg(1000)->Arg(5000)->Unit(benchmark::kMillisecond);

// The filter's neighbourhoods (range 4) of every WM location: a chain of N locations, one loop
// closure every 50. Arg 1: N; Arg 2: 1 = all at once (Memory::WmNeighbourhoods), 0 = one search per
// location (Memory::WmNeighbourhood, how they were computed before), 2 = kept from the image
// before (NeighbourhoodCache) after one image's changes: a new location, one transferred.
void BM_WmNeighbourhoods(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  DictionaryOptions dictionary_options;
  Memory memory(DescriptorKind::kFloat, 2, dictionary_options);
  std::vector<LocationId> ids;
  for (int i = 0; i < n; ++i) {
    ids.push_back(memory.AddToStm(Signature(), i, ids.empty() ? kNoLocation : ids.back()).id);
    if (i >= 100 && i % 50 == 0) {
      memory.at(ids.back()).loop_closures.insert(ids[i - 100]);
      memory.at(ids[i - 100]).loop_closures.insert(ids.back());
    }
  }
  memory.MoveStmOverflowToWm(20);
  NeighbourhoodCache cache;
  cache.Update(memory, 4);
  for (auto _ : state) {
    if (state.range(1) == 2) {
      state.PauseTiming();
      ids.push_back(memory.AddToStm(Signature(), n, ids.back()).id);
      memory.MoveStmOverflowToWm(20);
      std::vector<WordId> orphans;
      memory.Release(*memory.working_memory().begin(), &orphans);  // the oldest
      state.ResumeTiming();
      benchmark::DoNotOptimize(cache.Update(memory, 4));
    } else if (state.range(1) == 1) {
      benchmark::DoNotOptimize(memory.WmNeighbourhoods(4));
    } else {
      Neighbourhoods neighbourhoods;
      for (LocationId id : memory.working_memory())
        neighbourhoods[id] = memory.WmNeighbourhood(id, 4);
      benchmark::DoNotOptimize(neighbourhoods);
    }
  }
}
BENCHMARK(BM_WmNeighbourhoods)
    ->Args({500, 0})
    ->Args({500, 1})
    ->Args({500, 2})
    ->Args({2000, 0})
    ->Args({2000, 1})
    ->Args({2000, 2})
    ->Unit(benchmark::kMillisecond);

// A Rehearsal merge's update of LTM's link graph (LongTermMemory::RedirectLocation), with N
// locations in LTM: the cost must not grow with N (it looked at every entry before: 5 ms at
// 40,000). Each iteration merges a new in-memory location linked to the newest LTM location.
void BM_RedirectLocation(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  const std::filesystem::path path =
      std::filesystem::temp_directory_path() / ("memloop_bench_redirect_" + std::to_string(n));
  std::filesystem::remove(path);
  {
    LongTermMemory ltm(path.string());
    for (int id = 1; id <= n; ++id) {
      Location location;
      location.id = id;
      location.neighbours = {id - 1, id + 1};
      location.images = {id};
      ltm.Store(location);
    }
    ltm.Flush();
    LocationId absorbed = n + 1;
    for (auto _ : state) {
      ltm.RedirectLocation(absorbed, absorbed + 1, {n, absorbed + 1});
      // Committed every 20 merges, as the detector's checkpoints do (the queue's overlay of
      // uncommitted redirections is walked by each new one).
      if (++absorbed % 20 == 0) {
        state.PauseTiming();
        ltm.Flush();
        state.ResumeTiming();
      }
    }
  }
  for (const char* suffix : {"", "-wal", "-shm"}) std::filesystem::remove(path.string() + suffix);
}
BENCHMARK(BM_RedirectLocation)->Arg(1000)->Arg(50000)->Unit(benchmark::kMicrosecond);

// verify.max_roll_degrees: the view roll of the highest hypothesis, once per image, O(n^2) in the
// words both signatures hold once (a true revisit of lip6_outdoor: a median 36, at most ~400).
void BM_ViewRoll(benchmark::State& state) {
  WordCorrespondences matched;
  cv::RNG rng(7);
  for (int k = 0; k < state.range(0); ++k) {
    const cv::Point2f a(rng.uniform(0.f, 240.f), rng.uniform(0.f, 192.f));
    matched.in_a.push_back(a);
    matched.in_b.emplace_back(a.x * 0.97f + 0.26f * a.y, a.y * 0.97f - 0.26f * a.x);  // 15 degrees
  }
  for (auto _ : state) benchmark::DoNotOptimize(EstimateViewRoll(matched));
}
BENCHMARK(BM_ViewRoll)->Arg(36)->Arg(400)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace memloop

BENCHMARK_MAIN();
