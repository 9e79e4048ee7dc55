// `memloop report`: one self-contained HTML file (no network, opens from disk) with the
// precision-recall curve, the processing time per image with the T_time line (the paper's
// Fig. 4), WM and dictionary sizes over the run, the ground-truth matrix with the detections
// (true positives, false positives, loop closures on ignored pairs and misses in different
// colours), the summary table and, given the run's images, each loop closure's two images.
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
  // The folder or video the run read: when given, a section shows each loop closure's two images
  // side by side (thumbnails inlined), at most `max_views` of them, false positives first.
  std::string images;
  int max_views = 200;
};

// The page as text. Throws Error when gnuplot cannot draw, InputError naming options.images when
// it is not the run's sequence.
std::string MakeReport(const std::vector<RunRow>& rows, const GroundTruth& truth,
                       const RunEvaluation& evaluation, const ReportOptions& options);

// Without ground truth: the summary, time and memory figures and the views, no pair judged.
std::string MakeRunReport(const std::vector<RunRow>& rows, const ReportOptions& options);

}  // namespace memloop
