// Retrieval (paper III-E): LTM neighbours of the highest hypothesis come back into WM.
#pragma once

#include <vector>

#include "detector/memory.h"
#include "storage/long_term_memory.h"

namespace memloop {

struct RetrievalOutcome {
  std::vector<LocationId> retrieved;
  int words_added = 0;     // unmatched words put back into the dictionary
  int words_replaced = 0;  // old words re-matched to newer ones
};

// Brings back at most `max_retrieved` LTM locations within `range` links of `highest` (nearest
// first, then oldest). Their words still in the dictionary get a reference; words that left it
// are matched against it: a match replaces the old word (in the signature and everywhere in LTM,
// and the old word is removed), a non-match returns to the dictionary under its old id.
RetrievalOutcome Retrieve(LocationId highest, int max_retrieved, int range, Memory& memory,
                          LongTermMemory& ltm);

// The words of `location` that left the dictionary, re-matched as above (exposed for tests).
RetrievalOutcome RematchWords(Location& location, Dictionary& dictionary, LongTermMemory& ltm);

}  // namespace memloop
