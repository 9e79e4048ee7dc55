// Retrieval by appearance (memloop; docs/design.md): what the detector does with the
// AppearanceIndex beyond searching it, describing new locations and restoring it on resume, with
// the map file kept in step.
#pragma once

#include <cstddef>
#include <opencv2/core.hpp>

#include "detector/memory.h"
#include "memloop/options.h"
#include "storage/long_term_memory.h"
#include "storage/ltm_database.h"
#include "vocabulary/appearance_index.h"

namespace memloop {

// The description of a new location whose features (`descriptors`) the dictionary quantized into
// `signature`, words from `first_new_word` on created by it. Those first join the vocabulary while
// it is not complete, and what joins is written to the map (the description is the caller's to
// write).
Appearance DescribeNewLocation(AppearanceIndex& appearance, LongTermMemory& ltm,
                               const Signature& signature, const cv::Mat& descriptors,
                               WordId first_new_word);

// The z the best LTM location needs to be retrieved by appearance among `searched` LTM
// locations: memory.appearance_min_z, or appearance_chance_multiple times sqrt(2 ln N) when that
// is more. sqrt(2 ln N) is how far the largest of N independent standard normal scores lies
// above their mean (extreme-value theory); measured here, the best chance z of an image that
// revisits nothing sits at 1.9-2.0 times it at its 99th percentile from N = 400 to 26,000.
double AppearanceMinZ(const MemoryOptions& options, size_t searched);

// Resuming: the map's vocabulary and the descriptions of its locations in memory and LTM (LTM's
// searched). Throws DatabaseError when they are damaged.
void ReloadAppearance(LtmDatabase& database, const Memory& memory, const LongTermMemory& ltm,
                      AppearanceIndex& appearance);

}  // namespace memloop
