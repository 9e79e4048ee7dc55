// The detector's parts as its Options make them: what each component is given besides the
// options it shares, and which optional parts exist.
#pragma once

#include <memory>
#include <opencv2/core.hpp>

#include "memloop/feature_extractor.h"
#include "memloop/options.h"
#include "storage/long_term_memory.h"
#include "vocabulary/appearance_index.h"

namespace memloop {

// The 8-bit grey image features are extracted from; InputError for an empty image, another depth
// or another number of channels than 1, 3 (BGR) or 4 (BGRA).
cv::Mat ToGray(const cv::Mat& image);

// `options` once ValidateOptions accepts them.
const Options& Validated(const Options& options);

// The selection's options: T_minHyp within the WM budget.
FilterOptions SelectionOptions(const Options& options);

// The dictionary's options: a background rebuild is swapped in when ready with T_time on.
DictionaryOptions DictionaryOptionsOf(const Options& options);

// The index of retrieval by appearance (memory.appearance_retrieval), or null.
std::unique_ptr<AppearanceIndex> MakeAppearanceIndex(const Options& options,
                                                     const FeatureExtractor& extractor);

}  // namespace memloop
