#include "session.h"

#include <fmt/format.h>
#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>
#include <thread>

#include "command_files.h"
#include "interrupt.h"
#include "memloop/detector.h"
#include "memloop/errors.h"
#include "memloop/evaluation.h"
#include "memloop/realtime.h"
#include "memloop/run_csv.h"
#include "progress.h"
#include "storage/map_writer_lock.h"

namespace memloop::cli {
namespace {

namespace fs = std::filesystem;

constexpr const char* kTemporaryPrefix = "memloop-";

bool ProcessIsGone(long pid) { return kill(static_cast<pid_t>(pid), 0) != 0 && errno == ESRCH; }

// Temporary maps of runs that were killed (kill -9 leaves no chance to remove them):
// "memloop-<pid>-<n>.db*" whose process is gone.
void RemoveOrphanedTemporaryMaps(const fs::path& folder) {
  std::error_code error;
  for (const auto& entry : fs::directory_iterator(folder, error)) {
    const std::string name = entry.path().filename().string();
    if (name.rfind(kTemporaryPrefix, 0) != 0 || !entry.is_regular_file(error)) continue;
    char* end = nullptr;
    const long pid = std::strtol(name.c_str() + std::strlen(kTemporaryPrefix), &end, 10);
    if (end == nullptr || *end != '-' || pid <= 0 || name.find(".db") == std::string::npos)
      continue;
    if (pid != getpid() && ProcessIsGone(pid)) fs::remove(entry.path(), error);
  }
}

// A map file and its WAL files.
void RemoveMap(const std::string& path) {
  std::error_code ignored;
  for (const char* suffix : {"", "-wal", "-shm", "-lock"}) fs::remove(path + suffix, ignored);
}

// A map file in the temporary folder, removed (with its WAL files) when this goes: at the end,
// on an error and after SIGINT/SIGTERM; those of killed runs go at the next run's start.
class TemporaryDatabase {
 public:
  TemporaryDatabase() {
    static std::atomic<int> counter{0};
    const fs::path folder = fs::temp_directory_path();
    RemoveOrphanedTemporaryMaps(folder);
    path_ = (folder / (kTemporaryPrefix + std::to_string(getpid()) + "-" +
                       std::to_string(counter++) + ".db"))
                .string();
  }
  ~TemporaryDatabase() { RemoveMap(path_); }
  const std::string& path() const { return path_; }

 private:
  std::string path_;
};

// The CSV and the map are outputs (the map an input too when localizing against it), and neither
// is an input nor the other, however spelled.
void CheckOutputs(const std::string& csv_path, const std::string& database_path, bool localizing,
                  const SessionOptions& session) {
  std::vector<NamedPath> inputs = session.inputs;
  std::vector<NamedPath> outputs;
  for (NamedPath& file : MapFiles(database_path, "the map (--db)")) {
    (localizing ? inputs : outputs).push_back(std::move(file));
  }
  outputs.push_back({"--out", csv_path});  // the one refused when it is the map
  CheckOutputsAreNotInputs(inputs, outputs);
}

// Runs a write of the CSV; when it fails (a full disk), the map closes at the checkpoint of the
// image before, which the CSV holds: the map is never ahead of the CSV, and --resume goes on
// from the first image whose row is missing.
template <typename Write>
void KeepMapBehind(Detector& detector, Write write) {
  try {
    write();
  } catch (...) {
    detector.CloseAtLastCheckpoint();
    throw;
  }
}

// --resume: the input must be the one the map's last session was made from. Names are compared
// where both sides know them (a folder or dataset; not a video or a camera, nor a map made before
// memloop recorded images).
void CheckInputContinues(const ImageSequence& sequence, const MapProgress& progress,
                         const std::string& database_path, const std::string& input) {
  const MapSession& session = progress.last_session;
  if (session.id < 0) return;
  // The input's frame 0 is the session's first image: a later session's first recorded one, the
  // map's image 0 for the first session (a map upgraded from format 4 records images from later).
  const ImageIndex start = session.id == 0 ? 0 : session.first_image;
  const int held = session.last_image - start + 1;
  const std::string label = input.empty() ? "the input" : input;
  if (sequence.size() >= 0 && sequence.size() < held) {
    throw InputError(label,
                     fmt::format("holds {} images, where the map {} holds {} of it (images "
                                 "{} to {}): not the input the map was made from",
                                 sequence.size(), database_path, held, start, session.last_image));
  }
  const std::string first = sequence.NameOf(session.first_image - start);
  const std::string last = sequence.NameOf(held - 1);
  if (first.empty() || session.first_name.empty()) return;
  if (first != session.first_name || last != session.last_name) {
    throw InputError(
        label, fmt::format("does not continue the map {}: its session {} began with '{}' and "
                           "holds up to '{}', where this input's images {} and {} are '{}' and "
                           "'{}' (give the input it was made from, or use --new-session)",
                           database_path, session.id, session.first_name, session.last_name,
                           session.first_image - start + 1, held, first, last));
  }
}

}  // namespace

SessionReport RunSession(ImageSequence& sequence, const Options& options,
                         const std::string& database_path, const std::string& csv_path,
                         const SessionOptions& session) {
  const bool localizing = options.memory.localization != 0;
  const bool extends = session.resume || session.new_session;  // an existing map
  if (localizing && (database_path.empty() || extends)) {
    throw ParameterError("memory.localization",
                         database_path.empty()
                             ? "memory.localization=1 needs the map to localize against (--db)"
                             : std::string(session.resume ? "--resume" : "--new-session") +
                                   " extends the map, memory.localization=1 does not: use one "
                                   "or the other");
  }
  if (session.resume && session.new_session) {
    throw ParameterError("--new-session",
                         "--resume goes on with the map's last session, "
                         "--new-session starts another: use one or the other");
  }
  if (extends && database_path.empty()) {
    throw ParameterError(session.resume ? "--resume" : "--new-session",
                         "needs the map to extend (--db)");
  }
  if (session.realtime_priority != kUsualScheduling) {  // out of range (0 too) is refused
    try {
      SetThisThreadsRealTimePriority(session.realtime_priority);
    } catch (const Error& error) {
      throw ParameterError("--realtime-priority", error.what());
    }
    std::cout << "per-image threads at real-time priority " << session.realtime_priority
              << " (SCHED_FIFO)" << std::endl;
  }
  // Outputs are checked before anything is created or opened for writing: a refused run leaves
  // no file behind and changes none.
  CheckOutputs(csv_path, database_path, localizing, session);
  if (extends || localizing) {
    ThrowIfBeingWritten(database_path, localizing       ? "localize against it"
                                       : session.resume ? "resume"
                                                        : "add a session to it");
  }
  if (!csv_path.empty() && !session.resume) RunCsvWriter::CheckCanCreate(csv_path);
  if (session.resume) {
    // A map whose checkpoint cannot be read is refused by the detector below, saying why.
    std::optional<MapProgress> progress;
    try {
      progress = ReadMapProgress(database_path);
    } catch (const DatabaseError&) {
      if (!csv_path.empty()) throw;
    }
    if (progress) {
      CheckInputContinues(sequence, *progress, database_path, session.input);
      // A later session's CSV holds that session's images only.
      const long long images = progress->last_session.id > 0 ? progress->last_session.images
                                                             : progress->images_processed;
      // A run killed after the map's last checkpoint has up to two checkpoints' images more in
      // its CSV (options.h, memory.checkpoint_interval), with T_time on skipped ones too.
      const long long rows_after =
          2LL * std::max(1, options.memory.checkpoint_interval) +
          (options.memory.time_limit_ms > 0 ? options.memory.checkpoint_max_skipped : 0);
      if (!csv_path.empty()) {
        RunCsvWriter::CheckContinues(csv_path, progress->last_image, images, rows_after);
      }
    }
  }
  if (session.new_session) ReadMapProgress(database_path);  // refused before anything is opened
  std::unique_ptr<TemporaryDatabase> temporary;
  if (database_path.empty()) temporary = std::make_unique<TemporaryDatabase>();
  const std::string& map_path = temporary ? temporary->path() : database_path;
  auto detector = std::make_unique<Detector>(options, map_path,
                                             session.resume        ? MapMode::kResume
                                             : session.new_session ? MapMode::kNewSession
                                                                   : MapMode::kNew);
  if (session.fleet_catch_up) {
    const size_t places = detector->CatchUpWithFleet();
    std::cout << "fleet: " << places << " places of other robots joined the map" << std::endl;
  }
  std::unique_ptr<RunCsvWriter> csv;
  if (localizing) {
    std::cout << "localizing against " << database_path << " (" << detector->images_processed()
              << " images in the map; it is not modified)" << std::endl;
  }
  // The input's frame 0 is the session's first image.
  const ImageIndex first_image = detector->session_first_image();
  if (session.new_session) {
    std::cout << "new session " << detector->session() << " in " << database_path
              << ": its images from image " << first_image << " on ("
              << detector->images_processed() << " images in the map)" << std::endl;
  }
  if (session.resume) {
    std::cout << "resuming " << database_path << " after image " << detector->last_image() << " ("
              << detector->images_processed() << " images in the map";
    if (detector->session() > 0) {
      std::cout << "; session " << detector->session() << " from image " << first_image;
    }
    std::cout << ")" << std::endl;
    sequence.SkipTo(detector->last_image() + 1 - first_image);
    if (!csv_path.empty()) {
      csv = std::make_unique<RunCsvWriter>(csv_path, detector->last_image());
    }
  } else if (!csv_path.empty()) {
    try {  // a new map's or a new session's CSV
      csv = std::make_unique<RunCsvWriter>(csv_path);
    } catch (const Error&) {
      detector.reset();
      if (!temporary && !localizing && !extends) RemoveMap(map_path);  // this run's new, empty map
      throw;
    }
  }

  SessionReport report;
  report.time_limit_ms = options.memory.time_limit_ms;
  report.time_target = options.memory.time_target;
  int loop_closures = 0;
  Progress progress(sequence.size());
  const InterruptWatch interrupt;
  Frame frame;
  std::optional<std::chrono::steady_clock::time_point> handed;  // the last frame's, when paced
  while (interrupt.signal() == 0 && sequence.Next(&frame)) {
    if (frame.dropped > 0 && report.dropped == 0) {
      progress.Print(
          "warning: frames are dropped: the detector is slower than the camera "
          "(--rate HZ takes frames at a pace it keeps)",
          stderr);
    }
    report.dropped += frame.dropped;
    if (!frame.error.empty()) {
      progress.Print(fmt::format("warning: skipping {}: {}", frame.name, frame.error), stderr);
      ++report.skipped;
      continue;
    }
    ImageInfo info;
    info.index = first_image + frame.index;
    info.name = frame.name;
    info.timestamp = frame.timestamp;
    if (session.pace_hz > 0) {
      if (handed) {
        std::this_thread::sleep_until(
            *handed + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                          std::chrono::duration<double>(1.0 / session.pace_hz)));
      }
      handed = std::chrono::steady_clock::now();
    }
    Result result = detector->Process(frame.image, frame.depth, info);
    for (const std::string& notice : result.map_notices)
      progress.Print("memloop: " + notice, stderr);
    if (result.HasLoopClosure()) {
      ++loop_closures;
      if (session.print_loop_closures) progress.Print(result.Brief(), stdout);
    }
    if (csv) KeepMapBehind(*detector, [&] { csv->Write(frame.name, result); });
    report.names.push_back(frame.name);
    report.results.push_back(std::move(result));
    progress.Update(frame.index + 1, loop_closures);  // of the input
  }
  report.interrupted_by = interrupt.signal();
  if (csv) KeepMapBehind(*detector, [&] { csv->Close(); });
  detector->Close();
  return report;
}

void ThrowIfInterrupted(const SessionReport& report, const std::string& database_path) {
  if (report.interrupted_by == 0) return;
  const std::string last =
      report.results.empty() ? "none" : std::to_string(report.results.back().image_index);
  std::string message = "interrupted by " + SignalName(report.interrupted_by) + " after image " +
                        last + "; the results are complete up to it";
  if (!database_path.empty()) {
    message += ", and the map " + database_path + " can go on with --resume";
  }
  throw Interrupted(report.interrupted_by, message);
}

namespace {

// A second line when T_time is under what the stages WM does not drive need (issue 37): the
// transfer cannot hold such a bound, and the user is told the floor instead of finding out.
std::string TightTimeLimitWarning(const SessionReport& report) {
  if (report.time_limit_ms <= 0 || report.results.empty()) return "";
  std::vector<double> fixed;
  for (const Result& result : report.results) {
    fixed.push_back(std::max(0.0, result.times.total_ms - result.times.WmStagesMs()));
  }
  std::nth_element(fixed.begin(), fixed.begin() + fixed.size() / 2, fixed.end());
  const double floor_ms = fixed[fixed.size() / 2];
  const double target_ms = report.time_target * report.time_limit_ms;
  if (floor_ms <= target_ms) return "";
  return fmt::format(
      "\nwarning: T_time {:g} ms is under this machine's floor: the stages WM does not drive "
      "(features, quantization, retrieval, checkpoint) take a median {:.1f} ms, over the time "
      "target ({:g} x T_time = {:.1f} ms), so transferring WM cannot keep iterations under T_time; "
      "give T_time {:.0f} ms or more (memloop eval --time-limit-ms shows the floor)",
      report.time_limit_ms, floor_ms, report.time_target, target_ms,
      std::ceil(floor_ms / report.time_target));
}

// A line when iterations passed T_time while the detector's thread was mostly off the CPU (issue
// 37): other programs at the same priority share the cores, and no transfer makes up for the
// time the images wait for them.
std::string CpuWaitWarning(const SessionReport& report) {
  if (report.time_limit_ms <= 0) return "";
  int over = 0;
  std::vector<std::pair<double, double>> cpu_and_wall;
  for (const Result& result : report.results) {
    over += result.times.total_ms > report.time_limit_ms;
    cpu_and_wall.emplace_back(result.times.cpu_ms, result.times.total_ms);
  }
  const double share = MedianCpuShare(cpu_and_wall);
  if (over == 0 || share < 0 || share >= kWaitedCpuShare) return "";
  return fmt::format(
      "\nwarning: {} iterations over T_time {:g} ms while the detector's thread was on the CPU "
      "a median {:.0f}% of each iteration: other programs share the cores and the images wait "
      "for them, whatever WM holds; --realtime-priority N gives the detector the CPU first "
      "(docs/cli.md), or give T_time more room",
      over, report.time_limit_ms, 100 * share);
}

}  // namespace

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
  char text[400];
  std::snprintf(text, sizeof(text),
                "images: %zu processed, %d skipped; loop closures: %d; iteration time: median "
                "%.1f ms, max %.1f ms; max WM size: %d locations; max dictionary size: %d words",
                report.results.size(), report.skipped, loop_closures, median, max, max_wm,
                max_words);
  std::string summary = text;
  if (report.dropped > 0) summary += fmt::format("; camera frames dropped: {}", report.dropped);
  return summary + TightTimeLimitWarning(report) + CpuWaitWarning(report);
}

}  // namespace memloop::cli
