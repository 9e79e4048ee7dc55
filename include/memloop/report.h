// `memloop report`: one self-contained HTML file (no network, opens from disk). First the
// summary (what the run accepted at its T_loop, then the best threshold's recall at 100%
// precision, T_time, the parameters), then the loop closures and the misses by file name (with
// their images when given: the query, the place chosen, the true match), then the ground-truth
// matrix with the detections, each point linked to its pair, the precision-recall curve, the
// processing time per image with the T_time line (the paper's Fig. 4), WM and dictionary sizes.
// The matrix is memloop's own SVG; the other figures are drawn by gnuplot as SVG and inlined.
#pragma once

#include <string>
#include <vector>

#include "memloop/evaluation.h"
#include "memloop/ground_truth.h"
#include "memloop/run_csv.h"

namespace memloop {

// One of the run's parameters, as its map records it.
struct ReportParameter {
  std::string name;
  std::string value;
  std::string default_value;
};

struct ReportOptions {
  std::string title = "memloop run";
  double time_limit_ms = 0;      // T_time of the run, drawn when > 0
  bool ignored_as_true = false;  // the ground truth was made GroundTruth::IgnoredAsLoops(): said so
  std::string ground_truth;      // what the ground truth was read from, named in the summary
  // The folder or video the run read: when given, a section shows each loop closure's two images
  // side by side (thumbnails inlined), at most `max_views` of them, false positives first.
  std::string images;
  int max_views = 200;
  std::vector<ReportParameter> parameters;  // the run's (from its map); empty: not known
};

// The page as text. Throws Error when gnuplot cannot draw, InputError naming options.images when
// it is not the run's sequence.
std::string MakeReport(const std::vector<RunRow>& rows, const GroundTruth& truth,
                       const RunEvaluation& evaluation, const ReportOptions& options);

// Without ground truth: the summary, time and memory figures and the views, no pair judged.
std::string MakeRunReport(const std::vector<RunRow>& rows, const ReportOptions& options);

}  // namespace memloop
