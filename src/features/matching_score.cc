#include "features/matching_score.h"

#include <cmath>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

namespace memloop {

std::vector<ImageTransformation> StandardTransformations(cv::Size size) {
  const cv::Point2f centre(size.width / 2.0f, size.height / 2.0f);
  std::vector<ImageTransformation> list;
  ImageTransformation rotation;
  rotation.name = "rotation 30 deg";
  rotation.warp = cv::getRotationMatrix2D(centre, 30, 1.0);
  list.push_back(rotation);
  ImageTransformation scale;
  scale.name = "scale 0.7";
  scale.warp = cv::Matx23d(0.7, 0, 0, 0, 0.7, 0);
  scale.size = cv::Size(static_cast<int>(size.width * 0.7), static_cast<int>(size.height * 0.7));
  list.push_back(scale);
  ImageTransformation brighter;
  brighter.name = "brightness +30%";
  brighter.gain = 1.3;
  list.push_back(brighter);
  ImageTransformation darker;
  darker.name = "brightness -30%";
  darker.gain = 0.7;
  list.push_back(darker);
  ImageTransformation blur;
  blur.name = "Gaussian blur sigma 2";
  blur.blur_sigma = 2;
  list.push_back(blur);
  ImageTransformation jpeg;
  jpeg.name = "JPEG quality 40";
  jpeg.jpeg_quality = 40;
  list.push_back(jpeg);
  return list;
}

cv::Mat ApplyTransformation(const cv::Mat& gray, const ImageTransformation& transformation) {
  cv::Mat result;
  const cv::Size size = transformation.size.empty() ? gray.size() : transformation.size;
  cv::warpAffine(gray, result, cv::Mat(transformation.warp), size, cv::INTER_AREA,
                 cv::BORDER_CONSTANT, cv::Scalar(0));
  if (transformation.gain != 1.0) result.convertTo(result, CV_8U, transformation.gain);
  if (transformation.blur_sigma > 0) {
    cv::GaussianBlur(result, result, cv::Size(), transformation.blur_sigma);
  }
  if (transformation.jpeg_quality > 0) {
    std::vector<uchar> bytes;
    cv::imencode(".jpg", result, bytes, {cv::IMWRITE_JPEG_QUALITY, transformation.jpeg_quality});
    result = cv::imdecode(bytes, cv::IMREAD_GRAYSCALE);
  }
  return result;
}

MatchingScore EvaluateMatching(const FeatureExtractor& extractor, const cv::Mat& gray,
                               const ImageTransformation& transformation, double radius_pixels,
                               double nndr_ratio) {
  const cv::Mat second_image = ApplyTransformation(gray, transformation);
  const Features first = extractor.Extract(gray);
  const Features second = extractor.Extract(second_image);
  const int norm = extractor.Kind() == DescriptorKind::kFloat ? cv::NORM_L2 : cv::NORM_HAMMING;
  const cv::Rect inside(8, 8, second_image.cols - 16, second_image.rows - 16);
  const cv::Matx23d& warp = transformation.warp;
  MatchingScore score;
  int repeated = 0;
  int matched = 0;
  for (size_t i = 0; i < first.keypoints.size(); ++i) {
    const cv::Point2f& p = first.keypoints[i].pt;
    const cv::Point2f truth(static_cast<float>(warp(0, 0) * p.x + warp(0, 1) * p.y + warp(0, 2)),
                            static_cast<float>(warp(1, 0) * p.x + warp(1, 1) * p.y + warp(1, 2)));
    if (!inside.contains(truth)) continue;
    ++score.keypoints;
    double nearest_position = 1e30;
    double best = 1e30;
    double second_best = 1e30;
    int best_index = -1;
    for (size_t j = 0; j < second.keypoints.size(); ++j) {
      nearest_position =
          std::min<double>(nearest_position, cv::norm(second.keypoints[j].pt - truth));
      const double distance = cv::norm(first.descriptors.row(static_cast<int>(i)),
                                       second.descriptors.row(static_cast<int>(j)), norm);
      if (distance < best) {
        second_best = best;
        best = distance;
        best_index = static_cast<int>(j);
      } else if (distance < second_best) {
        second_best = distance;
      }
    }
    repeated += nearest_position <= radius_pixels;
    if (best_index >= 0 && best < nndr_ratio * second_best &&
        cv::norm(second.keypoints[best_index].pt - truth) <= radius_pixels) {
      ++matched;
    }
  }
  if (score.keypoints > 0) {
    score.repeatability = static_cast<double>(repeated) / score.keypoints;
    score.matching_score = static_cast<double>(matched) / score.keypoints;
  }
  return score;
}

}  // namespace memloop
