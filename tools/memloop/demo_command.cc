// memloop demo: the built-in synthetic route with revisits (or, with --places, a long sequence of
// generated places), run at default parameters, scored
// against its exact ground truth. memloop generate FOLDER writes the same route as image files.
#include <cstdio>
#include <iostream>
#include <set>

#include "command_files.h"
#include "commands.h"
#include "memloop/evaluation.h"
#include "memloop/fleet_routes.h"
#include "memloop/place_sequence.h"
#include "memloop/synthetic_route.h"
#include "progress.h"
#include "session.h"

namespace memloop::cli {
namespace {

// The demo prints its scores, not a line per loop closure (hundreds on the route).
SessionOptions ScoredSession() {
  SessionOptions session;
  session.print_loop_closures = false;
  return session;
}
const SessionOptions kScoredSession = ScoredSession();

// Frames rendered on demand from a generated sequence (SyntheticRoute or PlaceSequence).
template <typename Generated>
class GeneratedSequence : public ImageSequence {
 public:
  explicit GeneratedSequence(const Generated& generated) : generated_(generated) {}
  bool Next(Frame* frame) override {
    if (next_ >= generated_.size()) return false;
    frame->index = next_;
    frame->name = std::to_string(next_ + 1) + ".png";
    frame->image = generated_.Render(next_++);
    frame->error.clear();
    return true;
  }
  int size() const override { return generated_.size(); }

 private:
  const Generated& generated_;
  int next_ = 0;
};

// Each loop closure with its verdict, the summary, then precision and recall against the
// sequence's exact ground truth (IsLoop: no N x N matrix, which 50,000 images could not afford).
template <typename Generated>
void PrintScored(const Generated& generated, const SessionReport& report) {
  std::set<int> images_with_loop;
  for (const auto& pair : generated.GroundTruthPairs()) images_with_loop.insert(pair.first);
  const int loop_images = static_cast<int>(images_with_loop.size());
  int detections = 0;
  int true_positives = 0;
  for (const Result& result : report.results) {
    if (!result.HasLoopClosure()) continue;
    bool correct = false;
    for (ImageIndex match : result.loop_closure_images) {
      correct = correct || generated.IsLoop(result.image_index, match);
    }
    ++detections;
    true_positives += correct;
    std::cout << result.Brief() << (correct ? "  [true]" : "  [FALSE]") << "\n";
  }
  std::cout << Summary(report) << "\n";
  std::printf("precision %.1f%% (%d/%d), recall %.1f%% (%d/%d images with a loop)\n",
              detections == 0 ? 100.0 : 100.0 * true_positives / detections, true_positives,
              detections, loop_images == 0 ? 0.0 : 100.0 * true_positives / loop_images,
              true_positives, loop_images);
}

// Returns --places: given, the command uses a PlaceSequence instead of the demo route.
CLI::Option* AddPlaceOptions(CLI::App& command, PlaceSequenceOptions* options) {
  CLI::Option* places =
      command.add_option("--places", options->places,
                         "A long sequence of this many distinct places (for scale: any length) "
                         "instead of the demo route");
  command.add_option("--frames-per-place", options->frames_per_place, "Frames of each visit")
      ->capture_default_str();
  command
      .add_option("--revisit-every", options->revisit_every,
                  "One revisit of an earlier place after every N new places (0: none)")
      ->capture_default_str();
  command
      .add_option("--min-revisit-age", options->min_revisit_age,
                  "A revisited place was last seen at least this many images before")
      ->capture_default_str();
  return places;
}

}  // namespace

void AddDemoCommand(CLI::App& app) {
  struct Arguments {
    std::string database;
    std::string out;
    std::vector<std::string> assignments;
    std::string config;
    std::string preset = "default";
    int seed = SyntheticRouteOptions().seed;
    std::string folder;
    std::string layout = "images";
    PlaceSequenceOptions places;
    int robots = 1;
    int realtime_priority = kUsualScheduling;
    double pace_hz = 0;
  };
  auto arguments = std::make_shared<Arguments>();
  CLI::App* demo = app.add_subcommand(
      "demo", "Run on the built-in synthetic route and score against its exact ground truth");
  demo->add_option("--db", arguments->database, "New map database file; default: temporary");
  demo->add_option("--out", arguments->out, "CSV of per-image results");
  AddPresetOption(*demo, &arguments->preset)->capture_default_str();
  AddConfigOption(*demo, &arguments->config);
  demo->add_option("--set", arguments->assignments, "Parameter NAME=VALUE")->take_all();
  demo->add_option("--seed", arguments->seed, "Seed of the generated world")->capture_default_str();
  AddRealtimePriorityOption(*demo, &arguments->realtime_priority);
  AddPaceOption(*demo, &arguments->pace_hz);
  CLI::Option* demo_places = AddPlaceOptions(*demo, &arguments->places);
  demo->callback([arguments, demo_places] {
    const Options options =
        WithSettings(Preset(arguments->preset), arguments->config, arguments->assignments);
    SessionOptions session = kScoredSession;
    session.inputs = FileIfGiven(arguments->config, "the parameter file (--config)");
    session.realtime_priority = arguments->realtime_priority;
    session.pace_hz = arguments->pace_hz;
    if (demo_places->count() > 0) {
      arguments->places.seed = arguments->seed;
      const PlaceSequence places(arguments->places);
      GeneratedSequence<PlaceSequence> sequence(places);
      std::cout << "Generated places: " << places.size() << " images of "
                << arguments->places.image_width << "x" << arguments->places.image_height << ", "
                << arguments->places.places << " places, " << places.revisits() << " revisits ("
                << places.revisit_frames() << " images)\n";
      const SessionReport report =
          RunSession(sequence, options, arguments->database, arguments->out, session);
      PrintScored(places, report);
      ThrowIfInterrupted(report, arguments->database);
      return;
    }
    SyntheticRouteOptions route_options;
    route_options.seed = arguments->seed;
    const SyntheticRoute route(route_options);
    GeneratedSequence<SyntheticRoute> sequence(route);
    std::cout << "Synthetic route: " << route.size() << " images of " << route_options.image_width
              << "x" << route_options.image_height << ", " << route.GroundTruthPairs().size()
              << " ground-truth loop pairs\n";
    const SessionReport report =
        RunSession(sequence, options, arguments->database, arguments->out, session);
    PrintScored(route, report);
    ThrowIfInterrupted(report, arguments->database);
  });

  CLI::App* generate = app.add_subcommand(
      "generate",
      "Write the synthetic route as images/1.png..N.png (or a TUM folder, or a ROS 2 bag) with "
      "ground_truth_pairs.csv");
  generate->add_option("folder", arguments->folder, "Folder to write into (created if missing)")
      ->required();
  generate->add_option("--seed", arguments->seed, "Seed of the generated world")
      ->capture_default_str();
  generate
      ->add_option("--layout", arguments->layout,
                   "images (images/N.png), tum (a TUM RGB-D folder, 10 Hz: rgb/, rgb.txt and, for "
                   "the route, depth/, depth.txt, groundtruth.txt, odometry.txt, camera.conf) or "
                   "ros2-bag (ros2_bag/: /camera/image_raw, 10 Hz)")
      ->check(CLI::IsMember({"images", "tum", "ros2-bag"}))
      ->capture_default_str();
  CLI::Option* generate_places = AddPlaceOptions(*generate, &arguments->places);
  CLI::Option* generate_robots =
      generate
          ->add_option("--robots", arguments->robots,
                       "Routes of this many robots over one world, FOLDER/a, FOLDER/b, ... (images "
                       "and their own ground_truth_pairs.csv), with FOLDER/fleet_pairs.csv: the "
                       "places two robots share")
          ->check(CLI::Range(2, 26));
  generate_robots->excludes(generate_places);
  generate->callback([arguments, generate_places, generate_robots] {
    const GeneratedLayout layout = ParseGeneratedLayout(arguments->layout);
    if (generate_robots->count() > 0) {
      if (layout != GeneratedLayout::kImages) {
        throw CLI::ValidationError("--robots", "writes image folders only (--layout images)");
      }
      SyntheticRouteOptions route_options;
      route_options.seed = arguments->seed;
      const FleetRoutes fleet(arguments->robots, route_options);
      int images = 0;
      for (int robot = 0; robot < fleet.robots(); ++robot) images += fleet.route(robot).size();
      Progress progress(images, "images written");
      fleet.Write(arguments->folder, [&](int written) { progress.Update(written); });
      return;
    }
    if (generate_places->count() > 0) {
      arguments->places.seed = arguments->seed;
      const PlaceSequence places(arguments->places);
      Progress progress(places.size(), "images written");
      places.Write(
          arguments->folder, [&](int written) { progress.Update(written); }, layout);
      return;
    }
    SyntheticRouteOptions route_options;
    route_options.seed = arguments->seed;
    const SyntheticRoute route(route_options);
    Progress progress(route.size(), "images written");
    route.Write(
        arguments->folder, [&](int written) { progress.Update(written); }, layout);
  });
}

}  // namespace memloop::cli
