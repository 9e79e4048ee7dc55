// Precision and recall of loop-closure detections against ground truth (paper Sec. IV, after
// Cummins & Newman): a detection is true when the query image and any image of the matched
// location form a ground-truth pair (a location that absorbed others stands for all of their
// images); recall counts the images that have at least one ground-truth match.
#pragma once

#include <functional>
#include <vector>

#include "memloop/types.h"

namespace memloop {

struct Detection {
  ImageIndex query = kNoImage;
  std::vector<ImageIndex> matched_images;
};

struct PrecisionRecall {
  int detections = 0;
  int true_positives = 0;
  int false_positives = 0;
  int loop_images = 0;  // images with at least one ground-truth match
  double Precision() const { return detections == 0 ? 1.0 : double(true_positives) / detections; }
  double Recall() const { return loop_images == 0 ? 0.0 : double(true_positives) / loop_images; }
};

// `is_loop(query, match)`: ground truth for match < query. `image_count`: images of the sequence.
PrecisionRecall Evaluate(const std::vector<Detection>& detections,
                         const std::function<bool(ImageIndex, ImageIndex)>& is_loop,
                         int image_count);

}  // namespace memloop
