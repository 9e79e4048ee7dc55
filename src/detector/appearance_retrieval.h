// Retrieval by appearance (memloop; docs/design.md): what the detector does with the
// AppearanceIndex beyond searching it, describing new locations and restoring it on resume, with
// the map file kept in step.
#pragma once

#include <opencv2/core.hpp>

#include "detector/memory.h"
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

// Resuming: the map's vocabulary and the descriptions of its locations in memory and LTM (LTM's
// searched). Throws DatabaseError when they are damaged.
void ReloadAppearance(LtmDatabase& database, const Memory& memory, const LongTermMemory& ltm,
                      AppearanceIndex& appearance);

}  // namespace memloop
