#pragma once

#include <string>
#include <vector>

#include "memloop/image_sequence.h"
#include "memloop/options.h"
#include "memloop/result.h"

namespace memloop::cli {

struct SessionReport {
  std::vector<Result> results;  // one per processed image
  std::vector<std::string> names;
  int skipped = 0;  // unreadable images, warned and skipped
};

// Feeds every frame of `sequence` to a Detector writing its map to `database_path` ("" = a
// temporary file removed afterwards), and the per-image rows to `csv_path` ("" = none). With
// `resume`, the map in `database_path` goes on from its last checkpoint: frames up to the image
// it holds are skipped, and the CSV keeps its rows up to that image.
SessionReport RunSession(ImageSequence& sequence, const Options& options,
                         const std::string& database_path, const std::string& csv_path,
                         bool resume = false);

// "images: 130 processed, 0 skipped; loop closures: 52; iteration time: median 12.1 ms, max ..."
std::string Summary(const SessionReport& report);

}  // namespace memloop::cli
