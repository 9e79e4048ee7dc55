// How well a feature backend survives a known image transformation (Mikolajczyk & Schmid's
// protocol, as the SURF paper uses): the test applies an affine transformation (or a photometric
// change) itself, so the true position of every keypoint in the second image is known.
#pragma once

#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "memloop/feature_extractor.h"

namespace memloop {

struct ImageTransformation {
  std::string name;
  cv::Matx23d warp = cv::Matx23d(1, 0, 0, 0, 1, 0);  // pixel of the first -> of the second
  cv::Size size;                                     // of the second image; empty: the same
  double gain = 1.0;                                 // intensity * gain
  double blur_sigma = 0;                             // Gaussian blur, pixels
  int jpeg_quality = 0;                              // 1-100: re-compressed; 0: not
};

// The transformations of the evaluation: rotation 30 degrees, scale 0.7, brightness +30% and
// -30%, Gaussian blur (sigma 2), JPEG re-compression (quality 40), for an image of `size`.
std::vector<ImageTransformation> StandardTransformations(cv::Size size);
cv::Mat ApplyTransformation(const cv::Mat& gray, const ImageTransformation& transformation);

struct MatchingScore {
  int keypoints = 0;          // keypoints of the first image whose true position lies in the second
  double repeatability = 0;   // fraction of those with a keypoint of the second within the radius
  double matching_score = 0;  // fraction whose nearest descriptor passes the ratio test and lies
                              // within the radius of the true position
};

MatchingScore EvaluateMatching(const FeatureExtractor& extractor, const cv::Mat& gray,
                               const ImageTransformation& transformation,
                               double radius_pixels = 2.5, double nndr_ratio = 0.8);

}  // namespace memloop
