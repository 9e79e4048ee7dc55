// memloop run IMAGES_DIR|VIDEO_FILE|--camera N [--rate HZ] [--db FILE [--resume]]
//             [--config FILE] [--set NAME=VALUE ...] [--out FILE.csv]
// With --set memory.localization=1 and --db MAP, images are localized against MAP, unchanged.
#include <cmath>
#include <cstdlib>
#include <iostream>

#include "commands.h"
#include "memloop/detector.h"
#include "memloop/errors.h"
#include "memloop/image_sequence.h"
#include "memloop/params.h"
#include "session.h"

namespace memloop::cli {
namespace {

// CLI11's PositiveNumber lets NaN through and names its bound as a 309-digit number.
CLI::Validator Number(const std::string& what, double min, bool min_allowed) {
  return CLI::Validator(
      [what, min, min_allowed](std::string& text) -> std::string {
        char* end = nullptr;
        const double value = std::strtod(text.c_str(), &end);
        const bool number = end != text.c_str() && *end == '\0' && std::isfinite(value);
        if (number && (value > min || (min_allowed && value == min))) return "";
        return "must be " + what + ", not '" + text + "'";
      },
      what);
}

}  // namespace

void AddRunCommand(CLI::App& app) {
  struct Arguments {
    std::string input;
    std::string database;
    std::string out;
    std::vector<std::string> assignments;
    std::string config;
    std::string preset;
    bool resume = false;
    int camera = -1;
    double rate_hz = 0;
  };
  auto arguments = std::make_shared<Arguments>();
  CLI::App* run = app.add_subcommand(
      "run", "Detect loop closures in a folder of images (natural numeric order) or a video");
  CLI::Option* input = run->add_option("input", arguments->input, "Folder of images or video file");
  CLI::Option* camera =
      run->add_option("--camera", arguments->camera,
                      "Live camera number (0 = the first) instead of an input; stop with Ctrl-C")
          ->check(Number("a camera number (0 or more)", 0, true));
  input->excludes(camera);
  run->add_option("--rate", arguments->rate_hz,
                  "Frames per second to take from a video (by timestamp) or a camera (the paper: "
                  "1); default every frame")
      ->check(Number("a number of frames per second over 0", 0, false));
  CLI::Option* database =
      run->add_option("--db", arguments->database,
                      "Map database file (the Long-Term Memory): a new file, or with --resume or "
                      "--set memory.localization=1 an existing map; default: a temporary file");
  run->add_flag("--resume", arguments->resume,
                "Go on with the map in --db from its last checkpoint: images after the one it "
                "holds are processed, --out is continued, parameters are the map's (--set may "
                "change those that do not define the map)")
      ->needs(database);
  run->add_option("--out", arguments->out, "CSV of per-image results");
  CLI::Option* preset = AddPresetOption(*run, &arguments->preset);
  AddConfigOption(*run, &arguments->config);
  run->add_option("--set", arguments->assignments, "Parameter NAME=VALUE (see 'memloop params')")
      ->take_all();
  preset->excludes(run->get_option("--resume"));
  run->callback([arguments] {
    Options options = WithSettings(
        arguments->resume ? ReadMapOptions(arguments->database)
                          : Preset(arguments->preset.empty() ? "default" : arguments->preset),
        arguments->config, arguments->assignments);
    if (options.memory.localization && !arguments->resume) {
      if (arguments->database.empty()) {
        throw ParameterError("memory.localization",
                             "memory.localization=1 needs --db MAP: the map to localize against");
      }
      if (!arguments->preset.empty()) {
        throw ParameterError("memory.localization",
                             "--preset: localization uses the parameters of the map in --db");
      }
      // The map's parameters, as with --resume; --config and --set apply on top.
      options = WithSettings(ReadMapOptions(arguments->database), arguments->config,
                             arguments->assignments);
    }
    if (arguments->input.empty() && arguments->camera < 0) {
      throw CLI::RequiredError("an input (folder or video) or --camera");
    }
    SequenceOptions sequence_options;
    sequence_options.rate_hz = arguments->rate_hz;
    auto sequence = arguments->camera >= 0
                        ? ImageSequence::OpenCamera(arguments->camera, sequence_options)
                        : ImageSequence::Open(arguments->input, sequence_options);
    SessionOptions session;
    session.resume = arguments->resume;
    const SessionReport report =
        RunSession(*sequence, options, arguments->database, arguments->out, session);
    std::cout << Summary(report) << "\n";
    ThrowIfInterrupted(report, options.memory.localization ? "" : arguments->database);
    if (report.results.empty() && !arguments->resume) {
      throw InputError(
          arguments->camera >= 0 ? "camera " + std::to_string(arguments->camera) : arguments->input,
          "no readable image (" + std::to_string(report.skipped) + " skipped)");
    }
  });
}

}  // namespace memloop::cli
