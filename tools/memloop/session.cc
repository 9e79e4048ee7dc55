#include "session.h"

#include <spdlog/spdlog.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>

#include "memloop/detector.h"
#include "memloop/run_csv.h"
#include "progress.h"

namespace memloop::cli {
namespace {

namespace fs = std::filesystem;

// A map file in the temporary folder, removed (with its WAL files) when this goes.
class TemporaryDatabase {
 public:
  TemporaryDatabase() {
    static std::atomic<int> counter{0};
    path_ = (fs::temp_directory_path() /
             ("memloop-" + std::to_string(getpid()) + "-" + std::to_string(counter++) + ".db"))
                .string();
  }
  ~TemporaryDatabase() {
    std::error_code ignored;
    for (const char* suffix : {"", "-wal", "-shm"}) fs::remove(path_ + suffix, ignored);
  }
  const std::string& path() const { return path_; }

 private:
  std::string path_;
};

}  // namespace

SessionReport RunSession(ImageSequence& sequence, const Options& options,
                         const std::string& database_path, const std::string& csv_path,
                         bool resume) {
  std::unique_ptr<TemporaryDatabase> temporary;
  if (database_path.empty()) temporary = std::make_unique<TemporaryDatabase>();
  Detector detector(options, temporary ? temporary->path() : database_path,
                    resume ? MapMode::kResume : MapMode::kNew);
  std::unique_ptr<RunCsvWriter> csv;
  if (resume) {
    std::cout << "resuming " << database_path << " after image " << detector.last_image() << " ("
              << detector.images_processed() << " images in the map)" << std::endl;
    sequence.SkipTo(detector.last_image() + 1);
    if (!csv_path.empty()) csv = std::make_unique<RunCsvWriter>(csv_path, detector.last_image());
  } else if (!csv_path.empty()) {
    csv = std::make_unique<RunCsvWriter>(csv_path);
  }

  SessionReport report;
  int loop_closures = 0;
  Progress progress(sequence.size());
  Frame frame;
  while (sequence.Next(&frame)) {
    if (!frame.error.empty()) {
      spdlog::warn("skipping {}: {}", frame.name, frame.error);
      ++report.skipped;
      continue;
    }
    Result result = detector.Process(frame.image, frame.index);
    loop_closures += result.HasLoopClosure();
    if (csv) csv->Write(frame.name, result);
    report.names.push_back(frame.name);
    report.results.push_back(std::move(result));
    progress.Update(frame.index + 1, loop_closures);
  }
  detector.Close();
  if (csv) csv->Close();
  return report;
}

std::string Summary(const SessionReport& report) {
  std::vector<double> times;
  int loop_closures = 0;
  int max_wm = 0;
  int max_words = 0;
  for (const Result& result : report.results) {
    times.push_back(result.times.total_ms);
    loop_closures += result.HasLoopClosure();
    max_wm = std::max(max_wm, result.wm_size);
    max_words = std::max(max_words, result.dictionary_size);
  }
  std::sort(times.begin(), times.end());
  const double median = times.empty() ? 0 : times[times.size() / 2];
  const double max = times.empty() ? 0 : times.back();
  char text[320];
  std::snprintf(text, sizeof(text),
                "images: %zu processed, %d skipped; loop closures: %d; iteration time: median "
                "%.1f ms, max %.1f ms; max WM size: %d locations; max dictionary size: %d words",
                report.results.size(), report.skipped, loop_closures, median, max, max_wm,
                max_words);
  return text;
}

}  // namespace memloop::cli
