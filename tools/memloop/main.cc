// memloop: real-time appearance-based loop closure detection with memory management.
// Subcommands: run, demo, generate, eval, report, inspect, export, view, params. Exit codes: 0 success; 1
// an error of input, map or output ("memloop: error: ..." names the file); 2 a command-line usage
// error; 130 / 143 a run stopped by SIGINT / SIGTERM (results and map complete up to the last
// image).
#include <malloc.h>

#include <CLI/CLI.hpp>
#include <cstdlib>
#include <iostream>
#include <opencv2/core/utils/logger.hpp>

#include "commands.h"
#include "interrupt.h"
#include "memloop/errors.h"
#include "memloop/params.h"

namespace memloop::cli {

Options WithSettings(Options options, const std::string& config_path,
                     const std::vector<std::string>& assignments) {
  if (!config_path.empty()) ApplyParameterFile(options, config_path);
  for (const std::string& assignment : assignments) SetParameter(options, assignment);
  return options;
}

CLI::Option* AddConfigOption(CLI::App& command, std::string* path) {
  return command.add_option(
      "--config", *path,
      "Parameter file: 'name = value' lines (or [section] then 'name = value'), # comments; "
      "applied after --preset, before --set");
}

CLI::Option* AddPresetOption(CLI::App& command, std::string* name) {
  return command.add_option(
      "--preset", *name,
      "Starting values: default (memloop's measured best), paper2011 (the paper's mechanisms as "
      "written), hand-held (a camera that rolls about its axis), day-night (places revisited "
      "under another light, in a --new-session of the map) or verified (loop closures under "
      "T_loop that geometry confirms, for a camera that moves); --set applies on top");
}

CLI::Option* AddRealtimePriorityOption(CLI::App& command, int* priority) {
  return command.add_option(
      "--realtime-priority", *priority,
      "Run the per-image threads under SCHED_FIFO at this priority (1-99; needs root, "
      "CAP_SYS_NICE or 'ulimit -r'): other programs then cannot delay an image; background "
      "threads (LTM writer, forest builds) stay behind. Default: the usual scheduling");
}

CLI::Option* AddPaceOption(CLI::App& command, double* hz) {
  return command
      .add_option("--pace", *hz,
                  "Hand frames to the detector at most HZ a second, as a camera at that rate (the "
                  "next one period after the last, or when the detector is done if later; none "
                  "dropped). Default: as fast as the detector goes")
      ->check(CLI::Validator(
          [](std::string& value) -> std::string {
            char* end = nullptr;
            const double hz = std::strtod(value.c_str(), &end);
            return *end == '\0' && hz > 0 ? ""
                                          : "must be a rate in Hz above 0, not '" + value + "'";
          },
          "HZ > 0"));
}

}  // namespace memloop::cli

int main(int argc, char** argv) {
  // One malloc arena for every thread (before any starts): memory the forest's background builds
  // free is then reused by all, not kept in the builders' arenas. 7,400 images at T_time 67 ms:
  // peak RSS 758-782 MB in 4 runs, against 766-929 MB (150 MB more in 2 of 5) with glibc's
  // default, for 3-6% more time (docs/scale.md). MALLOC_ARENA_MAX in the environment still wins.
  if (std::getenv("MALLOC_ARENA_MAX") == nullptr) mallopt(M_ARENA_MAX, 1);
  // memloop says itself, in one line, why a video or image cannot be read: OpenCV's and FFmpeg's
  // own warnings would come first and bury it. OPENCV_LOG_LEVEL / OPENCV_FFMPEG_LOGLEVEL set in
  // the environment still win, for debugging.
  if (std::getenv("OPENCV_LOG_LEVEL") == nullptr) {
    cv::utils::logging::setLogLevel(cv::utils::logging::LOG_LEVEL_SILENT);
  }
  setenv("OPENCV_FFMPEG_LOGLEVEL", "-8", /*overwrite=*/0);  // AV_LOG_QUIET
  CLI::App app{"memloop: real-time appearance-based loop closure detection (Labbe & Michaud 2011)"};
  app.require_subcommand(1);
  memloop::cli::AddRunCommand(app);
  memloop::cli::AddDemoCommand(app);
  memloop::cli::AddParamsCommand(app);
  memloop::cli::AddEvalCommand(app);
  memloop::cli::AddReportCommand(app);
  memloop::cli::AddInspectCommand(app);
  memloop::cli::AddExportCommand(app);
  memloop::cli::AddViewCommand(app);
  memloop::cli::AddFleetCommand(app);
  // CLI11 says only "A subcommand is required" for an unknown first word: name it.
  if (argc > 1 && argv[1][0] != '-' &&
      app.get_subcommands([&](CLI::App* command) { return command->get_name() == argv[1]; })
          .empty()) {
    std::string names;
    for (const CLI::App* command : app.get_subcommands({})) {
      names += (names.empty() ? "" : ", ") + command->get_name();
    }
    std::cerr << "memloop: error: unknown command '" << argv[1] << "' (commands: " << names
              << "; see memloop --help)\n";
    return 2;
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& error) {
    const int code = app.exit(error);  // prints help, or the usage error
    return code == 0 ? 0 : 2;
  } catch (const memloop::cli::Interrupted& interrupted) {
    std::cerr << "memloop: " << interrupted.what() << "\n";
    return 128 + interrupted.signal();
  } catch (const std::exception& error) {
    std::cerr << "memloop: error: " << error.what() << "\n";
    return 1;
  }
  return 0;
}
