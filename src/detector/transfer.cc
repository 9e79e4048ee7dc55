#include "detector/transfer.h"

#include <algorithm>
#include <cmath>

#include "detector/stopwatch.h"

namespace memloop {

bool TimeExceeded(double elapsed_ms, double time_limit_ms, double target) {
  return time_limit_ms > 0 && elapsed_ms > target * time_limit_ms;
}

double WmTimeBudget(double elapsed_ms, double wm_ms, double target_ms, double min_share) {
  return std::max(target_ms - (elapsed_ms - wm_ms), min_share * target_ms);
}

bool WmIsTheCost(double elapsed_ms, double wm_ms, double target_ms, double min_share) {
  return min_share <= 0 || wm_ms > WmTimeBudget(elapsed_ms, wm_ms, target_ms, min_share);
}

int LocationsOverTime(double elapsed_ms, double wm_ms, double target_ms, int wm_size,
                      double max_fraction, double min_share) {
  if (max_fraction <= 0 || elapsed_ms <= target_ms || wm_ms <= 0 || wm_size <= 0) return 0;
  const double budget_ms = WmTimeBudget(elapsed_ms, wm_ms, target_ms, min_share);
  if (budget_ms <= 0) return 0;  // a slow stage WM does not drive: a smaller WM won't help
  const double kept = std::min(1.0, budget_ms / wm_ms);
  const int over = static_cast<int>(std::ceil(wm_size * (1.0 - kept)));
  return std::min(over, static_cast<int>(std::ceil(max_fraction * wm_size)));
}

TransferTrigger MakeTransferTrigger(const MemoryOptions& memory, double elapsed_ms, double wm_ms,
                                    int wm_size, size_t dictionary_size_at_start) {
  TransferTrigger trigger;
  const double target_ms = memory.time_target * memory.time_limit_ms;
  trigger.time_exceeded = TimeExceeded(elapsed_ms, memory.time_limit_ms, memory.time_target) &&
                          WmIsTheCost(elapsed_ms, wm_ms, target_ms, memory.wm_min_time_share);
  if (trigger.time_exceeded) {
    trigger.min_locations =
        LocationsOverTime(elapsed_ms, wm_ms, target_ms, wm_size, memory.transfer_max_fraction,
                          memory.wm_min_time_share);
  }
  trigger.max_wm_locations = memory.max_wm_locations;
  trigger.max_dictionary_words = memory.max_dictionary_words;
  trigger.dictionary_size_at_start = dictionary_size_at_start;
  return trigger;
}

std::vector<LocationId> TransferOrder(const Memory& memory, const std::set<LocationId>& immune,
                                      const std::set<LocationId>& last) {
  std::vector<LocationId> order;
  for (LocationId id : memory.working_memory()) {
    if (!immune.count(id)) order.push_back(id);
  }
  std::stable_sort(order.begin(), order.end(), [&](LocationId a, LocationId b) {
    const bool a_last = last.count(a) > 0;
    const bool b_last = last.count(b) > 0;
    if (a_last != b_last) return b_last;
    return memory.at(a).weight < memory.at(b).weight;  // ids are sorted: ties keep oldest first
  });
  return order;
}

std::vector<LocationId> Transfer(const TransferTrigger& trigger, const std::set<LocationId>& immune,
                                 const std::set<LocationId>& last, const Memory& memory,
                                 MapEditor& editor, const StepDeadline& deadline, bool* cut_short) {
  const Dictionary& dictionary = memory.dictionary();
  const auto over_budget = [&] {
    return (trigger.max_wm_locations > 0 &&
            static_cast<int>(memory.working_memory().size()) > trigger.max_wm_locations) ||
           (trigger.max_dictionary_words > 0 &&
            static_cast<int>(dictionary.size()) > trigger.max_dictionary_words);
  };
  std::vector<LocationId> transferred;
  if (cut_short != nullptr) *cut_short = false;
  if (!trigger.time_exceeded && !over_budget()) return transferred;
  for (LocationId id : TransferOrder(memory, immune, last)) {
    const bool rule_met = !transferred.empty() && !over_budget() &&
                          dictionary.size() <= trigger.dictionary_size_at_start;
    const bool enough = static_cast<int>(transferred.size()) >= trigger.min_locations;
    if (rule_met && (enough || !deadline.Fits())) {
      if (cut_short != nullptr) *cut_short = !enough;
      break;
    }
    const Stopwatch stopwatch;
    editor.TransferToLtm(id);
    transferred.push_back(id);
    deadline.Record(stopwatch.ElapsedMs());
  }
  return transferred;
}

void RecentRetrievals::StartIteration(long long iteration) {
  for (auto entry = retrieved_at_.begin(); entry != retrieved_at_.end();) {
    entry =
        iteration - entry->second >= iterations_ ? retrieved_at_.erase(entry) : std::next(entry);
  }
}

void RecentRetrievals::Retrieved(const std::vector<LocationId>& ids, long long iteration) {
  if (iterations_ <= 0) return;
  for (LocationId id : ids) retrieved_at_[id] = iteration;
}

std::set<LocationId> RecentRetrievals::InWorkingMemory(const Memory& memory) const {
  std::set<LocationId> in_wm;
  for (const auto& [id, iteration] : retrieved_at_) {
    if (memory.InWorkingMemory(id)) in_wm.insert(id);
  }
  return in_wm;
}

}  // namespace memloop
