// Retrieval (paper III-E): LTM neighbours of the highest hypothesis come back into WM.
#pragma once

#include <functional>
#include <vector>

#include "detector/memory.h"
#include "detector/stopwatch.h"
#include "storage/long_term_memory.h"

namespace memloop {

struct RetrievalOutcome {
  std::vector<LocationId> retrieved;
  int words_added = 0;     // unmatched words put back into the dictionary
  int words_replaced = 0;  // old words re-matched to newer ones
  int deferred = 0;        // left in LTM this iteration: no time left for them (RetrievalClock)
};

// Retrieval under T_time (memloop, issue 9). The paper bounds retrieval by count alone ("a
// maximum of two locations ... because this step is time consuming"); re-matching a location's
// words costs about as much as quantizing an image, so two of them can push an iteration over
// T_time. With a deadline, a location is retrieved only when the time one retrieval is expected
// to take still ends before it; the others stay in LTM until an iteration has room (the highest
// hypothesis, and an appearance match, usually hold over several images).
class RetrievalClock {
 public:
  // The time one retrieval is expected to take, at most: the moving average of the last ones
  // measured plus twice their moving mean deviation (as TCP bounds a round trip, RFC 6298), since
  // a retrieval that waits for a core costs twice the usual. 0 until one is measured. Kept
  // across iterations by the caller.
  struct Cost {
    // After this many iterations in a row that deferred a retrieval, one is retrieved whatever
    // the estimate (if the iteration is not past the deadline already), so that one slow
    // retrieval cannot keep all others out for good: its time refreshes the estimate.
    static constexpr int kProbeAfter = 8;

    double mean_ms = 0;
    double deviation_ms = 0;
    bool measured = false;
    int deferred_in_a_row = 0;  // iterations that deferred one since the last measured

    void Record(double ms);
    // An iteration deferred a retrieval: the deviation decays as a retrieval of the mean time
    // would make it, and the count towards a probe grows.
    void Deferred();
    double expected_ms() const { return mean_ms + 2 * deviation_ms; }
    bool ProbeDue() const { return deferred_in_a_row >= kProbeAfter; }
  };

  RetrievalClock() = default;  // no deadline: the count alone bounds retrieval
  // `elapsed_ms`: the iteration's time so far; `deadline_ms` on that clock (0 or less: none).
  RetrievalClock(std::function<double()> elapsed_ms, double deadline_ms, Cost* cost)
      : elapsed_ms_(std::move(elapsed_ms)), deadline_ms_(deadline_ms), cost_(cost) {}

  bool Fits() const;  // elapsed + expected <= deadline
  void Record(double ms) const;

 private:
  std::function<double()> elapsed_ms_;
  double deadline_ms_ = 0;
  Cost* cost_ = nullptr;
};

// Brings back at most `max_retrieved` LTM locations within `range` links of `highest` (nearest
// first, then oldest), each only while `clock` fits it. Their words still in the dictionary get
// a reference; words that left it are matched against it: a match replaces the old word (in the
// signature and everywhere in LTM, and the old word is removed), a non-match returns to the
// dictionary under its old id.
RetrievalOutcome Retrieve(LocationId highest, int max_retrieved, int range, Memory& memory,
                          LongTermMemory& ltm, const RetrievalClock& clock = RetrievalClock());

// The words of `location` that left the dictionary, re-matched as above (exposed for tests).
RetrievalOutcome RematchWords(Location& location, Dictionary& dictionary, LongTermMemory& ltm);

}  // namespace memloop
