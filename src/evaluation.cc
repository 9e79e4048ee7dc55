#include "memloop/evaluation.h"

namespace memloop {

PrecisionRecall Evaluate(const std::vector<Detection>& detections,
                         const std::function<bool(ImageIndex, ImageIndex)>& is_loop,
                         int image_count) {
  PrecisionRecall result;
  for (ImageIndex query = 0; query < image_count; ++query) {
    for (ImageIndex match = 0; match < query; ++match) {
      if (is_loop(query, match)) {
        ++result.loop_images;
        break;
      }
    }
  }
  for (const Detection& detection : detections) {
    ++result.detections;
    bool correct = false;
    for (ImageIndex match : detection.matched_images) {
      correct = correct || (match < detection.query && is_loop(detection.query, match));
    }
    ++(correct ? result.true_positives : result.false_positives);
  }
  return result;
}

}  // namespace memloop
