// III-E in the iteration: which LTM locations come back into WM this image, for the highest
// hypothesis and for the place recognized by appearance, under T_time read ahead and readied over
// several iterations (retrieval_staging.h).
#pragma once

#include <functional>
#include <memory>
#include <vector>

#include "detector/memory.h"
#include "detector/retrieval.h"
#include "detector/retrieval_staging.h"
#include "detector/step_deadline.h"
#include "detector/travel_direction.h"
#include "memloop/options.h"
#include "memloop/result.h"
#include "storage/long_term_memory.h"
#include "storage/ltm_read_ahead.h"

namespace memloop {

// Whether the highest hypothesis, of value `value`, is worth retrieving its LTM neighbours for:
// at least memory.retrieval_min_value; under T_time, a value under memory.retrieval_strong_value
// only when the retrieval (`expected_ms`) is expected to end within the first half of T_time,
// `elapsed_ms` being the iteration's time so far. A staged retrieval's cost falls mostly on the
// next iterations, so what is asked for must leave them room: under a loose T_time (67 ms, or 700
// by default) every iteration does, as with T_time off; under a tight one, where the signature
// step alone takes over half of T_time, only the hypotheses worth it are retrieved for.
bool WorthRetrieving(const MemoryOptions& memory, double value, double elapsed_ms,
                     double expected_ms);

class RetrievalStep {
 public:
  // The read-ahead thread and the search beside the extraction exist only when T_time is on with
  // memory.retrieval_within_time and memory.retrieval_read_ahead (and, for the search,
  // memory.retrieval_over_iterations).
  RetrievalStep(const MemoryOptions& memory, int neighbour_range, Memory& memory_state,
                LongTermMemory& ltm);

  // To hold while the image's features are extracted (the dictionary unchanged meanwhile): the
  // staged locations' words are searched on another thread until it goes.
  StagedWordSearch::Running SearchBesideExtraction();

  // The locations retrieved into WM: the neighbours of `by_hypothesis` and of `by_appearance`
  // (kNoLocation: none), then staged ones carried on. `deadline_of` gives the iteration's deadline
  // for a step of the given expected cost (StepDeadline() with T_time off). Deferred and unread
  // locations are counted in `result`.
  std::vector<LocationId> Retrieve(LocationId by_hypothesis, LocationId by_appearance,
                                   const std::function<StepDeadline(StepCost*)>& deadline_of,
                                   Result& result);
  // A location's retrieval is expected to take this long (0 until one is timed, or T_time off).
  double ExpectedLocationMs() const { return location_cost_.expected_ms(); }

 private:
  RetrievalTime TimeOf(const std::function<StepDeadline(StepCost*)>& deadline_of);

  MemoryOptions options_;
  int range_;
  Memory& memory_;
  LongTermMemory& ltm_;
  TravelDirection direction_;  // staged: which neighbours are asked for first
  StepCost location_cost_;     // one retrieval's expected time (T_time on), or its end's (staged)
  StepCost chunk_cost_;        // one chunk of a staged location's search
  RetrievalStaging staging_;   // memory.retrieval_over_iterations
  std::unique_ptr<LtmReadAhead> read_ahead_;  // null unless T_time is on
  // Last: it stops before what it reads goes.
  std::unique_ptr<StagedWordSearch> staged_search_;
};

}  // namespace memloop
