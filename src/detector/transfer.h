// Transfer (paper III-F): WM locations of lowest weight, then oldest, go to LTM until the
// dictionary is no larger than at the start of the iteration ("the number of words transferred
// ... is [not] less than the number of words added from the new or retrieved locations").
#pragma once

#include <set>
#include <vector>

#include "detector/map_editor.h"
#include "detector/memory.h"

namespace memloop {

struct TransferTrigger {
  bool time_exceeded = false;    // TimeExceeded(): the iteration near T_time
  int max_wm_locations = 0;      // deterministic budget, 0 = none
  int max_dictionary_words = 0;  // deterministic budget, 0 = none
  size_t dictionary_size_at_start = 0;
};

// The time trigger: the iteration so far (`elapsed_ms`, up to the transfer step) plus what will
// follow it (`remaining_ms`: the checkpoint, as last measured) reaches `target` x T_time
// (memory.time_target; the paper: 1, elapsed > T_time). False when T_time is off (0).
bool TimeExceeded(double elapsed_ms, double remaining_ms, double time_limit_ms, double target);

// WM locations in the order they would be transferred: lowest weight first, then oldest
// (smallest id); `immune` ones (retrieved this iteration) never; `last` ones (the highest
// hypothesis' neighbourhood) only after all others, in the same order among themselves.
std::vector<LocationId> TransferOrder(const Memory& memory, const std::set<LocationId>& immune,
                                      const std::set<LocationId>& last = {});

// Transfers while the trigger holds (at least one location once triggered). Returns the ids.
std::vector<LocationId> Transfer(const TransferTrigger& trigger, const std::set<LocationId>& immune,
                                 const std::set<LocationId>& last, const Memory& memory,
                                 MapEditor& editor);

}  // namespace memloop
