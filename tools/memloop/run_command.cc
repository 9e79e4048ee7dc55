// memloop run IMAGES_DIR|DATASET_DIR|BAG [--topic T]|VIDEO_FILE|--camera N [--format F] [--rate HZ]
//             [--db FILE [--resume|--new-session]] [--config FILE] [--set NAME=VALUE ...]
//             [--out FILE.csv]
// With --set memory.localization=1 and --db MAP, images are localized against MAP, unchanged.
#include <cmath>
#include <cstdlib>
#include <iostream>

#include "command_files.h"
#include "commands.h"
#include "memloop/detector.h"
#include "memloop/errors.h"
#include "memloop/fleet.h"
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
    std::string robot;
    bool fleet_catch_up = false;
    std::string out;
    std::vector<std::string> assignments;
    std::string config;
    std::string preset;
    bool resume = false;
    bool new_session = false;
    std::string format = "auto";
    std::string topic;
    std::string depth_folder;
    std::string depth_topic;
    double depth_scale = 0;
    int camera = -1;
    double rate_hz = 0;
    int realtime_priority = kUsualScheduling;
    double pace_hz = 0;
  };
  auto arguments = std::make_shared<Arguments>();
  CLI::App* run = app.add_subcommand(
      "run",
      "Detect loop closures in a folder of images (natural numeric order), a dataset folder with "
      "timestamps (TUM, EuRoC, KITTI), a ROS bag or a video");
  CLI::Option* input =
      run->add_option("input", arguments->input,
                      "Folder of images, dataset folder, ROS 1 bag (.bag), ROS 2 bag (folder with "
                      "metadata.yaml, or .db3) or video file");
  run->add_option("--topic", arguments->topic,
                  "The bag's topic of sensor_msgs/Image or CompressedImage; default: its only "
                  "image topic");
  run->add_option("--depth", arguments->depth_folder,
                  "Folder of depth maps registered to the images, named by their file stems "
                  "(16-bit PNG or 32-bit float); a TUM folder's depth.txt is read without it. "
                  "With camera.fx..cy, loop closures' translations are then in metres");
  run->add_option("--depth-topic", arguments->depth_topic,
                  "The bag's depth image topic (16UC1 millimetres or 32FC1 metres), registered to "
                  "--topic; each image takes the depth map nearest its time stamp");
  run->add_option("--depth-scale", arguments->depth_scale,
                  "A 16-bit depth map's units per metre; default: 5000 for a TUM folder's "
                  "depth.txt, else 1000 (millimetres)")
      ->check(Number("units per metre, over 0", 0, false));
  CLI::Option* camera =
      run->add_option("--camera", arguments->camera,
                      "Live camera number (0 = the first) instead of an input; stop with Ctrl-C")
          ->check(Number("a camera number (0 or more)", 0, true));
  input->excludes(camera);
  run->add_option("--format", arguments->format,
                  "How the folder lists its images: auto (a dataset layout when one is "
                  "recognised), folder (every file, natural order), tum (rgb.txt), euroc "
                  "(mav0/cam0/data.csv), kitti (times.txt or image_00/timestamps.txt)")
      ->check(CLI::IsMember({"auto", "folder", "tum", "euroc", "kitti"}));
  run->add_option("--rate", arguments->rate_hz,
                  "Frames per second to take from a video or a dataset folder (by timestamp) or a "
                  "camera (the paper: 1); default every frame")
      ->check(Number("a number of frames per second over 0", 0, false));
  CLI::Option* database =
      run->add_option("--db", arguments->database,
                      "Map database (the Long-Term Memory): a file, or a fleet's map on a server "
                      "(postgresql://ROBOT@HOST/DBNAME); a new map, or with --resume or "
                      "--set memory.localization=1 an existing one; default: a temporary file");
  run->add_option("--robot", arguments->robot,
                  "With --db postgresql://HOST/DBNAME (a fleet's map, docs/fleet.md): the robot, "
                  "whose database role the run connects as")
      ->needs(database);
  run->add_flag("--fleet-catch-up", arguments->fleet_catch_up,
                "With --robot: the places other robots have stored so far join the map before the "
                "first image (then memory.fleet_imports an image)");
  run->add_flag("--resume", arguments->resume,
                "Go on with the map in --db from its last checkpoint: images after the one it "
                "holds are processed, --out is continued, parameters are the map's (--set may "
                "change those that do not define the map)")
      ->needs(database);
  run->add_flag("--new-session", arguments->new_session,
                "Add the input to the map in --db as a new session (multi-session mapping): its "
                "images are linked to the map's only by loop closures; parameters are the map's")
      ->needs(database)
      ->excludes("--resume");
  run->add_option("--out", arguments->out, "CSV of per-image results");
  CLI::Option* preset = AddPresetOption(*run, &arguments->preset);
  AddConfigOption(*run, &arguments->config);
  run->add_option("--set", arguments->assignments, "Parameter NAME=VALUE (see 'memloop params')")
      ->take_all();
  AddRealtimePriorityOption(*run, &arguments->realtime_priority);
  AddPaceOption(*run, &arguments->pace_hz);
  preset->excludes(run->get_option("--resume"));
  preset->excludes(run->get_option("--new-session"));
  run->callback([arguments] {
    arguments->database = RobotMapUri(arguments->database, arguments->robot);
    const bool extends = arguments->resume || arguments->new_session;
    Options options =
        WithSettings(extends ? ReadMapOptions(arguments->database)
                             : Preset(arguments->preset.empty() ? "default" : arguments->preset),
                     arguments->config, arguments->assignments);
    if (options.memory.localization && !extends) {
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
    sequence_options.format = ParseInputFormat(arguments->format);
    sequence_options.topic = arguments->topic;
    sequence_options.depth_folder = arguments->depth_folder;
    sequence_options.depth_topic = arguments->depth_topic;
    sequence_options.depth_units_per_metre = arguments->depth_scale;
    auto sequence = arguments->camera >= 0
                        ? ImageSequence::OpenCamera(arguments->camera, sequence_options)
                        : ImageSequence::Open(arguments->input, sequence_options);
    SessionOptions session;
    session.resume = arguments->resume;
    session.new_session = arguments->new_session;
    session.input = arguments->input;
    session.realtime_priority = arguments->realtime_priority;
    session.pace_hz = arguments->pace_hz;
    session.fleet_catch_up = arguments->fleet_catch_up;
    if (session.fleet_catch_up && arguments->robot.empty()) {
      throw CLI::ValidationError("--fleet-catch-up", "needs a fleet's map: --robot");
    }
    session.inputs = RunInputs(arguments->input, sequence_options);
    for (NamedPath& file : FileIfGiven(arguments->config, "the parameter file (--config)")) {
      session.inputs.push_back(std::move(file));
    }
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
