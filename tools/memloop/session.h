#pragma once

#include <limits>
#include <string>
#include <vector>

#include "memloop/image_sequence.h"
#include "memloop/options.h"
#include "memloop/result.h"
#include "util/output_files.h"

namespace memloop::cli {

struct SessionReport {
  std::vector<Result> results;  // one per processed image
  std::vector<std::string> names;
  int skipped = 0;           // unreadable images, warned and skipped
  int interrupted_by = 0;    // SIGINT or SIGTERM that ended the run early, 0 if none
  long long dropped = 0;     // camera frames lost because the detector was slower
  double time_limit_ms = 0;  // the run's T_time and memory.time_target, for the summary's warning
  double time_target = 1;
};

// SessionOptions::realtime_priority when --realtime-priority is not given.
constexpr int kUsualScheduling = std::numeric_limits<int>::min();

struct SessionOptions {
  bool resume = false;              // go on with the map at the database path
  bool print_loop_closures = true;  // a line on stdout per loop closure, as it is found
  bool new_session = false;         // a new session in the map at the database path
  std::string input;                // names the input in errors ("" for a camera)
  // 1-99: the per-image threads under SCHED_FIFO at it; any other value given is refused.
  int realtime_priority = kUsualScheduling;
  double pace_hz = 0;           // > 0: frames handed over at most this many a second
  bool fleet_catch_up = false;  // Detector::CatchUpWithFleet before the first image
  // The files the command reads (its input, --config): neither the CSV nor the map may be one.
  std::vector<NamedPath> inputs;
};

// Feeds every frame of `sequence` to a Detector writing its map to `database_path` ("" = a
// temporary file removed afterwards), and the per-image rows to `csv_path` ("" = none), one
// flushed row per image. With `resume`, the map in `database_path` goes on from its last
// checkpoint: frames up to the image it holds are skipped, and the CSV keeps its rows up to that
// image; the input must continue the map's last session (its first and last images' names, when
// both are known). With `new_session`, the map gets a new session (MapMode::kNewSession) whose
// images are numbered after the map's. Outputs are checked before any is created. SIGINT/SIGTERM
// end the run after the current image, with the map closed (see interrupted_by). With
// `realtime_priority`, the calling thread is put under SCHED_FIFO before anything is created (a
// refusal is an Error), and the detector's threads inherit it (util/thread_priority.h). With
// `pace_hz`, a frame is handed to the detector one period after the previous one was, or once
// the detector is done with that one if later: a camera at that rate, the detector idle between
// its images, and no frame dropped.
SessionReport RunSession(ImageSequence& sequence, const Options& options,
                         const std::string& database_path, const std::string& csv_path,
                         const SessionOptions& session = {});

// After the summary is printed: throws Interrupted when a signal ended the run.
void ThrowIfInterrupted(const SessionReport& report, const std::string& database_path);

// "images: 130 processed, 0 skipped; loop closures: 52; iteration time: median 12.1 ms, max ..."
std::string Summary(const SessionReport& report);

}  // namespace memloop::cli
