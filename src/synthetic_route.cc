#include "memloop/synthetic_route.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "memloop/errors.h"

namespace memloop {
namespace {

constexpr int kDetourGap = 4;  // steps: more than two image widths, no overlap

// Random shapes of random gray levels over smooth noise: corners and blobs everywhere, and no two
// places alike.
cv::Mat MakeTexture(int width, int height, cv::RNG& rng) {
  cv::Mat coarse(height / 16 + 1, width / 16 + 1, CV_8U);
  rng.fill(coarse, cv::RNG::UNIFORM, 60, 190);
  cv::Mat texture;
  cv::resize(coarse, texture, cv::Size(width, height), 0, 0, cv::INTER_CUBIC);
  const int shapes = width * height / 900;
  for (int n = 0; n < shapes; ++n) {
    const cv::Point center(rng.uniform(0, width), rng.uniform(0, height));
    const cv::Scalar gray(rng.uniform(0, 256));
    const int size = rng.uniform(3, 22);
    switch (rng.uniform(0, 4)) {
      case 0:
        cv::circle(texture, center, size, gray, cv::FILLED, cv::LINE_AA);
        break;
      case 1:
        cv::rectangle(texture, center, center + cv::Point(size, rng.uniform(3, 22)), gray,
                      cv::FILLED);
        break;
      case 2:
        cv::ellipse(texture, center, cv::Size(size, rng.uniform(2, 12)), rng.uniform(0, 180), 0,
                    360, gray, cv::FILLED, cv::LINE_AA);
        break;
      default:
        cv::line(texture, center, center + cv::Point(rng.uniform(-25, 25), rng.uniform(-25, 25)),
                 gray, rng.uniform(1, 4), cv::LINE_AA);
    }
  }
  return texture;
}

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

  const cv::Mat loop = MakeTexture(loop_width, world_height, rng);
  const cv::Mat detour = MakeTexture(detour_width, world_height, rng);
  world_ = cv::Mat(world_height, loop_width + wrap_width + detour_width, CV_8U);
  loop.copyTo(world_.colRange(0, loop_width));
  loop.colRange(0, wrap_width).copyTo(world_.colRange(loop_width, loop_width + wrap_width));
  detour.copyTo(world_.colRange(loop_width + wrap_width, world_.cols));

  const auto add_frame = [&](double x, bool in_loop, int visit) {
    Frame frame{x, in_loop, visit, 0, 0, 1, 0, 1, 0};
    frame.dx = rng.uniform(-12.0, 12.0);
    frame.dy = rng.uniform(-8.0, 8.0);
    frame.scale = rng.uniform(0.95, 1.05);
    frame.angle_degrees = rng.uniform(-3.0, 3.0);
    frame.gain = rng.uniform(0.8, 1.2);
    frame.bias = rng.uniform(-20.0, 20.0);
    frames_.push_back(frame);
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
  const double origin_x =
      frame.x + frame.dx + (frame.in_loop ? 0 : std::ceil(loop_length_) + 2 * options_.image_width);
  const double origin_y = 30 + frame.dy;
  // Output pixel -> world pixel: rotation and scale about the image centre, then the offset.
  const cv::Point2f centre(options_.image_width / 2.0f, options_.image_height / 2.0f);
  cv::Mat to_world = cv::getRotationMatrix2D(centre, frame.angle_degrees, 1.0 / frame.scale);
  to_world.at<double>(0, 2) += origin_x;
  to_world.at<double>(1, 2) += origin_y;
  cv::Mat view;
  cv::warpAffine(world_, view, to_world, cv::Size(options_.image_width, options_.image_height),
                 cv::INTER_LINEAR | cv::WARP_INVERSE_MAP, cv::BORDER_REFLECT);
  view.convertTo(view, CV_8U, frame.gain, frame.bias);
  cv::Mat noise(view.size(), CV_16S);
  cv::RNG noise_rng(static_cast<uint64_t>(options_.seed) * 1000003u + index);
  noise_rng.fill(noise, cv::RNG::NORMAL, 0, 2.0);
  cv::Mat noisy;
  view.convertTo(noisy, CV_16S);
  noisy += noise;
  noisy.convertTo(view, CV_8U);
  cv::Mat color;
  cv::cvtColor(view, color, cv::COLOR_GRAY2BGR);
  return color;
}

cv::Mat SyntheticRoute::RenderGray(int index) const {
  cv::Mat gray;
  cv::cvtColor(Render(index), gray, cv::COLOR_BGR2GRAY);
  return gray;
}

bool SyntheticRoute::IsLoop(int query, int match) const {
  const Frame& a = frames_.at(query);
  const Frame& b = frames_.at(match);
  if (match >= query || !a.in_loop || !b.in_loop || a.visit == b.visit) return false;
  double distance = std::fabs((a.x + a.dx) - (b.x + b.dx));
  distance = std::min(distance, loop_length_ - distance);  // the loop closes on itself
  return distance <= options_.same_place_fraction * options_.image_width;
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

void SyntheticRoute::Write(const std::string& folder) const {
  const std::string images = folder + "/images";
  std::error_code error;
  std::filesystem::create_directories(images, error);
  if (error) throw InputError(images, "cannot create the folder (" + error.message() + ")");
  for (int index = 0; index < size(); ++index) {
    const std::string path = images + "/" + std::to_string(index + 1) + ".png";
    if (!cv::imwrite(path, Render(index))) throw InputError(path, "cannot write the image");
  }
  const std::string csv_path = folder + "/ground_truth_pairs.csv";
  std::ofstream csv(csv_path);
  csv << "query,match\n";
  for (const auto& [query, match] : GroundTruthPairs()) {
    csv << query + 1 << ".png," << match + 1 << ".png\n";
  }
  csv.close();  // the last buffer's write is checked too
  if (!csv) throw InputError(csv_path, "cannot write the ground truth");
}

}  // namespace memloop
