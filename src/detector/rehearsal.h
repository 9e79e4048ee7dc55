// Rehearsal (paper III-B): the new location is compared with the STM locations, most recent
// first; the first whose similarity (eq. 1) exceeds T_rehearsal is merged into it. With
// `most_similar` (memory.rehearsal_most_similar, the paper's 2011 code) every STM location is
// compared and the most similar one is merged, if above T_rehearsal (ties: the newest).
#pragma once

#include <vector>

#include "detector/map_editor.h"
#include "detector/memory.h"

namespace memloop {

struct RehearsalOutcome {
  LocationId merged_id = kNoLocation;  // L_c, kNoLocation when none was similar enough
  double similarity = 0;
  // On a merge, the words z_t held before z_c replaced them: the image's own
  // (filter.support_from_image). Empty when nothing was merged.
  std::vector<WordId> replaced_words;
};

// Compares L_t (`new_id`, the newest STM location) with the other STM locations. On a merge:
// z_t is cleared and z_c copied into it, weight_t += weight_c + 1, L_c's links go to L_t and
// L_c is deleted from STM (through `editor`, which keeps LTM, the dictionary and the filter in
// agreement).
RehearsalOutcome Rehearse(LocationId new_id, double threshold, Memory& memory, MapEditor& editor,
                          bool most_similar = false);

}  // namespace memloop
