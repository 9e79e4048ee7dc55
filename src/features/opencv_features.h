#pragma once

#include <opencv2/features2d.hpp>

#include "memloop/feature_extractor.h"

namespace memloop {

// Keypoints (and their descriptor rows) in a total order: strongest first, then by position,
// size and angle. OpenCV's detectors gather keypoints from parallel workers, so their order can
// vary between runs; this makes signatures repeatable.
Features SortStrongestFirst(Features features);

// An OpenCV detector-descriptor's features in that order; an image without keypoints gives an
// empty matrix of the right width and type (`dim` columns of `cv_type`). `upright`: every
// keypoint is described at angle 0 (the detector's orientations dropped, and keypoints it made
// once per dominant orientation, as SIFT does, kept once), as U-SURF.
Features DetectAndDescribe(cv::Feature2D& detector, const cv::Mat& gray, int dim, int cv_type,
                           bool upright = false);

}  // namespace memloop
