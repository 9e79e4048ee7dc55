// `memloop report`: one self-contained HTML file (no network, opens from disk) with the
// precision-recall curve, the processing time per image with the T_time line (the paper's
// Fig. 4), WM and dictionary sizes over the run, the ground-truth matrix with the detections
// (true positives, false positives and misses in different colours) and the summary table.
// Figures are drawn by gnuplot as SVG and inlined.
#pragma once

#include <string>
#include <vector>

#include "memloop/evaluation.h"
#include "memloop/ground_truth.h"
#include "memloop/run_csv.h"

namespace memloop {

struct ReportOptions {
  std::string title = "memloop run";
  double time_limit_ms = 0;      // T_time of the run, drawn when > 0
  bool ignored_as_true = false;  // the ground truth was made GroundTruth::IgnoredAsLoops(): said so
};

// The page as text. Throws Error when gnuplot cannot draw.
std::string MakeReport(const std::vector<RunRow>& rows, const GroundTruth& truth,
                       const RunEvaluation& evaluation, const ReportOptions& options);

}  // namespace memloop
