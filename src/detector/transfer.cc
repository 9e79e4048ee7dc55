#include "detector/transfer.h"

#include <algorithm>

namespace memloop {

bool TimeExceeded(double elapsed_ms, double remaining_ms, double time_limit_ms, double target) {
  return time_limit_ms > 0 && elapsed_ms + remaining_ms > target * time_limit_ms;
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
                                 MapEditor& editor) {
  const Dictionary& dictionary = memory.dictionary();
  const auto over_budget = [&] {
    return (trigger.max_wm_locations > 0 &&
            static_cast<int>(memory.working_memory().size()) > trigger.max_wm_locations) ||
           (trigger.max_dictionary_words > 0 &&
            static_cast<int>(dictionary.size()) > trigger.max_dictionary_words);
  };
  std::vector<LocationId> transferred;
  if (!trigger.time_exceeded && !over_budget()) return transferred;
  for (LocationId id : TransferOrder(memory, immune, last)) {
    const bool enough = !over_budget() && dictionary.size() <= trigger.dictionary_size_at_start;
    if (enough && !transferred.empty()) break;
    editor.TransferToLtm(id);
    transferred.push_back(id);
  }
  return transferred;
}

}  // namespace memloop
