// Steps that must fit in T_time (memloop, issue 9): a repeated step (retrieving one location,
// transferring one) is taken only when the time it is expected to take still ends before a
// deadline on the iteration's clock; the rest waits for a later iteration.
#pragma once

#include <functional>

namespace memloop {

// The time one step is expected to take, at most: the moving average of the last ones measured
// plus twice their moving mean deviation (as TCP bounds a round trip, RFC 6298), since a step that
// waits for a core takes twice the usual. 0 until one is measured. Kept across iterations.
class StepCost {
 public:
  // After this many iterations in a row that deferred the step, it is taken once whatever the
  // estimate (not past the deadline, though), so that one slow step cannot keep all others out
  // for good: its time refreshes the estimate.
  static constexpr int kProbeAfter = 8;

  void Record(double ms);
  // An iteration deferred the step: the deviation decays as a step of the mean time would make
  // it, and the count towards a probe grows.
  void Deferred();

  double expected_ms() const { return mean_ms_ + 2 * deviation_ms_; }
  double mean_ms() const { return mean_ms_; }
  double deviation_ms() const { return deviation_ms_; }
  bool measured() const { return measured_; }
  bool probe_due() const { return deferred_in_a_row_ >= kProbeAfter; }

 private:
  double mean_ms_ = 0;
  double deviation_ms_ = 0;
  bool measured_ = false;
  int deferred_in_a_row_ = 0;  // iterations that deferred the step since the last measured
};

class StepDeadline {
 public:
  StepDeadline() = default;  // none: every step fits (T_time off)
  // `elapsed_ms`: the iteration's time so far; `deadline_ms` on that clock (0 or less: none).
  StepDeadline(std::function<double()> elapsed_ms, double deadline_ms, StepCost* cost)
      : elapsed_ms_(std::move(elapsed_ms)), deadline_ms_(deadline_ms), cost_(cost) {}

  // elapsed + expected (+ `then_ms`, what must still fit after the step) <= deadline.
  bool Fits(double then_ms = 0) const;
  // How long the step may wait before it starts and still fit: deadline - elapsed - expected
  // (infinity without a deadline, 0 at the least).
  double SlackMs() const;
  void Record(double ms) const;
  double ExpectedMs() const;  // the step's expected time, 0 when a probe is due (or no cost)

 private:
  std::function<double()> elapsed_ms_;
  double deadline_ms_ = 0;
  StepCost* cost_ = nullptr;
};

}  // namespace memloop
