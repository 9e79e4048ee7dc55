// memloop run IMAGES_DIR|VIDEO_FILE [--db FILE [--resume]] [--set NAME=VALUE ...] [--out FILE.csv]
#include <iostream>

#include "commands.h"
#include "memloop/detector.h"
#include "memloop/errors.h"
#include "memloop/image_sequence.h"
#include "memloop/params.h"
#include "session.h"

namespace memloop::cli {

void AddRunCommand(CLI::App& app) {
  struct Arguments {
    std::string input;
    std::string database;
    std::string out;
    std::vector<std::string> assignments;
    std::string config;
    std::string preset;
    bool resume = false;
  };
  auto arguments = std::make_shared<Arguments>();
  CLI::App* run = app.add_subcommand(
      "run", "Detect loop closures in a folder of images (natural numeric order) or a video");
  run->add_option("input", arguments->input, "Folder of images or video file")->required();
  CLI::Option* database = run->add_option(
      "--db", arguments->database,
      "Map database file (the Long-Term Memory): a new file, or with --resume an existing map; "
      "default: a temporary file");
  run->add_flag("--resume", arguments->resume,
                "Go on with the map in --db from its last checkpoint: images after the one it "
                "holds are processed, --out is continued, parameters are the map's (--set may "
                "change those that do not define the map)")
      ->needs(database);
  run->add_option("--out", arguments->out, "CSV of per-image results");
  CLI::Option* preset = run->add_option(
      "--preset", arguments->preset,
      "Starting values: default (memloop's measured best) or paper2011 (the paper's mechanisms "
      "as written); --set applies on top");
  AddConfigOption(*run, &arguments->config);
  run->add_option("--set", arguments->assignments, "Parameter NAME=VALUE (see 'memloop params')")
      ->take_all();
  preset->excludes(run->get_option("--resume"));
  run->callback([arguments] {
    const Options options = WithSettings(
        arguments->resume ? ReadMapOptions(arguments->database)
                          : Preset(arguments->preset.empty() ? "default" : arguments->preset),
        arguments->config, arguments->assignments);
    auto sequence = ImageSequence::Open(arguments->input);
    SessionOptions session;
    session.resume = arguments->resume;
    const SessionReport report =
        RunSession(*sequence, options, arguments->database, arguments->out, session);
    std::cout << Summary(report) << "\n";
    ThrowIfInterrupted(report, arguments->database);
    if (report.results.empty() && !arguments->resume) {
      throw InputError(arguments->input,
                       "no readable image (" + std::to_string(report.skipped) + " skipped)");
    }
  });
}

}  // namespace memloop::cli
