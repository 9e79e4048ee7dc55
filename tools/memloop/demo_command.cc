// memloop demo: the built-in synthetic route with revisits, run at default parameters, scored
// against its exact ground truth. memloop generate FOLDER writes the same route as image files.
#include <cstdio>
#include <iostream>

#include "commands.h"
#include "memloop/evaluation.h"
#include "memloop/synthetic_route.h"
#include "session.h"

namespace memloop::cli {
namespace {

class RouteSequence : public ImageSequence {
 public:
  explicit RouteSequence(const SyntheticRoute& route) : route_(route) {}
  bool Next(Frame* frame) override {
    if (next_ >= route_.size()) return false;
    frame->index = next_;
    frame->name = std::to_string(next_ + 1) + ".png";
    frame->image = route_.Render(next_++);
    frame->error.clear();
    return true;
  }
  int size() const override { return route_.size(); }

 private:
  const SyntheticRoute& route_;
  int next_ = 0;
};

}  // namespace

void AddDemoCommand(CLI::App& app) {
  struct Arguments {
    std::string database;
    std::string out;
    std::vector<std::string> assignments;
    std::string preset = "default";
    int seed = SyntheticRouteOptions().seed;
    std::string folder;
  };
  auto arguments = std::make_shared<Arguments>();
  CLI::App* demo = app.add_subcommand(
      "demo", "Run on the built-in synthetic route and score against its exact ground truth");
  demo->add_option("--db", arguments->database, "New map database file; default: temporary");
  demo->add_option("--out", arguments->out, "CSV of per-image results");
  demo->add_option("--preset", arguments->preset,
                   "Starting values: default (memloop's measured best) or paper2011 (the paper's "
                   "mechanisms as written); --set applies on top")
      ->capture_default_str();
  demo->add_option("--set", arguments->assignments, "Parameter NAME=VALUE")->take_all();
  demo->add_option("--seed", arguments->seed, "Seed of the generated world")->capture_default_str();
  demo->callback([arguments] {
    SyntheticRouteOptions route_options;
    route_options.seed = arguments->seed;
    const SyntheticRoute route(route_options);
    RouteSequence sequence(route);
    const Options options = OptionsFromAssignments(arguments->assignments, arguments->preset);
    std::cout << "Synthetic route: " << route.size() << " images of " << route_options.image_width
              << "x" << route_options.image_height << ", " << route.GroundTruthPairs().size()
              << " ground-truth loop pairs\n";
    const SessionReport report = RunSession(sequence, options, arguments->database, arguments->out);

    std::vector<Detection> detections;
    const GroundTruth truth = route.Truth();
    for (const Result& result : report.results) {
      if (!result.HasLoopClosure()) continue;
      detections.push_back({result.image_index, result.loop_closure_images});
      const bool correct = Evaluate({detections.back()}, truth).true_positives == 1;
      std::cout << result.Brief() << (correct ? "  [true]" : "  [FALSE]") << "\n";
    }
    const PrecisionRecall score = Evaluate(detections, truth);
    std::cout << Summary(report) << "\n";
    std::printf("precision %.1f%% (%d/%d), recall %.1f%% (%d/%d images with a loop)\n",
                100 * score.Precision(), score.true_positives, score.detections,
                100 * score.Recall(), score.true_positives, score.loop_images);
  });

  CLI::App* generate = app.add_subcommand(
      "generate", "Write the synthetic route as images/1.png..N.png with ground_truth_pairs.csv");
  generate->add_option("folder", arguments->folder, "Folder to write into (created if missing)")
      ->required();
  generate->add_option("--seed", arguments->seed, "Seed of the generated world")
      ->capture_default_str();
  generate->callback([arguments] {
    SyntheticRouteOptions route_options;
    route_options.seed = arguments->seed;
    SyntheticRoute(route_options).Write(arguments->folder);
  });
}

}  // namespace memloop::cli
