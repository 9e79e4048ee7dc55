// The whole-image channel's cost (features.whole_image; docs/design.md, "Whole-image channel"):
// describing an image, and scoring a descriptor against a WM of N locations. Beside it, the
// other per-image description of the whole image: its camera roll (camera_roll.h).
#include <benchmark/benchmark.h>

#include <opencv2/core.hpp>
#include <vector>

#include "features/camera_roll.h"
#include "features/whole_image_descriptor.h"
#include "memloop/synthetic_route.h"

namespace memloop {
namespace {

// A generated 16:9 gray image `width` pixels wide.
cv::Mat GrayImage(int64_t width) {
  SyntheticRouteOptions options;
  options.image_width = static_cast<int>(width);
  options.image_height = options.image_width * 9 / 16;
  return SyntheticRoute(options).RenderGray(3);
}

void BM_WholeImageDescribe(benchmark::State& state) {
  const cv::Mat gray = GrayImage(state.range(0));
  for (auto _ : state) benchmark::DoNotOptimize(DescribeWholeImage(gray));
}
BENCHMARK(BM_WholeImageDescribe)->Arg(320)->Arg(960)->Unit(benchmark::kMicrosecond);

// N descriptors of generated images, scored against one: the channel's part of the likelihood.
void BM_WholeImageScoreWm(benchmark::State& state) {
  const SyntheticRoute route;
  std::vector<WholeImageDescriptor> wm;
  for (int k = 0; k < 64; ++k) wm.push_back(DescribeWholeImage(route.RenderGray(k)));
  const WholeImageDescriptor query = DescribeWholeImage(route.RenderGray(100));
  const auto locations = static_cast<size_t>(state.range(0));
  for (auto _ : state) {
    double sum = 0;
    for (size_t j = 0; j < locations; ++j) sum += WholeImageSimilarity(query, wm[j % wm.size()]);
    benchmark::DoNotOptimize(sum);
  }
}
BENCHMARK(BM_WholeImageScoreWm)->Arg(100)->Arg(500)->Arg(2000)->Unit(benchmark::kMicrosecond);

// The camera's roll from an image's edges (camera_roll.h): once per image with the rolled view
// (surf.rolled_view_degrees, the default) or roll compensation (--preset hand-held).
void BM_EstimateCameraRoll(benchmark::State& state) {
  const cv::Mat gray = GrayImage(state.range(0));
  for (auto _ : state) benchmark::DoNotOptimize(EstimateCameraRoll(gray));
}
BENCHMARK(BM_EstimateCameraRoll)->Arg(320)->Arg(960)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace memloop
