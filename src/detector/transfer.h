// Transfer (paper III-F): WM locations of lowest weight, then oldest, go to LTM until the
// dictionary is no larger than at the start of the iteration ("the number of words transferred
// ... is [not] less than the number of words added from the new or retrieved locations").
#pragma once

#include <map>
#include <set>
#include <vector>

#include "detector/map_editor.h"
#include "detector/memory.h"
#include "detector/step_deadline.h"
#include "memloop/options.h"

namespace memloop {

struct TransferTrigger {
  bool time_exceeded = false;    // TimeExceeded(): the iteration near T_time
  int max_wm_locations = 0;      // deterministic budget, 0 = none
  int max_dictionary_words = 0;  // deterministic budget, 0 = none
  size_t dictionary_size_at_start = 0;
  int min_locations = 0;  // transferred at least (LocationsOverTime), once triggered
};

// The time trigger: the iteration so far (`elapsed_ms`, up to the transfer step, the previous
// image's checkpoint included) is over `target` x T_time (memory.time_target; the paper: 1,
// elapsed > T_time). False when T_time is off (0).
bool TimeExceeded(double elapsed_ms, double time_limit_ms, double target);

// The time WM's stages (`wm_ms`: likelihood, filter, selection) may take in an iteration of
// `elapsed_ms` aiming at `target_ms`: what the rest (elapsed_ms - wm_ms) leaves of the target,
// and at least `min_share` of it (memory.wm_min_time_share; 0 = the paper: what the rest leaves,
// possibly nothing).
double WmTimeBudget(double elapsed_ms, double wm_ms, double target_ms, double min_share);

// Whether an iteration over the time target transfers for time: with min_share 0 (the paper)
// always; else only when WM's stages take more than their budget (a smaller WM cannot make up
// for slow features or retrieval, issue 37).
bool WmIsTheCost(double elapsed_ms, double wm_ms, double target_ms, double min_share);

// memloop's time controller (memory.transfer_max_fraction; not in the paper): how many WM
// locations to transfer so that the next iteration fits `target_ms`. WM's stages are scaled down
// to their budget (WmTimeBudget); at most ceil(max_fraction x wm_size), so that one iteration
// slowed by the machine costs little of WM. 0 when under the target, when the budget is 0 (the
// rest alone reaches the target and min_share is 0: a smaller WM would not help), or when
// max_fraction is 0 (the paper's rule alone: words transferred = words added, about one
// location per iteration).
int LocationsOverTime(double elapsed_ms, double wm_ms, double target_ms, int wm_size,
                      double max_fraction, double min_share = 0);

// This iteration's trigger (III-F) from memory.*: T_time through its target, when WM is the cost
// (WmIsTheCost: over the target through stages WM does not drive, WM is kept, issue 37), with
// LocationsOverTime's count, and the budgets. `elapsed_ms` counts the iteration up to the
// transfer step, the previous image's checkpoint included, so that the whole iteration stays
// under T_time (issue 9); `wm_ms` is WM's stages' share of it.
TransferTrigger MakeTransferTrigger(const MemoryOptions& memory, double elapsed_ms, double wm_ms,
                                    int wm_size, size_t dictionary_size_at_start);

// WM locations in the order they would be transferred: lowest weight first, then oldest
// (smallest id); `immune` ones (retrieved this iteration) never; `last` ones (the highest
// hypothesis' neighbourhood, the locations just retrieved) only after all others, in the same
// order among themselves.
std::vector<LocationId> TransferOrder(const Memory& memory, const std::set<LocationId>& immune,
                                      const std::set<LocationId>& last = {});

// The locations retrieved in the last `iterations` iterations, the retrieving one included
// (0: none). Two uses: III-F's immunity to Transfer ("the retrieved locations of the current
// iteration", 1; the paper's 2011 code: 10, Mem/DelayRequired; memory.retrieved_immune_iterations),
// and memloop's "leave WM last" (memory.retrieved_kept_last_iterations). Iterations are counted
// by the caller (images processed). The kept-last ones are in the checkpoint (a resumed run
// transfers as the uninterrupted one); the immune ones, one iteration by default, are not.
class RecentRetrievals {
 public:
  explicit RecentRetrievals(int iterations) : iterations_(iterations) {}
  // Forgets the locations retrieved `iterations` or more iterations before `iteration`.
  void StartIteration(long long iteration);
  void Retrieved(const std::vector<LocationId>& ids, long long iteration);
  // Those still in WM.
  std::set<LocationId> InWorkingMemory(const Memory& memory) const;
  // Each location with the iteration that retrieved it (the checkpoint's), and back.
  const std::map<LocationId, long long>& retrieved_at() const { return retrieved_at_; }
  void Reload(std::map<LocationId, long long> retrieved_at) {
    retrieved_at_ = std::move(retrieved_at);
  }

 private:
  int iterations_;
  std::map<LocationId, long long> retrieved_at_;
};

// Transfers while the trigger holds (at least one location, and trigger.min_locations, once
// triggered). Returns the ids. The paper's rule and the budgets are met whatever the time; the
// locations beyond them that min_locations asks for go only while they fit `deadline` (memloop:
// 20 of them at once took 15 ms and a third of the iterations over T_time). `cut_short`, when
// given, is set when the deadline stopped it before min_locations.
std::vector<LocationId> Transfer(const TransferTrigger& trigger, const std::set<LocationId>& immune,
                                 const std::set<LocationId>& last, const Memory& memory,
                                 MapEditor& editor, const StepDeadline& deadline = StepDeadline(),
                                 bool* cut_short = nullptr);

}  // namespace memloop
