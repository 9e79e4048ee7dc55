#include "detector/retrieval.h"

#include <algorithm>
#include <limits>
#include <set>

#include "detector/stopwatch.h"
#include "memloop/errors.h"
#include "vocabulary/word_index.h"

namespace memloop {
namespace {

// The rows `picked` of `descriptors`, in that order.
cv::Mat RowsOf(const cv::Mat& descriptors, const std::vector<size_t>& picked) {
  cv::Mat rows;
  for (size_t row : picked) rows.push_back(descriptors.row(static_cast<int>(row)));
  return rows;
}

// The answer `searched` holds for `word`, or null.
const WordAnswer* AnswerIn(const WordMatches* searched, WordId word) {
  if (searched == nullptr) return nullptr;
  const auto answer = searched->find(word);
  return answer == searched->end() ? nullptr : &answer->second;
}

}  // namespace

RetrievalOutcome RematchWords(Location& location, Dictionary& dictionary, LongTermMemory& ltm,
                              const PrefetchedRows* rows, const WordMatches* searched) {
  RetrievalOutcome outcome;
  std::vector<WordId> missing;
  for (const auto& [word, count] : location.signature.Histogram()) {
    if (!dictionary.Contains(word)) missing.push_back(word);
  }
  if (missing.empty()) return outcome;
  const cv::Mat descriptors =
      LoadWordDescriptors(missing, dictionary, ltm, rows, location.id, /*required=*/true);
  std::vector<WordId> matches(missing.size(), kNoWord);
  std::vector<size_t> to_search;  // rows of `missing` to search now
  std::vector<size_t> recheck;    // rows answered "none": compared with the words joined since
  std::vector<std::pair<float, float>> recheck_found;
  long long recheck_mark = dictionary.JoinMark();
  for (size_t row = 0; row < missing.size(); ++row) {
    const WordAnswer* found = AnswerIn(searched, missing[row]);
    if (found != nullptr && found->match != kNoWord && dictionary.Contains(found->match)) {
      matches[row] = found->match;
    } else if (found != nullptr && found->match == kNoWord) {
      recheck.push_back(row);
      recheck_found.emplace_back(found->nearest, found->second);
      recheck_mark = std::min(recheck_mark, found->mark);
    } else {  // not searched yet, or the word it matched has left
      to_search.push_back(row);
    }
  }
  if (!recheck.empty()) {
    const std::optional<std::vector<WordId>> since =
        dictionary.MatchSince(RowsOf(descriptors, recheck), recheck_found, recheck_mark);
    for (size_t i = 0; i < recheck.size(); ++i) {
      if (since) {
        matches[recheck[i]] = (*since)[i];
      } else {  // forgotten what joined since: searched again
        to_search.push_back(recheck[i]);
      }
    }
  }
  if (!to_search.empty()) {
    const std::vector<WordId> found = dictionary.Match(RowsOf(descriptors, to_search));
    for (size_t i = 0; i < found.size(); ++i) matches[to_search[i]] = found[i];
  }
  std::vector<WordId> unmatched_ids;
  std::vector<size_t> unmatched_rows;
  for (size_t row = 0; row < missing.size(); ++row) {
    if (matches[row] == kNoWord) {
      unmatched_ids.push_back(missing[row]);
      unmatched_rows.push_back(row);
      continue;
    }
    for (WordId& word : location.signature.words) {
      if (word == missing[row]) word = matches[row];
    }
    ltm.ReplaceWord(missing[row], matches[row]);
    ++outcome.words_replaced;
  }
  dictionary.Add(unmatched_ids, RowsOf(descriptors, unmatched_rows));
  // Other LTM locations may hold these words too: keep them in LTM when they leave again.
  for (WordId word : unmatched_ids) dictionary.MarkReferencedByLtm(word);
  outcome.words_added = static_cast<int>(unmatched_ids.size());
  return outcome;
}

namespace {

// Iterations of retrievals whose rows are read ahead: this one's and the next's.
constexpr size_t kReadAheadIterations = 2;

// The rows of `id` read ahead, current, waited for as long as `deadline` allows; nullopt when not
// read in time.
std::optional<PrefetchedRows> ReadAhead(LocationId id, LtmReadAhead& read_ahead,
                                        const LongTermMemory& ltm, const StepDeadline& deadline) {
  std::optional<PrefetchedRows> rows = read_ahead.WaitRead(id, deadline.SlackMs());
  // Read long ago (kept while other locations were retrieved): read again on its thread.
  if (rows && !ltm.Current(*rows)) rows = read_ahead.WaitRead(id, deadline.SlackMs());
  return rows;
}

// A location asked for when no retrieval fits (RetrievalTime::stage_deferred): staged, without
// waiting for its rows, and wanted, so that it is readied beside the next extraction and carried
// on. Without this, the neighbour ahead of a place recognized by appearance, deferred in the image
// that brought the place back, was asked for again only if the next image recognized it too, and
// the revisit was lost when it did not (a z under AppearanceMinZ).
void StageDeferred(LocationId id, const RetrievalTime& time) {
  if (!time.stage_deferred || time.read_ahead == nullptr || time.staging == nullptr) return;
  RetrievalStaging::Staged* staged = time.staging->Find(id);
  if (staged == nullptr) {
    std::optional<PrefetchedRows> rows = time.read_ahead->WaitRead(id, 0);
    if (!rows) return;
    staged = &time.staging->Start(id, std::move(*rows));
  }
  time.staging->Want(*staged, time.priority);
}

// One location of LTM: retrieved into `memory` (or deferred, or staged for later), `outcome`
// counting it. `wanted`: this iteration asks for it (staged, it is then searched first beside the
// next extraction); otherwise it is only carried on (ContinueStaged).
void RetrieveOne(LocationId id, Memory& memory, LongTermMemory& ltm, const RetrievalTime& time,
                 bool wanted, bool ahead, RetrievalOutcome& outcome) {
  if (!time.location.Fits()) {
    ++outcome.deferred;
    if (wanted) StageDeferred(id, time);
    return;
  }
  LtmReadAhead* read_ahead = time.read_ahead;
  RetrievalStaging* staging = read_ahead != nullptr ? time.staging : nullptr;
  RetrievalStaging::Staged* staged = staging != nullptr ? staging->Find(id) : nullptr;
  std::optional<PrefetchedRows> rows;
  if (read_ahead != nullptr && (staged == nullptr || !ltm.Current(staged->rows))) {
    rows = ReadAhead(id, *read_ahead, ltm, time.location);
    if (!rows) {
      ++outcome.deferred;
      ++outcome.unread;
      return;
    }
    if (staged != nullptr) {
      staged->rows = std::move(*rows);  // its answers hold: a word's descriptor never changes
    } else if (staging != nullptr) {
      staged = &staging->Start(id, std::move(*rows));
    }
  }
  if (staged != nullptr) {
    if (wanted) staging->Want(*staged, time.priority);
    bool searched = SearchStagedWords(*staged, memory.dictionary(), ltm, time.search_chunk,
                                      time.location.ExpectedMs(), time.staged_checks);
    const bool recent_twins = wanted && time.recent_twins >= 0;
    if (!searched && (ahead || recent_twins)) {
      // No time to search them. A place the robot has not reached yet has no twins: its words
      // left are compared at its retrieval (RematchWords) with the words that joined since.
      // Otherwise its twins are mostly the words of the images that recognize it now
      // (memory.retrieval_recent_twins): compared with the words of the last few images, whose
      // number bounds the comparison's time.
      constexpr float kNone = std::numeric_limits<float>::max();
      const long long mark =
          ahead ? memory.dictionary().JoinMark() : staging->JoinMarkBefore(time.recent_twins);
      for (WordId word : UnsearchedWords(*staged, memory.dictionary(), ltm).first) {
        staged->matches[word] = WordAnswer{kNoWord, kNone, kNone, mark};
      }
      searched = true;
    }
    if (!searched || !time.location.Fits()) {
      ++outcome.deferred;
      return;
    }
  }
  const PrefetchedRows* from = staged != nullptr ? &staged->rows : rows ? &*rows : nullptr;
  const Stopwatch stopwatch;
  std::optional<Location> location = from ? ltm.Retrieve(id, *from) : ltm.Retrieve(id);
  const RetrievalOutcome words = RematchWords(*location, memory.dictionary(), ltm, from,
                                              staged != nullptr ? &staged->matches : nullptr);
  outcome.words_added += words.words_added;
  outcome.words_replaced += words.words_replaced;
  // A word now in the dictionary may also be held by other LTM locations.
  for (WordId word : location->signature.words) memory.dictionary().MarkReferencedByLtm(word);
  memory.Restore(std::move(*location));
  outcome.retrieved.push_back(id);
  time.location.Record(stopwatch.ElapsedMs());
  if (staged != nullptr) staging->Erase(id);
}

}  // namespace

RetrievalOutcome Retrieve(LocationId highest, int max_retrieved, int range, Memory& memory,
                          LongTermMemory& ltm, const RetrievalTime& time) {
  RetrievalOutcome outcome;
  if (highest == kNoLocation || max_retrieved <= 0) return outcome;
  const Neighbourhood neighbourhood = FindNeighbourhood(highest, range, [&](LocationId id) {
    return memory.Contains(id) ? memory.LinksOf(id) : ltm.LinksOf(id);
  });
  std::vector<std::pair<int, LocationId>> by_distance;  // nearest first, then oldest
  for (const auto& [id, distance] : neighbourhood) {
    if (ltm.Contains(id)) by_distance.emplace_back(distance, id);
  }
  // Staged, a location comes back one or two images after it is asked for: the neighbour the
  // robot goes to next must be asked for first, or it joins WM after the robot got there and the
  // transition model has nothing to carry the hypothesis onto (issue 37).
  if (time.staging != nullptr && time.ahead_unsearched && time.newer_first) {
    std::stable_sort(by_distance.begin(), by_distance.end(), [](const auto& a, const auto& b) {
      return a.first != b.first ? a.first < b.first : a.second > b.second;
    });
  }
  std::vector<LocationId> in_ltm;
  for (const auto& [distance, id] : by_distance) in_ltm.push_back(id);
  // Read ahead: those this iteration retrieves and those the next would, not the whole
  // neighbourhood. A chance hypothesis' neighbourhood in LTM was read for nothing: in the late
  // state of a 49,050-image run (bench/late_state.sh), 3,016 locations read for 917 retrieved.
  if (time.read_ahead != nullptr) {
    const size_t ahead =
        std::min(in_ltm.size(), kReadAheadIterations * static_cast<size_t>(max_retrieved));
    time.read_ahead->Request(std::vector<LocationId>(in_ltm.begin(), in_ltm.begin() + ahead));
  }
  for (LocationId id : in_ltm) {
    if (static_cast<int>(outcome.retrieved.size()) + outcome.deferred >= max_retrieved) break;
    const bool ahead = time.ahead_unsearched && id != highest && (id > highest) == time.newer_first;
    RetrieveOne(id, memory, ltm, time, /*wanted=*/true, ahead, outcome);
  }
  return outcome;
}

RetrievalOutcome ContinueStaged(int max_retrieved, Memory& memory, LongTermMemory& ltm,
                                const RetrievalTime& time) {
  RetrievalOutcome outcome;
  if (time.staging == nullptr || time.read_ahead == nullptr) return outcome;
  const long long now = time.staging->iteration();
  for (const auto& [id, staged] : time.staging->ByRecency()) {
    if (static_cast<int>(outcome.retrieved.size()) >= max_retrieved) break;
    if (staged->touched == now) continue;  // wanted this iteration: done above
    if (now - staged->touched > RetrievalStaging::kCarryOnFor) break;  // older ones follow
    if (!ltm.Contains(id)) {  // retrieved otherwise meanwhile
      time.staging->Erase(id);
      continue;
    }
    RetrieveOne(id, memory, ltm, time, /*wanted=*/false, /*ahead=*/false, outcome);
  }
  outcome.deferred = 0;  // what was not carried on stays staged, as it was
  outcome.unread = 0;
  return outcome;
}

}  // namespace memloop
