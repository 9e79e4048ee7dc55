// Precision and recall of loop-closure detections against ground truth (paper Sec. IV, after
// Cummins & Newman): a detection is true when the query image and any image of the matched
// location form a ground-truth pair (a location that absorbed others stands for all of their
// images); recall counts the images that have at least one ground-truth match.
#pragma once

#include <utility>
#include <vector>

#include "memloop/ground_truth.h"
#include "memloop/run_csv.h"
#include "memloop/types.h"

namespace memloop {

struct Detection {
  ImageIndex query = kNoImage;
  std::vector<ImageIndex> matched_images;
};

struct PrecisionRecall {
  int detections = 0;  // true + false (not those on ignored pairs)
  int true_positives = 0;
  int false_positives = 0;
  int ignored = 0;      // detections on pairs the ground truth ignores: counted neither way
  int loop_images = 0;  // images with at least one earlier ground-truth match
  double Precision() const { return detections == 0 ? 1.0 : double(true_positives) / detections; }
  double Recall() const { return loop_images == 0 ? 0.0 : double(true_positives) / loop_images; }
};

PrecisionRecall Evaluate(const std::vector<Detection>& detections, const GroundTruth& truth);

// One detection as Evaluate counts it: true when the query and any matched image form a pair;
// ignored when none does but one pair is ignored by the ground truth; else false.
enum class Verdict { kTrue, kFalse, kIgnored };
Verdict Judge(ImageIndex query, const std::vector<ImageIndex>& matched_images,
              const GroundTruth& truth);

// A point of the precision-recall curve: the hypotheses of value >= threshold accepted.
struct PrecisionRecallPoint {
  double threshold = 0;
  int true_positives = 0;
  int false_positives = 0;
  double precision = 1;
  double recall = 0;
};

// What `memloop eval` reports for a run against ground truth.
struct RunEvaluation {
  PrecisionRecall accepted;  // the loop closures the run accepted (at its T_loop)
  // Sweeping the acceptance threshold over every eligible highest hypothesis (one that T_loop
  // alone decided: RunRow::hypothesis_eligible), highest first;
  // hypotheses of equal value enter together (one point per distinct value).
  std::vector<PrecisionRecallPoint> curve;
  double recall_at_full_precision = 0;  // the best recall of a point with no false positive
  double threshold_at_full_precision = 0;
  // The paper's Table 1 row.
  int images = 0;
  int max_wm_size = 0;
  int max_dictionary_size = 0;
  double max_iteration_ms = 0;
  double median_iteration_ms = 0;
  // The time bound (issue 9), when T_time is given: iterations that took longer than T_time, and
  // the longest iteration as a multiple of T_time (the paper's worst case: 1.75 s / 1.4 s = 1.25).
  // The floor under T_time: the median of what an iteration spends outside the stages that grow
  // with WM (features, quantization, rehearsal, retrieval, transfer, checkpoint). A T_time under
  // floor / memory.time_target cannot be held by transferring WM (issue 37).
  double median_fixed_ms = 0;
  double time_limit_ms = 0;  // 0: not given, the three below are 0
  int iterations_over_time_limit = 0;
  double max_over_time_limit = 0;
  // Of those over T_time, the iterations whose thread was on the CPU under kWaitedCpuShare of
  // their time (the CSV's cpu_ms; 0 without it).
  int over_time_limit_waiting = 0;
  // The detector's thread on the CPU: the median over iterations of cpu_ms / iteration_ms; -1
  // when the CSV does not say (runs before the column, or a system without a thread clock).
  double median_cpu_share = -1;
  // Iterations in which the time limit changed something (RunRow::time_decided), and the first;
  // a run with none gives the same rows on any machine and under any load.
  int time_decided_iterations = 0;
  ImageIndex first_time_decided = kNoImage;
  std::string first_time_decided_what;
  double FractionOverTimeLimit() const {
    return images == 0 ? 0.0 : double(iterations_over_time_limit) / images;
  }
};

// One line on whether the time limit changed the run's results (RunEvaluation::
// time_decided_iterations): nothing, so the run repeats exactly; or in how many iterations, the
// first and what.
std::string TimeDecidedLine(const RunEvaluation& evaluation);

// The detector's thread's CPU time over an iteration's wall time (StageTimes::cpu_ms / total_ms)
// is near 1 when the thread had a core; an iteration that took longer while its thread ran less
// than this share of it waited: for the CPU (other programs at the same priority), the search's
// helper thread or the disk, not for the detector's own work (issue 37). Measured, 6,300
// generated images at a tight T_time: median 0.93-0.94 on a quiet 2-core machine, 0.29-0.35 with
// another program's two busy loops (0.96 with them under a real-time priority).
constexpr double kWaitedCpuShare = 0.5;

// The median of cpu_ms / wall_ms over iterations (pairs cpu_ms, wall_ms); -1 when no iteration's
// CPU time was measured (every cpu_ms 0 or negative).
double MedianCpuShare(const std::vector<std::pair<double, double>>& cpu_and_wall_ms);

// Rows as read by ReadRunCsv; ground truth over the same sequence; the run's T_time (0: none).
RunEvaluation EvaluateRun(const std::vector<RunRow>& rows, const GroundTruth& truth,
                          double time_limit_ms = 0);

}  // namespace memloop
