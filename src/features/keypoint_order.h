#pragma once

#include "memloop/feature_extractor.h"

namespace memloop {

// Keypoints (and their descriptor rows) in a total order: strongest first, then by position,
// size and angle. OpenCV's detectors gather keypoints from parallel workers, so their order can
// vary between runs; this makes signatures repeatable.
Features SortStrongestFirst(Features features);

}  // namespace memloop
