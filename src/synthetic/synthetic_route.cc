#include "memloop/synthetic_route.h"

#include <cmath>
#include <opencv2/imgproc.hpp>

#include "memloop/errors.h"
#include "synthetic/synthetic_view.h"

namespace memloop {
namespace {

constexpr int kDetourGap = 4;  // steps: more than two image widths, no overlap

}  // namespace

SyntheticRoute::SyntheticRoute(const SyntheticRouteOptions& options) : options_(options) {
  cv::RNG rng(static_cast<uint64_t>(options.seed));
  const int view_width = options.image_width;
  const int world_height = options.image_height + 60;  // room for vertical jitter
  loop_length_ = options.lap_frames * options.step_px;
  const int loop_width = static_cast<int>(std::ceil(loop_length_));
  const int wrap_width = 2 * view_width;
  const int detour_width =
      static_cast<int>((2 * options.detour_frames + kDetourGap) * options.step_px) + wrap_width;

  const cv::Mat loop = MakeTexture(loop_width, world_height, rng, options.facades);
  const cv::Mat detour = MakeTexture(detour_width, world_height, rng, options.facades);
  world_ = cv::Mat(world_height, loop_width + wrap_width + detour_width, CV_8U);
  loop.copyTo(world_.colRange(0, loop_width));
  loop.colRange(0, wrap_width).copyTo(world_.colRange(loop_width, loop_width + wrap_width));
  detour.copyTo(world_.colRange(loop_width + wrap_width, world_.cols));

  const auto add_frame = [&](double x, bool in_loop, int visit) {
    const ViewJitter j = ViewJitter::Random(rng);
    frames_.push_back({x, in_loop, visit, j.dx, j.dy, j.scale, j.angle_degrees, j.gain, j.bias});
  };
  for (int n = 0; n < options.lap_frames; ++n) add_frame(n * options.step_px, true, 0);
  for (int n = 0; n < options.detour_frames; ++n) add_frame(n * options.step_px, false, -1);
  for (int n = 0; n < options.lap_frames; ++n) add_frame(n * options.step_px, true, 1);
  // The second detour goes on to new places: a gap of kDetourGap steps from the first one's end.
  for (int n = options.detour_frames; n < 2 * options.detour_frames; ++n) {
    add_frame((n + kDetourGap) * options.step_px, false, -1);
  }
  for (int n = 0; n < options.third_lap_frames; ++n) add_frame(n * options.step_px, true, 2);
}

cv::Mat SyntheticRoute::Render(int index) const {
  const Frame& frame = frames_.at(index);
  const double x =
      frame.x + (frame.in_loop ? 0 : std::ceil(loop_length_) + 2 * options_.image_width);
  const ViewJitter jitter{frame.dx,   frame.dy,  frame.scale, frame.angle_degrees,
                          frame.gain, frame.bias};
  return RenderView(world_, x, 30, jitter, options_.image_width, options_.image_height,
                    static_cast<uint64_t>(options_.seed) * 1000003u + index);
}

cv::Mat SyntheticRoute::RenderGray(int index) const {
  cv::Mat gray;
  cv::cvtColor(Render(index), gray, cv::COLOR_BGR2GRAY);
  return gray;
}

bool SyntheticRoute::IsLoop(int query, int match) const {
  const Frame& a = frames_.at(query);
  const Frame& b = frames_.at(match);
  if (match >= query || !a.in_loop || !b.in_loop) return false;
  const double same_place = options_.same_place_fraction * options_.image_width;
  const double direct = std::fabs((a.x + a.dx) - (b.x + b.dx));
  const double around = loop_length_ - direct;  // the loop closes on itself
  // Frames of one lap close to each other are neighbours, not loop closures; the lap's last
  // frames, back where it started, are.
  if (a.visit == b.visit) return direct > same_place && around <= same_place;
  return std::min(direct, around) <= same_place;
}

GroundTruth SyntheticRoute::Truth() const {
  cv::Mat labels(size(), size(), CV_8U, cv::Scalar(GroundTruth::kNone));
  for (const auto& [query, match] : GroundTruthPairs()) {
    labels.at<unsigned char>(query, match) = GroundTruth::kLoop;
  }
  return GroundTruth(labels);
}

std::vector<std::pair<int, int>> SyntheticRoute::GroundTruthPairs() const {
  std::vector<std::pair<int, int>> pairs;
  for (int query = 0; query < size(); ++query) {
    for (int match = 0; match < query; ++match) {
      if (IsLoop(query, match)) pairs.emplace_back(query, match);
    }
  }
  return pairs;
}

void SyntheticRoute::Write(const std::string& folder, const std::function<void(int)>& written,
                           GeneratedLayout layout) const {
  WriteSequence(
      folder, size(), [this](int index) { return Render(index); }, GroundTruthPairs(), written,
      layout);
}

}  // namespace memloop
