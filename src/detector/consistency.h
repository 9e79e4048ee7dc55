// The map's invariants, checked from the outside (Detector::CheckConsistency): what memory, the
// dictionary, LTM and the filter must agree on after every iteration. Used by the integration
// tests after every image (all of LTM) and by a resume (LTM near memory).
#pragma once

#include <string>
#include <vector>

#include "detector/bayes_filter.h"
#include "detector/map_editor.h"
#include "detector/memory.h"
#include "storage/long_term_memory.h"

namespace memloop {

// Which LTM locations are read from the file and checked (their links, and that each of their
// words is stored or kept in the dictionary for LTM).
enum class LtmCheck {
  kEvery,  // all of LTM: unfinished after 15 minutes at 1,040,000 locations (docs/scale.md)
  // Those linked to memory (the first retrieval reads) and the kNewestLtmChecked newest (the last
  // written before the checkpoint): what a resume checks, in time that does not grow with LTM.
  kNearMemory,
};
constexpr size_t kNewestLtmChecked = 1000;

// The LTM locations `check` reads, in id order (`newest`: kNearMemory's count of newest ids).
std::vector<LocationId> LtmLocationsToCheck(const Memory& memory, const LongTermMemory& ltm,
                                            LtmCheck check, size_t newest = kNewestLtmChecked);

// Returns one line per violation (at most `max_problems`); empty when consistent. `appearance`:
// retrieval by appearance's index, null when off. `whole_image`: features.whole_image, every
// location has a whole-image descriptor (else none has).
std::vector<std::string> CheckConsistency(const Memory& memory, LongTermMemory& ltm,
                                          const BayesFilter& filter,
                                          const std::vector<PastMatch>& past_matches,
                                          const AppearanceIndex* appearance = nullptr,
                                          bool whole_image = false, size_t max_problems = 20,
                                          LtmCheck ltm_check = LtmCheck::kEvery);

}  // namespace memloop
