// memloop run IMAGES_DIR|VIDEO_FILE [--db FILE] [--set NAME=VALUE ...] [--out FILE.csv]
#include <iostream>

#include "commands.h"
#include "memloop/errors.h"
#include "memloop/image_sequence.h"
#include "session.h"

namespace memloop::cli {

void AddRunCommand(CLI::App& app) {
  struct Arguments {
    std::string input;
    std::string database;
    std::string out;
    std::vector<std::string> assignments;
  };
  auto arguments = std::make_shared<Arguments>();
  CLI::App* run = app.add_subcommand(
      "run", "Detect loop closures in a folder of images (natural numeric order) or a video");
  run->add_option("input", arguments->input, "Folder of images or video file")->required();
  run->add_option("--db", arguments->database,
                  "New map database file (the Long-Term Memory); default: a temporary file");
  run->add_option("--out", arguments->out, "CSV of per-image results");
  run->add_option("--set", arguments->assignments, "Parameter NAME=VALUE (see 'memloop params')")
      ->take_all();
  run->callback([arguments] {
    const Options options = OptionsFromAssignments(arguments->assignments);
    auto sequence = ImageSequence::Open(arguments->input);
    const SessionReport report =
        RunSession(*sequence, options, arguments->database, arguments->out);
    for (const Result& result : report.results) {
      if (result.HasLoopClosure()) std::cout << result.Brief() << "\n";
    }
    std::cout << Summary(report) << "\n";
    if (report.results.empty()) {
      throw InputError(arguments->input,
                       "no readable image (" + std::to_string(report.skipped) + " skipped)");
    }
  });
}

}  // namespace memloop::cli
