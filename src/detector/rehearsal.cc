#include "detector/rehearsal.h"

namespace memloop {

RehearsalOutcome Rehearse(LocationId new_id, double threshold, Memory& memory, MapEditor& editor,
                          bool most_similar) {
  RehearsalOutcome outcome;
  const auto& stm = memory.stm();
  for (auto candidate = stm.rbegin(); candidate != stm.rend(); ++candidate) {
    if (*candidate == new_id) continue;
    const double similarity =
        Similarity(memory.at(new_id).signature, memory.at(*candidate).signature);  // eq. 1
    if (similarity <= threshold || similarity <= outcome.similarity) continue;
    outcome.merged_id = *candidate;
    outcome.similarity = similarity;
    if (!most_similar) break;  // "Rehearsal stops"
  }
  if (outcome.merged_id == kNoLocation) return outcome;

  const LocationId merged = outcome.merged_id;
  memory.at(new_id).weight += memory.at(merged).weight + 1;
  outcome.replaced_words = memory.at(new_id).signature.words;
  editor.ReplaceSignature(new_id, memory.at(merged).signature);
  editor.Merge(new_id, merged);
  return outcome;
}

}  // namespace memloop
