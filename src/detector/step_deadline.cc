#include "detector/step_deadline.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace memloop {

void StepCost::Record(double ms) {
  // RFC 6298's weights (1/8 for the mean, 1/4 for the deviation): the bound follows the map's
  // growth and the machine's load within a few steps.
  deferred_in_a_row_ = 0;
  if (!measured_) {
    mean_ms_ = ms;
    deviation_ms_ = ms / 2;
    measured_ = true;
    return;
  }
  deviation_ms_ += (std::abs(ms - mean_ms_) - deviation_ms_) / 4;
  mean_ms_ += (ms - mean_ms_) / 8;
}

void StepCost::Deferred() {
  deviation_ms_ -= deviation_ms_ / 4;
  ++deferred_in_a_row_;
}

bool StepDeadline::Fits(double then_ms) const {
  if (!elapsed_ms_ || deadline_ms_ <= 0) return true;
  return elapsed_ms_() + ExpectedMs() + then_ms <= deadline_ms_;
}

double StepDeadline::SlackMs() const {
  if (!elapsed_ms_ || deadline_ms_ <= 0) return std::numeric_limits<double>::infinity();
  return std::max(0.0, deadline_ms_ - elapsed_ms_() - ExpectedMs());
}

double StepDeadline::ExpectedMs() const {
  const bool estimated = cost_ != nullptr && !cost_->probe_due();
  return estimated ? cost_->expected_ms() : 0;
}

void StepDeadline::Record(double ms) const {
  if (cost_ != nullptr) cost_->Record(ms);
}

}  // namespace memloop
