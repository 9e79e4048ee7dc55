#include "memloop/evaluation.h"

#include <algorithm>

namespace memloop {

Verdict Judge(ImageIndex query, const std::vector<ImageIndex>& images, const GroundTruth& truth) {
  bool ignored = false;
  for (ImageIndex match : images) {
    if (match >= query) continue;
    const GroundTruth::Label label = truth.At(query, match);
    if (label == GroundTruth::kLoop) return Verdict::kTrue;
    ignored = ignored || label == GroundTruth::kIgnored;
  }
  return ignored ? Verdict::kIgnored : Verdict::kFalse;
}

namespace {

// Median and max iteration, and with T_time, the iterations over it and max / T_time.
void AddTimeBound(const std::vector<RunRow>& rows, double time_limit_ms, RunEvaluation* e) {
  std::vector<double> times;
  for (const RunRow& row : rows) times.push_back(row.iteration_ms);
  if (times.empty()) return;
  std::sort(times.begin(), times.end());
  e->median_iteration_ms = times[times.size() / 2];
  e->max_iteration_ms = times.back();
  std::vector<double> fixed;
  for (const RunRow& row : rows)
    fixed.push_back(std::max(0.0, row.iteration_ms - row.wm_stages_ms));
  std::nth_element(fixed.begin(), fixed.begin() + fixed.size() / 2, fixed.end());
  e->median_fixed_ms = fixed[fixed.size() / 2];
  std::vector<std::pair<double, double>> cpu_and_wall;
  for (const RunRow& row : rows) cpu_and_wall.emplace_back(row.cpu_ms, row.iteration_ms);
  e->median_cpu_share = MedianCpuShare(cpu_and_wall);
  if (time_limit_ms <= 0) return;
  e->time_limit_ms = time_limit_ms;
  e->iterations_over_time_limit =
      static_cast<int>(times.end() - std::upper_bound(times.begin(), times.end(), time_limit_ms));
  e->max_over_time_limit = e->max_iteration_ms / time_limit_ms;
  for (const RunRow& row : rows) {
    e->over_time_limit_waiting += row.iteration_ms > time_limit_ms && row.cpu_ms >= 0 &&
                                  row.cpu_ms < kWaitedCpuShare * row.iteration_ms;
  }
}

}  // namespace

double MedianCpuShare(const std::vector<std::pair<double, double>>& cpu_and_wall_ms) {
  std::vector<double> shares;
  bool measured = false;
  for (const auto& [cpu_ms, wall_ms] : cpu_and_wall_ms) {
    measured = measured || cpu_ms > 0;
    if (wall_ms > 0 && cpu_ms >= 0) shares.push_back(std::min(1.0, cpu_ms / wall_ms));
  }
  if (!measured || shares.empty()) return -1;
  std::nth_element(shares.begin(), shares.begin() + shares.size() / 2, shares.end());
  return shares[shares.size() / 2];
}

PrecisionRecall Evaluate(const std::vector<Detection>& detections, const GroundTruth& truth) {
  PrecisionRecall result;
  for (ImageIndex query = 0; query < truth.size(); ++query) {
    result.loop_images += truth.HasEarlierMatch(query);
  }
  for (const Detection& detection : detections) {
    switch (Judge(detection.query, detection.matched_images, truth)) {
      case Verdict::kTrue:
        ++result.true_positives;
        break;
      case Verdict::kFalse:
        ++result.false_positives;
        break;
      case Verdict::kIgnored:
        ++result.ignored;
        break;
    }
  }
  result.detections = result.true_positives + result.false_positives;
  return result;
}

RunEvaluation EvaluateRun(const std::vector<RunRow>& rows, const GroundTruth& truth,
                          double time_limit_ms) {
  RunEvaluation evaluation;
  AddTimeBound(rows, time_limit_ms, &evaluation);
  std::vector<Detection> accepted;
  struct Hypothesis {
    double value;
    Verdict verdict;
  };
  std::vector<Hypothesis> hypotheses;
  for (const RunRow& row : rows) {
    evaluation.images += 1;
    evaluation.max_wm_size = std::max(evaluation.max_wm_size, row.wm_size);
    evaluation.max_dictionary_size = std::max(evaluation.max_dictionary_size, row.dictionary_size);
    // Another robot's places (a fleet's map) are judged by EvaluateFleet, not by this run's truth.
    if (!row.matched_images.empty() && row.matched_robot.empty()) {
      accepted.push_back({row.image, row.matched_images});
    }
    if (!row.time_decided.empty() && evaluation.time_decided_iterations++ == 0) {
      evaluation.first_time_decided = row.image;
      evaluation.first_time_decided_what = row.time_decided;
    }
    if (row.hypothesis_id != kNoLocation && row.hypothesis_eligible &&
        row.hypothesis_robot.empty()) {
      hypotheses.push_back({row.hypothesis_value, Judge(row.image, row.hypothesis_images, truth)});
    }
  }
  evaluation.accepted = Evaluate(accepted, truth);
  const int loop_images = evaluation.accepted.loop_images;
  std::stable_sort(hypotheses.begin(), hypotheses.end(),
                   [](const Hypothesis& a, const Hypothesis& b) { return a.value > b.value; });
  PrecisionRecallPoint point;
  for (size_t i = 0; i < hypotheses.size(); ++i) {
    point.true_positives += hypotheses[i].verdict == Verdict::kTrue;
    point.false_positives += hypotheses[i].verdict == Verdict::kFalse;
    // Equal values cannot be told apart by a threshold: they enter together.
    if (i + 1 < hypotheses.size() && hypotheses[i + 1].value == hypotheses[i].value) continue;
    point.threshold = hypotheses[i].value;
    const int detections = point.true_positives + point.false_positives;
    point.precision = detections == 0 ? 1.0 : double(point.true_positives) / detections;
    point.recall = loop_images == 0 ? 0.0 : double(point.true_positives) / loop_images;
    evaluation.curve.push_back(point);
    if (point.false_positives == 0 && point.recall >= evaluation.recall_at_full_precision) {
      evaluation.recall_at_full_precision = point.recall;
      evaluation.threshold_at_full_precision = point.threshold;
    }
  }
  return evaluation;
}

std::string TimeDecidedLine(const RunEvaluation& e) {
  if (e.time_decided_iterations == 0) {
    return "time decided nothing: the same images give the same rows on any machine and under any "
           "load";
  }
  return "time decided something in " + std::to_string(e.time_decided_iterations) +
         " iterations (the first: image " + std::to_string(e.first_time_decided) + ", " +
         e.first_time_decided_what +
         "): from there, a run on another machine or under another load may differ (CSV column "
         "time_decided)";
}

}  // namespace memloop
