// Repeatability and matching score of each feature backend under known transformations, on the
// images of a folder (default: ../shared/datasets/rtabmap_samples/images, every 10th image) or on
// generated textures when the folder is absent. Prints a Markdown table.
// Backends: surf (defaults), surf h400 (Hessian threshold 400: about as many keypoints as SIFT),
// sift, orb. Usage: feature_matching [FOLDER] [--set NAME=VALUE ...] (parameters as memloop's)
#include <cstdio>
#include <filesystem>
#include <map>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "features/matching_score.h"
#include "memloop/image_sequence.h"
#include "memloop/params.h"
#include "memloop/synthetic_route.h"

int main(int argc, char** argv) {
  using namespace memloop;
  std::string folder = "../shared/datasets/rtabmap_samples/images";
  Options options;
  for (int i = 1; i < argc; ++i) {
    const std::string argument = argv[i];
    if (argument == "--set" && i + 1 < argc) {
      SetParameter(options, argv[++i]);
    } else {
      folder = argument;
    }
  }
  std::vector<cv::Mat> images;
  std::string source = folder;
  if (std::filesystem::is_directory(folder)) {
    const auto names = ListFolder(folder);
    for (size_t i = 0; i < names.size(); i += 10) {
      images.push_back(cv::imread(folder + "/" + names[i], cv::IMREAD_GRAYSCALE));
    }
  } else {
    source = "generated textures (512x384)";
    SyntheticRouteOptions route_options;
    route_options.image_width = 512;
    route_options.image_height = 384;
    const SyntheticRoute route(route_options);
    for (int i = 0; i < 8; ++i) {
      cv::Mat gray;
      cv::cvtColor(route.Render(i * 11), gray, cv::COLOR_BGR2GRAY);
      images.push_back(gray);
    }
  }
  std::printf("Images: %zu from %s; radius 2.5 px, ratio 0.8\n\n", images.size(), source.c_str());
  std::printf("| transformation | backend | keypoints | repeatability | matching score |\n");
  std::printf("| --- | --- | --- | --- | --- |\n");
  for (const auto& transformation : StandardTransformations(images.front().size())) {
    for (const std::string backend : {"surf", "surf h400", "sift", "orb"}) {
      FeatureOptions feature_options = options.features;
      feature_options.type = backend.substr(0, 4);
      if (backend == "surf h400") feature_options.surf_hessian_threshold = 400;
      const auto extractor = FeatureExtractor::Create(feature_options);
      double keypoints = 0, repeatability = 0, matching = 0;
      for (const cv::Mat& image : images) {
        const MatchingScore score = EvaluateMatching(*extractor, image, transformation);
        keypoints += score.keypoints;
        repeatability += score.repeatability;
        matching += score.matching_score;
      }
      const double n = static_cast<double>(images.size());
      std::printf("| %s | %s | %.0f | %.2f | %.2f |\n", transformation.name.c_str(),
                  backend.c_str(), keypoints / n, repeatability / n, matching / n);
    }
  }
  return 0;
}
