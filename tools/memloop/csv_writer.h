#pragma once

#include <fstream>
#include <string>

#include "memloop/result.h"

namespace memloop::cli {

// The per-image results of a run, one row per processed image, for plotting and `memloop eval`.
// Columns: see docs/cli.md. Times are in milliseconds.
class CsvWriter {
 public:
  // Throws InputError when `path` cannot be written.
  explicit CsvWriter(const std::string& path);
  void Write(const std::string& image_name, const Result& result);

 private:
  std::string path_;
  std::ofstream out_;
};

}  // namespace memloop::cli
