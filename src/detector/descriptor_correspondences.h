// Keypoint correspondences between two views by their descriptors: what a loop closure's pose is
// fitted to. Shared word ids alone leave too few on a changed viewpoint (gp_walk_a: 5-7 for a
// quarter of the loop closures), where the keypoints' descriptors still agree.
#pragma once

#include <opencv2/core.hpp>
#include <vector>

#include "detector/word_correspondences.h"

namespace memloop {

class Dictionary;
struct Signature;

// Keypoints with one descriptor row each (CV_32F: L2 distance; CV_8U: Hamming) and, for an image
// given with depth, each one's 3-D point (image_view.h).
struct DescribedView {
  std::vector<cv::KeyPoint> keypoints;
  cv::Mat descriptors;
  std::vector<cv::Point3f> points;  // empty, or one per keypoint (z = 0: no depth there)
  cv::Size image_size;              // its image's, when known
  int size() const { return static_cast<int>(keypoints.size()); }
};

// A location's view as the map holds it: its keypoints, each described by its word's descriptor
// (within the dictionary's ratio test of the keypoint's own, or the keypoint's own when it made
// the word): the map keeps no descriptor twice.
DescribedView WordDescribedView(const Signature& signature, const Dictionary& dictionary);

// Pairs (a's keypoint, b's keypoint) that are each other's nearest neighbour and pass Lowe's
// ratio test both ways (nearest < `ratio` * second nearest), in a's keypoint order: deterministic.
// With a's points, each pair's point too (points_a).
WordCorrespondences MatchDescriptors(const DescribedView& a, const DescribedView& b,
                                     double ratio = 0.8);

}  // namespace memloop
