#include "detector/detector_setup.h"

#include <algorithm>
#include <opencv2/imgproc.hpp>

#include "memloop/errors.h"
#include "memloop/params.h"

namespace memloop {

cv::Mat ToGray(const cv::Mat& image) {
  if (image.empty()) throw InputError("image", "empty image");
  if (image.depth() != CV_8U) throw InputError("image", "not an 8-bit image");
  cv::Mat gray;
  switch (image.channels()) {
    case 1:
      return image;
    case 3:
      cv::cvtColor(image, gray, cv::COLOR_BGR2GRAY);
      return gray;
    case 4:
      cv::cvtColor(image, gray, cv::COLOR_BGRA2GRAY);
      return gray;
    default:
      throw InputError("image", "unsupported number of channels");
  }
}

const Options& Validated(const Options& options) {
  ValidateOptions(options);
  return options;
}

// WM never holds more than its budget: a larger T_minHyp would refuse every loop closure.
FilterOptions SelectionOptions(const Options& options) {
  FilterOptions selection = options.filter;
  if (options.memory.max_wm_locations > 0) {
    selection.min_hypotheses = std::min(selection.min_hypotheses, options.memory.max_wm_locations);
  }
  return selection;
}

// With T_time on, runs depend on the machine anyway: a forest rebuilt in the background is used as
// soon as it is ready, never waited for. With T_time off it is used at a fixed insertion count.
DictionaryOptions DictionaryOptionsOf(const Options& options) {
  DictionaryOptions dictionary = options.dictionary;
  dictionary.rebuild_swap_when_ready = options.memory.time_limit_ms > 0;
  return dictionary;
}

std::unique_ptr<AppearanceIndex> MakeAppearanceIndex(const Options& options,
                                                     const FeatureExtractor& extractor) {
  if (!options.memory.appearance_retrieval) return nullptr;
  return std::make_unique<AppearanceIndex>(extractor.Kind(), extractor.DescriptorDim(),
                                           options.memory.appearance_vocabulary, options.dictionary,
                                           options.memory.appearance_max_postings);
}

}  // namespace memloop
