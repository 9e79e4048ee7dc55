// The map's invariants, checked from the outside (Detector::CheckConsistency): what memory, the
// dictionary, LTM and the filter must agree on after every iteration. Used by the integration
// tests after every image; too slow for every image of a long run (it reads all of LTM).
#pragma once

#include <string>
#include <vector>

#include "detector/bayes_filter.h"
#include "detector/map_editor.h"
#include "detector/memory.h"
#include "storage/long_term_memory.h"

namespace memloop {

// Returns one line per violation (at most `max_problems`); empty when consistent. `appearance`:
// retrieval by appearance's index, null when off. `whole_image`: features.whole_image, every
// location has a whole-image descriptor (else none has).
std::vector<std::string> CheckConsistency(const Memory& memory, LongTermMemory& ltm,
                                          const BayesFilter& filter,
                                          const std::vector<PastMatch>& past_matches,
                                          const AppearanceIndex* appearance = nullptr,
                                          bool whole_image = false, size_t max_problems = 20);

}  // namespace memloop
