#include "synthetic/synthetic_view.h"

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "memloop/errors.h"
#include "synthetic/ros2_bag_writer.h"
#include "util/output_files.h"

namespace memloop {
namespace {

// Blocks side by side along the texture, each a gray of its own (the smooth noise shows through
// a third) from its top to the bottom.
void DrawFacades(cv::Mat& texture, cv::RNG& rng) {
  for (int x = 0; x < texture.cols;) {
    const int width = std::min(rng.uniform(40, 140), texture.cols - x);
    const int top = rng.uniform(texture.rows / 20, texture.rows * 3 / 5);
    const cv::Mat block = texture(cv::Rect(x, top, width, texture.rows - top));
    cv::addWeighted(block, 1.0 / 3, block, 0, rng.uniform(20, 236) * 2.0 / 3, block);
    x += width;
  }
}

}  // namespace

cv::Mat MakeTexture(int width, int height, cv::RNG& rng, bool facades) {
  cv::Mat coarse(height / 16 + 1, width / 16 + 1, CV_8U);
  rng.fill(coarse, cv::RNG::UNIFORM, 60, 190);
  cv::Mat texture;
  cv::resize(coarse, texture, cv::Size(width, height), 0, 0, cv::INTER_CUBIC);
  if (facades) DrawFacades(texture, rng);
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

ViewJitter ViewJitter::Random(cv::RNG& rng) {
  ViewJitter jitter;
  jitter.dx = rng.uniform(-12.0, 12.0);
  jitter.dy = rng.uniform(-8.0, 8.0);
  jitter.scale = rng.uniform(0.95, 1.05);
  jitter.angle_degrees = rng.uniform(-3.0, 3.0);
  jitter.gain = rng.uniform(0.8, 1.2);
  jitter.bias = rng.uniform(-20.0, 20.0);
  return jitter;
}

cv::Mat RenderView(const cv::Mat& world, double x, double y, const ViewJitter& jitter, int width,
                   int height, uint64_t noise_seed) {
  // Output pixel -> world pixel: rotation and scale about the image centre, then the offset.
  const cv::Point2f centre(width / 2.0f, height / 2.0f);
  cv::Mat to_world = cv::getRotationMatrix2D(centre, jitter.angle_degrees, 1.0 / jitter.scale);
  to_world.at<double>(0, 2) += x + jitter.dx;
  to_world.at<double>(1, 2) += y + jitter.dy;
  cv::Mat view;
  cv::warpAffine(world, view, to_world, cv::Size(width, height),
                 cv::INTER_LINEAR | cv::WARP_INVERSE_MAP, cv::BORDER_REFLECT);
  view.convertTo(view, CV_8U, jitter.gain, jitter.bias);
  cv::Mat noise(view.size(), CV_16S);
  cv::RNG noise_rng(noise_seed);
  noise_rng.fill(noise, cv::RNG::NORMAL, 0, 2.0);
  cv::Mat noisy;
  view.convertTo(noisy, CV_16S);
  noisy += noise;
  noisy.convertTo(view, CV_8U);
  cv::Mat color;
  cv::cvtColor(view, color, cv::COLOR_GRAY2BGR);
  return color;
}

GeneratedLayout ParseGeneratedLayout(const std::string& name) {
  if (name == "images") return GeneratedLayout::kImages;
  if (name == "tum") return GeneratedLayout::kTum;
  if (name == "ros2-bag") return GeneratedLayout::kRos2Bag;
  throw ParameterError("--layout", "--layout: '" + name + "' is not one of images, tum, ros2-bag");
}

namespace {

constexpr double kFirstStamp = 1000;  // seconds: the generated camera's clock at frame 0
constexpr double kFramePeriod = 0.1;  // 10 Hz
constexpr const char* kBagTopic = "/camera/image_raw";

void CreateFolder(const std::string& folder) {
  std::error_code error;
  std::filesystem::create_directories(folder, error);
  if (error) throw InputError(folder, "cannot create the folder (" + error.message() + ")");
}

}  // namespace

double GeneratedStamp(int index) { return kFirstStamp + kFramePeriod * index; }

std::string FrameName(GeneratedLayout layout, int index) {
  const std::string file = std::to_string(index + 1) + ".png";
  if (layout == GeneratedLayout::kImages) return file;
  if (layout == GeneratedLayout::kTum) return "rgb/" + file;
  char name[96];
  std::snprintf(name, sizeof(name), "%s %.6f", kBagTopic, GeneratedStamp(index));
  return name;  // as the bag reader names a frame: topic and recording time
}

void WriteSequence(const std::string& folder, int size, const std::function<cv::Mat(int)>& render,
                   const std::vector<std::pair<int, int>>& pairs,
                   const std::function<void(int)>& written, GeneratedLayout layout) {
  const bool tum = layout == GeneratedLayout::kTum;
  const std::string images = folder + (tum ? "/rgb" : "/images");
  const std::string bag = folder + "/ros2_bag";
  const std::string csv_path = folder + "/ground_truth_pairs.csv";
  // A folder that holds what this would write is kept as it is: it may be a user's data set.
  std::vector<std::string> targets = {layout == GeneratedLayout::kRos2Bag ? bag : images, csv_path};
  if (tum) {
    for (const char* file : {"/rgb.txt", "/depth", "/depth.txt", "/groundtruth.txt",
                             "/odometry.txt", "/camera.conf"}) {
      targets.push_back(folder + file);
    }
  }
  for (const std::string& path : targets) {
    std::error_code error;
    if (std::filesystem::exists(path, error) &&
        !(std::filesystem::is_directory(path, error) && std::filesystem::is_empty(path, error))) {
      throw InputError(path,
                       "exists: generate writes a new sequence and overwrites nothing; "
                       "give a new or empty folder");
    }
  }
  if (layout == GeneratedLayout::kRos2Bag) {
    CreateFolder(folder);
    std::vector<BagImage> frames;
    for (int index = 0; index < size; ++index) {
      const double stamp = GeneratedStamp(index);
      frames.push_back({render(index), stamp, stamp});
      if (written) written(index + 1);
    }
    WriteRos2Bag(bag, kBagTopic, frames, BagEncoding::kBgr8);
  } else {
    CreateFolder(images);
    std::string listing = "# color images\n# generated by memloop\n# timestamp filename\n";
    for (int index = 0; index < size; ++index) {
      const std::string path = images + "/" + std::to_string(index + 1) + ".png";
      WriteWholeFile(
          path, "the image",
          [&](const std::string& temporary) {
            if (!cv::imwrite(temporary, render(index))) {
              throw InputError(path, "cannot write the image");
            }
          },
          /*sync=*/false);
      char line[96];
      std::snprintf(line, sizeof(line), "%.6f %s\n", GeneratedStamp(index),
                    FrameName(layout, index).c_str());
      listing += line;
      if (written) written(index + 1);
    }
    if (tum) WriteWholeFile(folder + "/rgb.txt", "the listing", listing);
  }
  std::string csv = "query,match\n";
  for (const auto& [query, match] : pairs) {
    csv += FrameName(layout, query) + "," + FrameName(layout, match) + "\n";
  }
  WriteWholeFile(csv_path, "the ground truth", csv);
}

}  // namespace memloop
