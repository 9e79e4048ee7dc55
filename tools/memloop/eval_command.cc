// memloop eval RUN.csv GROUND_TRUTH [--format auto|mat|image|pairs|matrix] [--json]
//              [--time-limit-ms T] [--ignored-as-true]
// memloop report RUN.csv [GROUND_TRUTH] [--format ...] [--out report.html] [--time-limit-ms T]
//   [--images FOLDER_OR_VIDEO]
//              [--ignored-as-true]
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>

#include "commands.h"
#include "memloop/errors.h"
#include "memloop/evaluation.h"
#include "memloop/ground_truth.h"
#include "memloop/report.h"
#include "memloop/run_csv.h"
#include "util/output_files.h"

namespace memloop::cli {
namespace {

nlohmann::json ToJson(const RunEvaluation& e, const GroundTruth& truth, bool ignored_as_true) {
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
           {{"size", truth.size()},
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
  std::printf("loop closures accepted: %d (true %d, false %d, on ignored pairs %d)\n",
              e.accepted.detections + e.accepted.ignored, e.accepted.true_positives,
              e.accepted.false_positives, e.accepted.ignored);
  std::printf("precision %.1f%%, recall %.1f%%\n", 100 * e.accepted.Precision(),
              100 * e.accepted.Recall());
  std::printf("recall at 100%% precision: %.1f%% (hypotheses >= %.4g accepted)\n",
              100 * e.recall_at_full_precision, e.threshold_at_full_precision);
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
};

// The run's rows and the ground truth over the same images (its size must be the run's).
Evaluated Evaluate(const std::string& run, const std::string& ground_truth,
                   const std::string& format, double time_limit_ms, bool ignored_as_true) {
  std::vector<RunRow> rows = ReadRunCsv(run);
  int image_count = 0;
  for (const RunRow& row : rows) image_count = std::max(image_count, row.image + 1);
  std::vector<std::string> names(image_count);
  for (const RunRow& row : rows) names[row.image] = row.name;
  GroundTruth truth =
      GroundTruth::Load(ground_truth, GroundTruth::ParseFormat(format), names, image_count);
  if (ignored_as_true) truth = truth.IgnoredAsLoops();
  RunEvaluation evaluation = EvaluateRun(rows, truth, time_limit_ms);
  return {std::move(rows), std::move(truth), std::move(evaluation)};
}

// The run's T_time, which its CSV does not record.
void AddTimeLimitOption(CLI::App& command, double* time_limit_ms) {
  command
      .add_option("--time-limit-ms", *time_limit_ms,
                  "T_time of the run (0: none): iterations over it, max / T_time, and the line on "
                  "the time figure")
      ->check(CLI::Validator(
          [](const std::string& text) {
            const double value = std::strtod(text.c_str(), nullptr);
            return std::isfinite(value) && value >= 0 ? std::string()
                                                      : "must be a finite number >= 0";
          },
          "MS>=0"));
}

void AddIgnoredAsTrueFlag(CLI::App& command, bool* ignored_as_true) {
  command.add_flag("--ignored-as-true", *ignored_as_true,
                   "Count the ground truth's ignored pairs as loops (the paper's 2011 protocol): a "
                   "detection on one is true; default: neither true nor false");
}

}  // namespace

void AddReportCommand(CLI::App& app) {
  struct Arguments {
    std::string run;
    std::string ground_truth;
    std::string format = "auto";
    std::string out = "report.html";
    double time_limit_ms = 0;
    bool ignored_as_true = false;
    std::string images;
    int max_views = ReportOptions().max_views;
  };
  auto arguments = std::make_shared<Arguments>();
  CLI::App* report = app.add_subcommand(
      "report", "One self-contained HTML page: PR curve, time per image, memory, detections");
  report->add_option("run", arguments->run, "CSV written by memloop run --out")->required();
  report->add_option("ground_truth", arguments->ground_truth,
                     "Ground truth (as for eval); without it, the run's own figures only");
  report
      ->add_option("--images", arguments->images,
                   "The folder or video the run read: each loop closure's two images side by side")
      ->check(CLI::ExistingPath);
  report
      ->add_option("--max-views", arguments->max_views,
                   "At most this many loop closures shown with --images (false positives first)")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  report->add_option("--format", arguments->format, "auto, mat, image, pairs or matrix")
      ->capture_default_str();
  report->add_option("--out", arguments->out, "HTML file to write")->capture_default_str();
  AddTimeLimitOption(*report, &arguments->time_limit_ms);
  AddIgnoredAsTrueFlag(*report, &arguments->ignored_as_true);
  report->callback([arguments] {
    std::error_code error;
    const bool image_folder = std::filesystem::is_directory(arguments->images, error);
    CheckOutputsAreNotInputs({{"the run's CSV", arguments->run},
                              {"the ground truth", arguments->ground_truth},
                              {"--images", arguments->images, image_folder}},
                             {{"--out", arguments->out}});
    if (arguments->ground_truth.empty() && arguments->ignored_as_true) {
      throw CLI::ValidationError("--ignored-as-true", "needs the ground truth");
    }
    RunCsvWriter::CheckCanCreate(arguments->out);
    ReportOptions options;
    options.title = "memloop: " + arguments->run;
    options.time_limit_ms = arguments->time_limit_ms;
    options.ignored_as_true = arguments->ignored_as_true;
    options.images = arguments->images;
    options.max_views = arguments->max_views;
    std::string page;
    if (arguments->ground_truth.empty()) {
      page = MakeRunReport(ReadRunCsv(arguments->run), options);
    } else {
      const Evaluated evaluated =
          Evaluate(arguments->run, arguments->ground_truth, arguments->format,
                   arguments->time_limit_ms, arguments->ignored_as_true);
      page = MakeReport(evaluated.rows, evaluated.truth, evaluated.evaluation, options);
    }
    WriteWholeFile(arguments->out, "the report", page);
    std::cout << "wrote " << arguments->out << "\n";
  });
}

void AddEvalCommand(CLI::App& app) {
  struct Arguments {
    std::string run;
    std::string ground_truth;
    std::string format = "auto";
    bool json = false;
    double time_limit_ms = 0;
    bool ignored_as_true = false;
  };
  auto arguments = std::make_shared<Arguments>();
  CLI::App* eval = app.add_subcommand(
      "eval", "Precision, recall, the precision-recall curve and Table 1 of a run's CSV");
  eval->add_option("run", arguments->run, "CSV written by memloop run --out")->required();
  eval->add_option("ground_truth", arguments->ground_truth,
                   "Ground truth: .mat, image (255 = loop), CSV of pairs, or text matrix")
      ->required();
  eval->add_option("--format", arguments->format, "auto, mat, image, pairs or matrix")
      ->capture_default_str();
  eval->add_flag("--json", arguments->json, "Print JSON");
  AddTimeLimitOption(*eval, &arguments->time_limit_ms);
  AddIgnoredAsTrueFlag(*eval, &arguments->ignored_as_true);
  eval->callback([arguments] {
    const Evaluated e = Evaluate(arguments->run, arguments->ground_truth, arguments->format,
                                 arguments->time_limit_ms, arguments->ignored_as_true);
    if (arguments->json) {
      std::cout << ToJson(e.evaluation, e.truth, arguments->ignored_as_true).dump(2) << "\n";
    } else {
      PrintText(e.evaluation, e.truth, arguments->run, arguments->ground_truth,
                arguments->ignored_as_true);
    }
  });
}

}  // namespace memloop::cli
