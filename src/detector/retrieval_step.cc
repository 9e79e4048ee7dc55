#include "detector/retrieval_step.h"

#include <utility>

namespace memloop {

bool WorthRetrieving(const MemoryOptions& memory, double value, double elapsed_ms,
                     double expected_ms) {
  if (value < memory.retrieval_min_value) return false;
  if (memory.time_limit_ms <= 0 || value >= memory.retrieval_strong_value) return true;
  return elapsed_ms + expected_ms <= 0.5 * memory.time_limit_ms;
}

RetrievalStep::RetrievalStep(const MemoryOptions& memory, int neighbour_range, Memory& memory_state,
                             LongTermMemory& ltm)
    : options_(memory), range_(neighbour_range), memory_(memory_state), ltm_(ltm) {
  // Under T_time, retrieval's reads of the map file are made ahead by a thread of their own
  // (ltm_read_ahead.h); with T_time off every read is waited for, as a repeatable run needs.
  if (memory.time_limit_ms <= 0 || !memory.retrieval_within_time || !memory.retrieval_read_ahead) {
    return;
  }
  read_ahead_ = std::make_unique<LtmReadAhead>(ltm);
  if (memory.retrieval_over_iterations) staged_search_ = std::make_unique<StagedWordSearch>();
}

StagedWordSearch::Running RetrievalStep::SearchBesideExtraction() {
  if (!staged_search_) return StagedWordSearch::Running(nullptr);
  return staged_search_->Start(staging_, memory_.dictionary(), ltm_, options_.retrieval_kd_checks);
}

RetrievalTime RetrievalStep::TimeOf(const std::function<StepDeadline(StepCost*)>& deadline_of) {
  RetrievalTime time;
  if (!options_.retrieval_within_time) return time;
  time.location = deadline_of(&location_cost_);
  time.search_chunk = deadline_of(&chunk_cost_);
  time.read_ahead = read_ahead_.get();
  if (staged_search_) {
    staging_.StartIteration(memory_.dictionary().JoinMark());
    time.staging = &staging_;
    time.staged_checks = options_.retrieval_kd_checks;
    time.ahead_unsearched = options_.retrieval_ahead_unsearched != 0;
    time.recent_twins = options_.retrieval_recent_twins;
    time.stage_deferred = options_.retrieval_stage_deferred != 0;
  }
  return time;
}

std::vector<LocationId> RetrievalStep::Retrieve(
    LocationId by_hypothesis, LocationId by_appearance,
    const std::function<StepDeadline(StepCost*)>& deadline_of, Result& result) {
  RetrievalTime time = TimeOf(deadline_of);
  direction_.Observe(by_appearance != kNoLocation ? by_appearance : by_hypothesis);
  time.newer_first = direction_.newer_first();
  std::vector<LocationId> targets = {by_hypothesis, by_appearance};
  // Staged (T_time on), the place recognized by appearance goes first: it stands out of all of
  // LTM, where a hypothesis just over memory.retrieval_min_value is mostly noise.
  if (time.staging != nullptr) std::swap(targets[0], targets[1]);
  std::vector<LocationId> retrieved;
  for (LocationId target : targets) {
    if (target == kNoLocation) continue;
    const RetrievalOutcome outcome =
        memloop::Retrieve(target, options_.max_retrieved, range_, memory_, ltm_, time);
    retrieved.insert(retrieved.end(), outcome.retrieved.begin(), outcome.retrieved.end());
    result.retrievals_deferred += outcome.deferred;
    result.retrievals_unread += outcome.unread;
    ++time.priority;
  }
  const RetrievalOutcome carried = ContinueStaged(options_.max_retrieved, memory_, ltm_, time);
  retrieved.insert(retrieved.end(), carried.retrieved.begin(), carried.retrieved.end());
  if (result.retrievals_deferred > 0) location_cost_.Deferred();
  if (result.retrievals_deferred > 0 || result.retrievals_unread > 0) {
    result.AddTimeDecision("retrieval_deferred");
  }
  if (!carried.retrieved.empty()) result.AddTimeDecision("retrieval_staged");
  return retrieved;
}

}  // namespace memloop
