#include "memloop/report.h"

#include <algorithm>
#include <cstdio>
#include <set>
#include <sstream>

#include "eval/gnuplot.h"
#include "eval/ground_truth_figure.h"
#include "eval/html_escape.h"
#include "eval/loop_closure_views.h"

namespace memloop {
namespace {

constexpr int kWidth = 720;
constexpr int kHeight = 420;

// A gnuplot datablock named `name` with one point per line.
std::string Datablock(const std::string& name,
                      const std::vector<std::pair<double, double>>& points) {
  std::ostringstream block;
  block << "$" << name << " << EOD\n";
  for (const auto& [x, y] : points) block << x << " " << y << "\n";
  block << "EOD\n";
  return block.str();
}

// "plot" with the clauses of the sets that have points (gnuplot refuses to plot nothing).
std::string PlotCommand(const std::vector<std::pair<bool, std::string>>& clauses) {
  std::string plot;
  for (const auto& [has_points, clause] : clauses) {
    if (has_points) plot += (plot.empty() ? "plot " : ", ") + clause;
  }
  return plot.empty() ? "plot NaN notitle\n" : plot + "\n";
}

std::string PrecisionRecallFigure(const RunEvaluation& e) {
  std::vector<std::pair<double, double>> curve;
  for (const auto& point : e.curve) curve.emplace_back(point.recall, point.precision);
  const std::vector<std::pair<double, double>> run = {
      {e.accepted.Recall(), e.accepted.Precision()}};
  return RenderSvg(
      Datablock("curve", curve) + Datablock("run", run) +
          "set xlabel 'Recall'\nset ylabel 'Precision'\nset grid\n"
          "set xrange [0:1]\nset yrange [0:1.05]\nset key bottom left\n" +
          PlotCommand({{!curve.empty(),
                        "$curve using 1:2 with linespoints lw 2 pt 7 ps 0.5 "
                        "lc rgb '#1f77b4' title 'threshold swept over the hypotheses'"},
                       {true,
                        "$run using 1:2 with points pt 9 ps 2.5 "
                        "lc rgb '#d62728' title 'the run (its T_loop)'"}}),
      kWidth, kHeight);
}

std::string TimeFigure(const std::vector<RunRow>& rows, double time_limit_ms) {
  std::vector<std::pair<double, double>> times;
  for (const RunRow& row : rows) times.emplace_back(row.image, row.iteration_ms);
  char limit[128] = "";
  if (time_limit_ms > 0) {
    std::snprintf(limit, sizeof(limit),
                  "%g with lines lw 2 lc rgb '#d62728' title 'T_{time} = %g ms'", time_limit_ms,
                  time_limit_ms);
  }
  return RenderSvg(Datablock("times", times) +
                       "set xlabel 'Image'\nset ylabel 'Processing time (ms)'\nset grid\n"
                       "set yrange [0:*]\nset key top left\n" +
                       PlotCommand({{true,
                                     "$times using 1:2 with points pt 7 ps 0.4 "
                                     "lc rgb '#1f77b4' title 'iteration time'"},
                                    {time_limit_ms > 0, limit}}),
                   kWidth, kHeight);
}

std::string MemoryFigure(const std::vector<RunRow>& rows) {
  std::vector<std::pair<double, double>> wm;
  std::vector<std::pair<double, double>> words;
  for (const RunRow& row : rows) {
    wm.emplace_back(row.image, row.wm_size);
    words.emplace_back(row.image, row.dictionary_size);
  }
  return RenderSvg(Datablock("wm", wm) + Datablock("words", words) +
                       "set xlabel 'Image'\nset ylabel 'WM size (locations)'\n"
                       "set y2label 'Dictionary size (words)'\nset ytics nomirror\nset y2tics\n"
                       "set yrange [0:*]\nset y2range [0:*]\nset grid\nset key top left\n" +
                       PlotCommand({{true,
                                     "$wm using 1:2 with lines lw 2 lc rgb '#1f77b4' "
                                     "title 'WM size'"},
                                    {true,
                                     "$words using 1:2 axes x1y2 with lines lw 2 "
                                     "lc rgb '#ff7f0e' title 'dictionary size'"}}),
                   kWidth, kHeight);
}

template <typename... Values>
std::string Printed(const char* format, Values... values) {
  char text[1024];
  std::snprintf(text, sizeof(text), format, values...);
  return text;
}

// Iterations over T_time and the longest as a multiple of it, when the run's T_time is known
// (TimeLimitRow gives T_time itself).
std::string TimeBoundRows(const RunEvaluation& e) {
  if (e.time_limit_ms <= 0) return "";
  std::string rows = Printed(
      "<tr><th>iterations over T<sub>time</sub></th><td>%d (%.2f%%)</td></tr>\n"
      "<tr><th>max iteration / T<sub>time</sub></th><td>%.2f</td></tr>\n"
      "<tr><th>fixed cost (median outside WM's stages)</th><td>%.1f ms</td></tr>\n",
      e.iterations_over_time_limit, 100 * e.FractionOverTimeLimit(), e.max_over_time_limit,
      e.median_fixed_ms);
  if (e.median_cpu_share >= 0) {
    rows += Printed(
        "<tr><th>detector's thread on the CPU (median share of an iteration)</th>"
        "<td>%.0f%%</td></tr>\n"
        "<tr><th>over T<sub>time</sub> with it on the CPU under %.0f%% of the time"
        "</th><td>%d</td></tr>\n",
        100 * e.median_cpu_share, 100 * kWaitedCpuShare, e.over_time_limit_waiting);
  }
  return rows;
}

// "T_time", the run's time bound, or how to give it.
std::string TimeLimitRow(const RunEvaluation& e) {
  return e.time_limit_ms > 0
             ? "<tr><th>T<sub>time</sub></th><td>" + Printed("%g ms", e.time_limit_ms) +
                   "</td></tr>\n" + TimeBoundRows(e)
             : "<tr><th>T<sub>time</sub></th><td>not given (--map or --time-limit-ms)</td></tr>\n";
}

// The map's parameters: those that differ from the defaults in the row, all of them folded.
std::string ParameterRows(const std::vector<ReportParameter>& parameters) {
  if (parameters.empty()) {
    return "<tr><th>parameters</th><td>not given (--map: the run's map records them)</td></tr>\n";
  }
  std::string changed, all;
  for (const ReportParameter& parameter : parameters) {
    const std::string pair = HtmlEscaped(parameter.name) + "=" + HtmlEscaped(parameter.value);
    if (parameter.value != parameter.default_value) changed += (changed.empty() ? "" : ", ") + pair;
    all += "<tr><td>" + HtmlEscaped(parameter.name) + "</td><td>" + HtmlEscaped(parameter.value) +
           "</td></tr>";
  }
  return "<tr><th>parameters</th><td>" + (changed.empty() ? "the defaults" : changed) +
         " <details><summary>all " + std::to_string(parameters.size()) + "</summary><table>" + all +
         "</table></details></td></tr>\n";
}

// The common rows after the verdicts: time, memory and parameters.
std::string RunRows(const RunEvaluation& e, const ReportOptions& options) {
  return TimeLimitRow(e) + "<tr><th>repeatability</th><td>" + TimeDecidedLine(e) + "</td></tr>\n" +
         Printed("<tr><th>iteration time</th><td>median %.1f ms, max %.3f s</td></tr>\n",
                 e.median_iteration_ms, e.max_iteration_ms / 1000) +
         Printed("<tr><th>max WM size, dictionary</th><td>%d locations, %d words</td></tr>\n",
                 e.max_wm_size, e.max_dictionary_size) +
         ParameterRows(options.parameters);
}

// What the run delivered first, then what a threshold chosen afterwards would have given.
std::string SummaryTable(const RunEvaluation& e, const GroundTruth& truth,
                         const ReportOptions& options) {
  return "<table class=\"summary\">\n" +
         Printed("<tr><th>images</th><td>%d</td></tr>\n", e.images) +
         "<tr><th>ground truth</th><td>" + HtmlEscaped(options.ground_truth) +
         Printed(": %d pairs, %d images with a loop", truth.PairCount(), e.accepted.loop_images) +
         (options.ignored_as_true ? " (ignored pairs counted as loops: --ignored-as-true)" : "") +
         "</td></tr>\n" +
         Printed(
             "<tr class=\"run\"><th>the run accepted, at its T<sub>loop</sub></th><td>%d "
             "loop closures (true %d, false %d, on ignored pairs %d): precision %.1f%%, "
             "recall %.1f%%</td></tr>\n",
             e.accepted.detections + e.accepted.ignored, e.accepted.true_positives,
             e.accepted.false_positives, e.accepted.ignored, 100 * e.accepted.Precision(),
             100 * e.accepted.Recall()) +
         Printed(
             "<tr><th>best threshold, chosen afterwards</th><td>recall at 100%% precision "
             "%.1f%% (hypotheses &ge; %.4g)</td></tr>\n",
             100 * e.recall_at_full_precision, e.threshold_at_full_precision) +
         RunRows(e, options) + "</table>\n";
}

// Records page errors and, once loaded, how many figures drew something and how many thumbnails
// decoded, on <body> (data-errors, data-rendered, data-images), where a headless browser's DOM
// dump can read them.
constexpr const char* kCheckScript = R"(<script>
window.memloopErrors = [];
window.addEventListener('error', function (e) { window.memloopErrors.push(String(e.message)); });
window.addEventListener('load', function () {
  var rendered = 0;
  document.querySelectorAll('.figure svg').forEach(function (svg) {
    var box = svg.getBBox();
    if (box.width > 0 && box.height > 0 && svg.querySelectorAll('path, circle, use').length > 0) rendered++;
  });
  document.body.setAttribute('data-rendered', String(rendered));
  var images = 0;
  document.querySelectorAll('.views img').forEach(function (img) {
    if (img.complete && img.naturalWidth > 0) images++;
  });
  document.body.setAttribute('data-images', String(images));
  var first = document.querySelector('.views tr img');
  document.body.setAttribute('data-first-pair-bottom', first ?
      String(Math.round(first.closest('tr').getBoundingClientRect().bottom + window.scrollY)) : '-1');
  document.body.setAttribute('data-errors', window.memloopErrors.join(' | '));
});
</script>)";

std::string Figure(const std::string& id, const std::string& title, const std::string& caption,
                   const std::string& svg) {
  return "<section class=\"figure\" id=\"" + id + "\">\n<h2>" + title + "</h2>\n" + svg +
         "\n<p class=\"caption\">" + caption + "</p>\n</section>\n";
}

}  // namespace

namespace {

// The page up to the summary table.
std::string PageStart(const std::string& title) {
  return "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<title>" +
         HtmlEscaped(title) + "</title>\n" + kCheckScript +
         "\n<style>\nbody { font-family: sans-serif; max-width: 1100px; margin: 1em auto; color: "
         "#222; }\nh1 { font-size: 1.4em; margin: 0.3em 0; }\nh2 { font-size: 1.2em; }\n"
         "table { border-collapse: collapse; }\nth, td { border: 1px solid #ccc; padding: 3px "
         "8px; text-align: left; vertical-align: top; }\n.summary th { width: 300px; }\n.summary "
         "tr.run td { font-weight: bold; }"
         "\n.figure { margin: 2em 0; }\n.caption { color: #555; }\n"
         ".views td:first-child { width: 260px; }\n.views tr:target { outline: 3px solid #1f77b4; }"
         "\n.views tr.false .verdict { color: #d62728; font-weight: bold; }\n"
         ".views tr.missed .verdict { color: #ff7f0e; font-weight: bold; }\n"
         ".views tr.ignored .verdict { color: #9467bd; }\n</style>\n"
         "</head>\n<body data-rendered=\"0\" data-errors=\"\">\n<h1>" +
         HtmlEscaped(title) + "</h1>\n";
}

// What needs no ground truth: time per image, WM and dictionary.
std::string RunFigures(const std::vector<RunRow>& rows, const ReportOptions& options) {
  std::string page = Figure("time", "Processing time per image",
                            "As the paper's Fig. 4: the time of each iteration, with the time "
                            "limit T<sub>time</sub> when given.",
                            TimeFigure(rows, options.time_limit_ms));
  page += Figure("memory", "Working Memory and dictionary",
                 "Locations in WM and words in the dictionary after each iteration.",
                 MemoryFigure(rows));
  return page;
}

std::vector<std::string> Names(const std::vector<RunRow>& rows) {
  std::vector<std::string> names;
  for (const RunRow& row : rows) {
    if (row.image >= static_cast<ImageIndex>(names.size())) names.resize(row.image + 1);
    names[row.image] = row.name;
  }
  return names;
}

// The queries that have a row in the views section (ChooseViews' list): what the figure links.
std::set<ImageIndex> Listed(const std::vector<LoopClosureView>& views) {
  std::set<ImageIndex> listed;
  for (const LoopClosureView& view : ChooseViews(views, kMaxListedViews)) listed.insert(view.query);
  return listed;
}

}  // namespace

std::string MakeReport(const std::vector<RunRow>& rows, const GroundTruth& truth,
                       const RunEvaluation& evaluation, const ReportOptions& options) {
  std::vector<LoopClosureView> views = AcceptedLoopClosures(rows, &truth);
  const std::vector<LoopClosureView> misses = MissedLoopClosures(rows, truth);
  views.insert(views.end(), misses.begin(), misses.end());
  std::string page = PageStart(options.title) + SummaryTable(evaluation, truth, options);
  page += LoopClosureViewsSection(views, rows, options.images, options.max_views);
  page += Figure("ground-truth", "Ground truth, loop closures and misses",
                 "Grey: ground-truth pairs (query, earlier match). Green: true positives. Purple: "
                 "loop closures on pairs the ground truth ignores (counted neither way). Red: "
                 "false positives. Orange: images with a ground-truth loop and no loop closure, "
                 "at their true match. A point leads to its images.",
                 GroundTruthSvg(truth, views, Listed(views), Names(rows)));
  page += Figure("precision-recall", "Precision-recall curve",
                 "Every iteration's highest hypothesis, accepted when its value is at least the "
                 "threshold; the run's own operating point is marked.",
                 PrecisionRecallFigure(evaluation));
  return page + RunFigures(rows, options) + "</body>\n</html>\n";
}

std::string MakeRunReport(const std::vector<RunRow>& rows, const ReportOptions& options) {
  // The time bound and the maxima, from the rows alone (no pair is judged).
  const RunEvaluation e =
      EvaluateRun(rows, GroundTruth(cv::Mat::zeros(1, 1, CV_8U)), options.time_limit_ms);
  int loop_closures = 0;
  for (const RunRow& row : rows) loop_closures += !row.matched_images.empty();
  const std::string summary =
      "<table class=\"summary\">\n" + Printed("<tr><th>images</th><td>%d</td></tr>\n", e.images) +
      Printed(
          "<tr class=\"run\"><th>loop closures accepted</th><td>%d (no ground truth given)"
          "</td></tr>\n",
          loop_closures) +
      RunRows(e, options) + "</table>\n";
  return PageStart(options.title) + summary +
         LoopClosureViewsSection(AcceptedLoopClosures(rows, nullptr), rows, options.images,
                                 options.max_views) +
         RunFigures(rows, options) + "</body>\n</html>\n";
}

}  // namespace memloop
