#include "detector/retrieval.h"

#include <set>

#include "detector/stopwatch.h"
#include "memloop/errors.h"

namespace memloop {

RetrievalOutcome RematchWords(Location& location, Dictionary& dictionary, LongTermMemory& ltm,
                              const PrefetchedRows* rows) {
  RetrievalOutcome outcome;
  std::vector<WordId> missing;
  for (const auto& [word, count] : location.signature.Histogram()) {
    if (!dictionary.Contains(word)) missing.push_back(word);
  }
  if (missing.empty()) return outcome;
  cv::Mat descriptors(static_cast<int>(missing.size()), dictionary.descriptor_dim(),
                      dictionary.descriptor_cv_type());
  const size_t row_bytes = descriptors.cols * descriptors.elemSize();
  for (size_t row = 0; row < missing.size(); ++row) {
    const auto descriptor = ltm.LoadWord(missing[row], rows);
    if (!descriptor || descriptor->size() != row_bytes) {
      throw DatabaseError(ltm.path(), "word " + std::to_string(missing[row]) + " of location " +
                                          std::to_string(location.id) + " is missing or damaged");
    }
    std::copy(descriptor->begin(), descriptor->end(), descriptors.ptr<unsigned char>(row));
  }
  const std::vector<WordId> matches = dictionary.Match(descriptors);
  std::vector<WordId> unmatched_ids;
  cv::Mat unmatched_descriptors;
  for (size_t row = 0; row < missing.size(); ++row) {
    if (matches[row] == kNoWord) {
      unmatched_ids.push_back(missing[row]);
      unmatched_descriptors.push_back(descriptors.row(static_cast<int>(row)));
      continue;
    }
    for (WordId& word : location.signature.words) {
      if (word == missing[row]) word = matches[row];
    }
    ltm.ReplaceWord(missing[row], matches[row]);
    ++outcome.words_replaced;
  }
  dictionary.Add(unmatched_ids, unmatched_descriptors);
  // Other LTM locations may hold these words too: keep them in LTM when they leave again.
  for (WordId word : unmatched_ids) dictionary.MarkReferencedByLtm(word);
  outcome.words_added = static_cast<int>(unmatched_ids.size());
  return outcome;
}

RetrievalOutcome Retrieve(LocationId highest, int max_retrieved, int range, Memory& memory,
                          LongTermMemory& ltm, const StepDeadline& deadline,
                          LtmReadAhead* read_ahead) {
  RetrievalOutcome outcome;
  if (highest == kNoLocation || max_retrieved <= 0) return outcome;
  const Neighbourhood neighbourhood = FindNeighbourhood(highest, range, [&](LocationId id) {
    return memory.Contains(id) ? memory.LinksOf(id) : ltm.LinksOf(id);
  });
  std::vector<LocationId> in_ltm;  // nearest first, then oldest
  for (const auto& [id, distance] : neighbourhood) {
    if (ltm.Contains(id)) in_ltm.push_back(id);
  }
  if (read_ahead != nullptr) read_ahead->Request(in_ltm);
  for (LocationId id : in_ltm) {
    if (static_cast<int>(outcome.retrieved.size()) + outcome.deferred >= max_retrieved) break;
    if (!deadline.Fits()) {
      ++outcome.deferred;
      continue;
    }
    std::optional<PrefetchedRows> rows;
    if (read_ahead != nullptr) {
      rows = read_ahead->WaitRead(id, deadline.SlackMs());
      // Read long ago (kept while other locations were retrieved): read again on its thread.
      if (rows && !ltm.Current(*rows)) rows = read_ahead->WaitRead(id, deadline.SlackMs());
      if (!rows) {
        ++outcome.deferred;
        ++outcome.unread;
        continue;
      }
    }
    const Stopwatch stopwatch;
    std::optional<Location> location = rows ? ltm.Retrieve(id, *rows) : ltm.Retrieve(id);
    const RetrievalOutcome words =
        RematchWords(*location, memory.dictionary(), ltm, rows ? &*rows : nullptr);
    outcome.words_added += words.words_added;
    outcome.words_replaced += words.words_replaced;
    // A word now in the dictionary may also be held by other LTM locations.
    for (WordId word : location->signature.words) memory.dictionary().MarkReferencedByLtm(word);
    memory.Restore(std::move(*location));
    outcome.retrieved.push_back(id);
    deadline.Record(stopwatch.ElapsedMs());
  }
  return outcome;
}

}  // namespace memloop
