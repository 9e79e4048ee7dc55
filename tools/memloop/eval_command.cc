// memloop eval RUN.csv GROUND_TRUTH_OR_DATASET_DIR [--ignore PAIRS.csv]
//              [--format auto|mat|image|pairs|matrix] [--json] [--time-limit-ms T]
//              [--ignored-as-true]
// memloop report RUN.csv [GROUND_TRUTH_OR_DATASET_DIR] [--ignore PAIRS.csv] [--format ...]
//                [--out report.html] [--time-limit-ms T] [--images FOLDER_OR_VIDEO]
//                [--ignored-as-true]
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>

#include "commands.h"
#include "memloop/detector.h"
#include "memloop/errors.h"
#include "memloop/evaluation.h"
#include "memloop/ground_truth.h"
#include "memloop/params.h"
#include "memloop/report.h"
#include "memloop/run_csv.h"
#include "util/output_files.h"

namespace memloop::cli {
namespace {

nlohmann::json ToJson(const RunEvaluation& e, const GroundTruth& truth,
                      const std::vector<std::string>& files, bool ignored_as_true) {
  nlohmann::json curve = nlohmann::json::array();
  for (const PrecisionRecallPoint& p : e.curve) {
    curve.push_back({{"threshold", p.threshold},
                     {"precision", p.precision},
                     {"recall", p.recall},
                     {"true_positives", p.true_positives},
                     {"false_positives", p.false_positives}});
  }
  return {{"images", e.images},
          {"ground_truth",
           {{"files", files},
            {"size", truth.size()},
            {"ignored_as_true", ignored_as_true},
            {"pairs", truth.PairCount()},
            {"images_with_loop", e.accepted.loop_images}}},
          {"loop_closures",
           {{"detections", e.accepted.detections},
            {"true_positives", e.accepted.true_positives},
            {"false_positives", e.accepted.false_positives},
            {"ignored", e.accepted.ignored}}},
          {"precision", e.accepted.Precision()},
          {"recall", e.accepted.Recall()},
          {"recall_at_100_precision", e.recall_at_full_precision},
          {"threshold_at_100_precision", e.threshold_at_full_precision},
          {"table1",
           {{"images", e.images},
            {"max_wm_size", e.max_wm_size},
            {"max_dictionary_size", e.max_dictionary_size},
            {"max_iteration_s", e.max_iteration_ms / 1000},
            {"median_iteration_s", e.median_iteration_ms / 1000},
            {"time_limit_s", e.time_limit_ms / 1000},
            {"iterations_over_time_limit", e.iterations_over_time_limit},
            {"percent_over_time_limit", 100 * e.FractionOverTimeLimit()},
            {"max_over_time_limit", e.max_over_time_limit},
            {"median_fixed_s", e.median_fixed_ms / 1000},
            {"median_cpu_share",
             e.median_cpu_share < 0 ? nlohmann::json(nullptr) : nlohmann::json(e.median_cpu_share)},
            {"over_time_limit_waiting", e.over_time_limit_waiting},
            {"time_decided_iterations", e.time_decided_iterations},
            {"first_time_decided_image", e.first_time_decided == kNoImage
                                             ? nlohmann::json(nullptr)
                                             : nlohmann::json(e.first_time_decided)},
            {"precision_percent", 100 * e.accepted.Precision()},
            {"recall_percent", 100 * e.accepted.Recall()}}},
          {"curve", curve}};
}

void PrintText(const RunEvaluation& e, const GroundTruth& truth, const std::string& run,
               const std::string& ground_truth, bool ignored_as_true) {
  std::printf("run %s: %d images; ground truth %s: %dx%d, %d pairs, %d images with a loop%s\n",
              run.c_str(), e.images, ground_truth.c_str(), truth.size(), truth.size(),
              truth.PairCount(), e.accepted.loop_images,
              ignored_as_true ? " (ignored pairs counted as loops)" : "");
  // What the run itself delivered first, then what a threshold chosen afterwards would give.
  std::printf(
      "the run accepted, at its T_loop: %d loop closures (true %d, false %d, on ignored pairs "
      "%d): precision %.1f%%, recall %.1f%%\n",
      e.accepted.detections + e.accepted.ignored, e.accepted.true_positives,
      e.accepted.false_positives, e.accepted.ignored, 100 * e.accepted.Precision(),
      100 * e.accepted.Recall());
  std::printf(
      "best threshold (chosen afterwards against the ground truth), recall at 100%% precision: "
      "%.1f%% (hypotheses >= %.4g)\n",
      100 * e.recall_at_full_precision, e.threshold_at_full_precision);
  std::printf("%s\n", TimeDecidedLine(e).c_str());
  std::printf("precision-recall curve: %zu points (--json lists them)\n", e.curve.size());
  std::printf(
      "Table 1: images %d | max WM size %d locations | max dictionary size %d words | "
      "max iteration time %.3f s | precision %.0f%% | recall %.0f%%\n",
      e.images, e.max_wm_size, e.max_dictionary_size, e.max_iteration_ms / 1000,
      100 * e.accepted.Precision(), 100 * e.accepted.Recall());
  if (e.time_limit_ms > 0) {
    std::printf(
        "time bound: T_time %g ms | median iteration %.1f ms | over T_time: %d (%.2f%%) | "
        "max iteration / T_time %.2f | fixed cost %.1f ms (median outside WM's stages: the "
        "floor under T_time x memory.time_target)\n",
        e.time_limit_ms, e.median_iteration_ms, e.iterations_over_time_limit,
        100 * e.FractionOverTimeLimit(), e.max_over_time_limit, e.median_fixed_ms);
    if (e.median_cpu_share >= 0) {
      std::printf(
          "detector's thread on the CPU: median %.0f%% of an iteration | over T_time with it on "
          "the CPU under %.0f%% of the time (waiting for the CPU, the search's helper thread or "
          "the disk): %d%s\n",
          100 * e.median_cpu_share, 100 * kWaitedCpuShare, e.over_time_limit_waiting,
          e.median_cpu_share < kWaitedCpuShare
              ? " | other programs shared the CPU: --realtime-priority gives it to the detector"
              : "");
    }
  }
}

struct Evaluated {
  std::vector<RunRow> rows;
  GroundTruth truth;
  RunEvaluation evaluation;
  std::vector<std::string> files;  // the ground truth's, its ignored pairs' second
};

struct GroundTruthArguments {
  std::string path;  // a file, or a data set's folder
  std::string ignore;
  std::string format = "auto";
  bool ignored_as_true = false;
};

// The run's rows and the ground truth over the same images (its size must be the run's).
Evaluated Evaluate(const std::string& run, const GroundTruthArguments& ground_truth,
                   double time_limit_ms) {
  std::vector<RunRow> rows = ReadRunCsv(run);
  int image_count = 0;
  for (const RunRow& row : rows) image_count = std::max(image_count, row.image + 1);
  std::vector<std::string> names(image_count);
  for (const RunRow& row : rows) names[row.image] = row.name;
  std::error_code error;
  std::vector<std::string> files = {ground_truth.path};
  if (std::filesystem::is_directory(ground_truth.path, error)) {
    if (ground_truth.format != "auto") {
      throw CLI::ValidationError("--format", "a data set folder picks its own ground truth");
    }
    files = GroundTruth::DatasetFiles(ground_truth.path);
  }
  if (!ground_truth.ignore.empty()) {
    files.resize(1);  // --ignore instead of a data set's own ignored pairs
    files.push_back(ground_truth.ignore);
  }
  GroundTruth truth = GroundTruth::Load(files[0], GroundTruth::ParseFormat(ground_truth.format),
                                        names, image_count);
  if (files.size() > 1) truth = truth.WithIgnoredPairs(files[1], names);
  if (ground_truth.ignored_as_true) truth = truth.IgnoredAsLoops();
  RunEvaluation evaluation = EvaluateRun(rows, truth, time_limit_ms);
  return {std::move(rows), std::move(truth), std::move(evaluation), std::move(files)};
}

// The run's map: its parameters and T_time, which the CSV does not record.
struct RunMap {
  std::string path;
  double time_limit_ms = -1;  // --time-limit-ms; -1: the map's, or none

  // T_time: --time-limit-ms when given, else the map's, else 0 (unknown).
  double TimeLimitMs() const {
    if (time_limit_ms >= 0) return time_limit_ms;
    return path.empty() ? 0 : ReadMapOptions(path).memory.time_limit_ms;
  }
  std::vector<ReportParameter> Parameters() const {
    std::vector<ReportParameter> parameters;
    if (path.empty()) return parameters;
    const Options map = ReadMapOptions(path);
    const Options defaults;
    for (const Parameter& parameter : memloop::Parameters()) {
      parameters.push_back({parameter.key, parameter.Get(map), parameter.Get(defaults)});
    }
    return parameters;
  }
};

void AddMapOption(CLI::App& command, RunMap* map) {
  command
      .add_option("--map", map->path,
                  "The run's map (memloop run --db): its parameters, and its T_time unless "
                  "--time-limit-ms is given")
      ->check(CLI::ExistingFile);
  command
      .add_option("--time-limit-ms", map->time_limit_ms,
                  "T_time of the run (0: none; default: the map's with --map, else none): "
                  "iterations over it, max / T_time, and the line on the time figure")
      ->check(CLI::Validator(
          [](const std::string& text) {
            const double value = std::strtod(text.c_str(), nullptr);
            return std::isfinite(value) && value >= 0 ? std::string()
                                                      : "must be a finite number >= 0";
          },
          "MS>=0"));
}

void AddGroundTruthOptions(CLI::App& command, GroundTruthArguments* ground_truth) {
  command
      .add_option("--ignore", ground_truth->ignore,
                  "CSV of pairs (query,match) that count neither as true nor as false, e.g. a "
                  "data set's ground_truth_ignore.csv beside its ground_truth_pairs.csv")
      ->check(CLI::ExistingFile);
  command.add_option("--format", ground_truth->format, "auto, mat, image, pairs or matrix")
      ->capture_default_str();
  command.add_flag("--ignored-as-true", ground_truth->ignored_as_true,
                   "Count the ground truth's ignored pairs as loops (the paper's 2011 protocol): a "
                   "detection on one is true; default: neither true nor false");
}

constexpr const char* kGroundTruthHelp =
    "Ground truth: a data set folder (ground_truth.bmp, or ground_truth_pairs.csv with "
    "ground_truth_ignore.csv, or ground_truth.mat), or a file: .mat, image (255 = loop, 0 = none, "
    "other = ignored), CSV of pairs, or text matrix";

}  // namespace

// What the ground truth was read from, as the output names it.
std::string Describe(const std::vector<std::string>& files) {
  return files.size() > 1 ? files[0] + " (ignored pairs: " + files[1] + ")" : files[0];
}

void AddReportCommand(CLI::App& app) {
  struct Arguments {
    std::string run;
    GroundTruthArguments ground_truth;
    std::string out = "report.html";
    RunMap map;
    std::string images;
    int max_views = ReportOptions().max_views;
  };
  auto arguments = std::make_shared<Arguments>();
  CLI::App* report = app.add_subcommand(
      "report", "One self-contained HTML page: PR curve, time per image, memory, detections");
  report->add_option("run", arguments->run, "CSV written by memloop run --out")->required();
  report->add_option("ground_truth", arguments->ground_truth.path,
                     std::string(kGroundTruthHelp) + "; without it, the run's own figures only");
  report
      ->add_option("--images", arguments->images,
                   "The folder or video the run read: each loop closure's two images side by side")
      ->check(CLI::ExistingPath);
  report
      ->add_option("--max-views", arguments->max_views,
                   "At most this many loop closures shown with --images (false positives first)")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  report->add_option("--out", arguments->out, "HTML file to write")->capture_default_str();
  AddMapOption(*report, &arguments->map);
  AddGroundTruthOptions(*report, &arguments->ground_truth);
  report->callback([arguments] {
    const GroundTruthArguments& ground_truth = arguments->ground_truth;
    std::error_code error;
    const bool image_folder = std::filesystem::is_directory(arguments->images, error);
    const bool dataset_folder = std::filesystem::is_directory(ground_truth.path, error);
    CheckOutputsAreNotInputs({{"the run's CSV", arguments->run},
                              {"--map", arguments->map.path},
                              {"the ground truth", ground_truth.path, dataset_folder},
                              {"--ignore", ground_truth.ignore},
                              {"--images", arguments->images, image_folder}},
                             {{"--out", arguments->out}});
    if (ground_truth.path.empty() &&
        (ground_truth.ignored_as_true || !ground_truth.ignore.empty())) {
      throw CLI::ValidationError(ground_truth.ignored_as_true ? "--ignored-as-true" : "--ignore",
                                 "needs the ground truth");
    }
    RunCsvWriter::CheckCanCreate(arguments->out);
    ReportOptions options;
    options.title = "memloop: " + arguments->run;
    options.time_limit_ms = arguments->map.TimeLimitMs();
    options.parameters = arguments->map.Parameters();
    options.ignored_as_true = ground_truth.ignored_as_true;
    options.images = arguments->images;
    options.max_views = arguments->max_views;
    std::string page;
    if (ground_truth.path.empty()) {
      page = MakeRunReport(ReadRunCsv(arguments->run), options);
    } else {
      const Evaluated evaluated = Evaluate(arguments->run, ground_truth, options.time_limit_ms);
      options.ground_truth = Describe(evaluated.files);
      page = MakeReport(evaluated.rows, evaluated.truth, evaluated.evaluation, options);
    }
    WriteWholeFile(arguments->out, "the report", page);
    std::cout << "wrote " << arguments->out << "\n";
  });
}

void AddEvalCommand(CLI::App& app) {
  struct Arguments {
    std::string run;
    GroundTruthArguments ground_truth;
    bool json = false;
    RunMap map;
  };
  auto arguments = std::make_shared<Arguments>();
  CLI::App* eval = app.add_subcommand(
      "eval",
      "What a run accepted (precision, recall at its T_loop), the best threshold's recall at 100% "
      "precision, the precision-recall curve and Table 1 of a run's CSV");
  eval->add_option("run", arguments->run, "CSV written by memloop run --out")->required();
  eval->add_option("ground_truth", arguments->ground_truth.path, kGroundTruthHelp)->required();
  eval->add_flag("--json", arguments->json, "Print JSON");
  AddMapOption(*eval, &arguments->map);
  AddGroundTruthOptions(*eval, &arguments->ground_truth);
  eval->callback([arguments] {
    const Evaluated e =
        Evaluate(arguments->run, arguments->ground_truth, arguments->map.TimeLimitMs());
    if (arguments->json) {
      std::cout
          << ToJson(e.evaluation, e.truth, e.files, arguments->ground_truth.ignored_as_true).dump(2)
          << "\n";
    } else {
      PrintText(e.evaluation, e.truth, arguments->run, Describe(e.files),
                arguments->ground_truth.ignored_as_true);
    }
  });
}

}  // namespace memloop::cli
