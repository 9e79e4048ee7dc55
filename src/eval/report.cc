#include "memloop/report.h"

#include <algorithm>
#include <cstdio>
#include <sstream>

#include "eval/gnuplot.h"
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

// The ground-truth matrix with the run's loop closures, each drawn as eval judges it (Judge):
// true, false, or on an ignored pair (counted neither way, so not drawn as a false positive).
std::string GroundTruthFigure(const std::vector<RunRow>& rows, const GroundTruth& truth) {
  std::vector<std::pair<double, double>> pairs, true_positives, false_positives, ignored, misses;
  for (int query = 0; query < truth.size(); ++query) {
    for (int match = 0; match < query; ++match) {
      if (truth.IsLoop(query, match)) pairs.emplace_back(match, query);
    }
  }
  std::vector<bool> found(truth.size(), false);
  for (const LoopClosureView& view : AcceptedLoopClosures(rows, &truth)) {
    const std::pair<double, double> point(view.match, view.query);
    if (view.verdict == "true") {
      true_positives.push_back(point);
      found[view.query] = true;
    } else {
      (view.verdict == "ignored" ? ignored : false_positives).push_back(point);
    }
  }
  for (int query = 0; query < truth.size(); ++query) {
    if (found[query] || !truth.HasEarlierMatch(query)) continue;
    for (int match = 0; match < query; ++match) {
      if (truth.IsLoop(query, match)) {
        misses.emplace_back(match, query);
        break;
      }
    }
  }
  const double last = truth.size() - 0.5;
  char ranges[160];
  std::snprintf(ranges, sizeof(ranges), "set xrange [-0.5:%g]\nset yrange [%g:-0.5]\n", last, last);
  return RenderSvg(Datablock("pairs", pairs) + Datablock("tp", true_positives) +
                       Datablock("fp", false_positives) + Datablock("ignored", ignored) +
                       Datablock("miss", misses) +
                       "set xlabel 'Matched image'\nset ylabel 'Query image'\nset size ratio -1\n" +
                       ranges + "set key outside right\nset grid\n" +
                       PlotCommand({{!pairs.empty(),
                                     "$pairs using 1:2 with points pt 5 ps 0.35 "
                                     "lc rgb '#c7c7c7' title 'ground truth'"},
                                    {!true_positives.empty(),
                                     "$tp using 1:2 with points pt 7 ps 0.7 "
                                     "lc rgb '#2ca02c' title 'true positive'"},
                                    {!ignored.empty(),
                                     "$ignored using 1:2 with points pt 4 ps 0.8 "
                                     "lc rgb '#9467bd' title 'on an ignored pair'"},
                                    {!false_positives.empty(),
                                     "$fp using 1:2 with points pt 2 ps 1.2 "
                                     "lc rgb '#d62728' title 'false positive'"},
                                    {!misses.empty(),
                                     "$miss using 1:2 with points pt 6 ps 0.9 "
                                     "lc rgb '#ff7f0e' title 'missed'"}}),
                   kHeight + 160, kHeight);
}

// Iterations over T_time and the longest as a multiple of it, when the run's T_time is known.
std::string TimeBoundRows(const RunEvaluation& e) {
  if (e.time_limit_ms <= 0) return "";
  char text[512];
  std::snprintf(text, sizeof(text),
                "<tr><th>iterations over T<sub>time</sub> (%g ms)</th><td>%d (%.2f%%)</td></tr>\n"
                "<tr><th>max iteration / T<sub>time</sub></th><td>%.2f</td></tr>\n"
                "<tr><th>fixed cost (median outside WM's stages)</th><td>%.1f ms</td></tr>\n",
                e.time_limit_ms, e.iterations_over_time_limit, 100 * e.FractionOverTimeLimit(),
                e.max_over_time_limit, e.median_fixed_ms);
  std::string rows = text;
  if (e.median_cpu_share >= 0) {
    std::snprintf(text, sizeof(text),
                  "<tr><th>detector's thread on the CPU (median share of an iteration)</th>"
                  "<td>%.0f%%</td></tr>\n"
                  "<tr><th>over T<sub>time</sub> with it on the CPU under %.0f%% of the time"
                  "</th><td>%d</td></tr>\n",
                  100 * e.median_cpu_share, 100 * kWaitedCpuShare, e.over_time_limit_waiting);
    rows += text;
  }
  return rows;
}

std::string SummaryTable(const RunEvaluation& e, const GroundTruth& truth, bool ignored_as_true) {
  char text[2048];
  std::snprintf(
      text, sizeof(text),
      "<table>\n"
      "<tr><th>images</th><td>%d</td></tr>\n"
      "<tr><th>ground truth</th><td>%d pairs, %d images with a loop%s</td></tr>\n"
      "<tr><th>loop closures accepted</th><td>%d (true %d, false %d, on ignored pairs "
      "%d)</td></tr>\n"
      "<tr><th>precision</th><td>%.1f%%</td></tr>\n"
      "<tr><th>recall</th><td>%.1f%%</td></tr>\n"
      "<tr><th>recall at 100%% precision</th><td>%.1f%% (hypotheses &ge; %.4g)</td></tr>\n"
      "<tr><th>max WM size</th><td>%d locations</td></tr>\n"
      "<tr><th>max dictionary size</th><td>%d words</td></tr>\n"
      "<tr><th>max iteration time</th><td>%.3f s</td></tr>\n"
      "<tr><th>median iteration time</th><td>%.1f ms</td></tr>\n"
      "%s"
      "</table>\n",
      e.images, truth.PairCount(), e.accepted.loop_images,
      ignored_as_true ? " (ignored pairs counted as loops: --ignored-as-true)" : "",
      e.accepted.detections + e.accepted.ignored, e.accepted.true_positives,
      e.accepted.false_positives, e.accepted.ignored, 100 * e.accepted.Precision(),
      100 * e.accepted.Recall(), 100 * e.recall_at_full_precision, e.threshold_at_full_precision,
      e.max_wm_size, e.max_dictionary_size, e.max_iteration_ms / 1000, e.median_iteration_ms,
      TimeBoundRows(e).c_str());
  return text;
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
         "\n<style>\nbody { font-family: sans-serif; max-width: 960px; margin: 2em auto; color: "
         "#222; }\n"
         "table { border-collapse: collapse; }\nth, td { border: 1px solid #ccc; padding: 4px "
         "10px; text-align: left; }\n.figure { margin: 2em 0; }\n.caption { color: #555; }\n"
         ".views tr.false td:first-child { color: #d62728; font-weight: bold; }\n"
         ".views tr.ignored td:first-child { color: #9467bd; }\n</style>\n"
         "</head>\n<body data-rendered=\"0\" data-errors=\"\">\n<h1>" +
         HtmlEscaped(title) + "</h1>\n";
}

// What needs no ground truth: time per image, WM and dictionary, and the views when asked for.
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

std::string Views(const std::vector<RunRow>& rows, const GroundTruth* truth,
                  const ReportOptions& options) {
  if (options.images.empty()) return "";
  return LoopClosureViewsSection(AcceptedLoopClosures(rows, truth), rows, options.images,
                                 options.max_views);
}

}  // namespace

std::string MakeReport(const std::vector<RunRow>& rows, const GroundTruth& truth,
                       const RunEvaluation& evaluation, const ReportOptions& options) {
  std::string page =
      PageStart(options.title) + SummaryTable(evaluation, truth, options.ignored_as_true);
  page += Figure("precision-recall", "Precision-recall curve",
                 "Every iteration's highest hypothesis, accepted when its value is at least the "
                 "threshold; the run's own operating point is marked.",
                 PrecisionRecallFigure(evaluation));
  page += RunFigures(rows, options);
  page += Figure("ground-truth", "Ground truth and detections",
                 "Grey: ground-truth pairs (query, earlier match). Green: true positives. Purple: "
                 "loop closures on pairs the ground truth ignores (counted neither way). Red: "
                 "false positives. Orange: images with a ground-truth loop and no true detection.",
                 GroundTruthFigure(rows, truth));
  return page + Views(rows, &truth, options) + "</body>\n</html>\n";
}

std::string MakeRunReport(const std::vector<RunRow>& rows, const ReportOptions& options) {
  // The time bound and the maxima, from the rows alone (no pair is judged).
  const RunEvaluation e =
      EvaluateRun(rows, GroundTruth(cv::Mat::zeros(1, 1, CV_8U)), options.time_limit_ms);
  int loop_closures = 0;
  for (const RunRow& row : rows) loop_closures += !row.matched_images.empty();
  char text[1024];
  std::snprintf(text, sizeof(text),
                "<table>\n<tr><th>images</th><td>%d</td></tr>\n"
                "<tr><th>loop closures accepted</th><td>%d (no ground truth given)</td></tr>\n"
                "<tr><th>max WM size</th><td>%d locations</td></tr>\n"
                "<tr><th>max dictionary size</th><td>%d words</td></tr>\n"
                "<tr><th>max iteration time</th><td>%.3f s</td></tr>\n"
                "<tr><th>median iteration time</th><td>%.1f ms</td></tr>\n%s</table>\n",
                e.images, loop_closures, e.max_wm_size, e.max_dictionary_size,
                e.max_iteration_ms / 1000, e.median_iteration_ms, TimeBoundRows(e).c_str());
  return PageStart(options.title) + text + RunFigures(rows, options) +
         Views(rows, nullptr, options) + "</body>\n</html>\n";
}

}  // namespace memloop
