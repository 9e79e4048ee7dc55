// Retrieval (paper III-E): LTM neighbours of the highest hypothesis come back into WM.
#pragma once

#include <vector>

#include "detector/memory.h"
#include "detector/retrieval_staging.h"
#include "detector/step_deadline.h"
#include "storage/long_term_memory.h"
#include "storage/ltm_read_ahead.h"

namespace memloop {

struct RetrievalOutcome {
  std::vector<LocationId> retrieved;
  int words_added = 0;     // unmatched words put back into the dictionary
  int words_replaced = 0;  // old words re-matched to newer ones
  int deferred = 0;        // left in LTM this iteration: no time left for them (StepDeadline)
  int unread = 0;          // of those, deferred because their rows were not read in time
};

// Under T_time: what bounds a retrieval (default: nothing, T_time off).
struct RetrievalTime {
  // One location's retrieval: whole, or (staged) its end, once its words are searched.
  StepDeadline location;
  // One chunk (WordIndex::kSearchChunk words) of a staged location's search, on one thread.
  StepDeadline search_chunk;
  // memory.retrieval_read_ahead: rows read on another thread (see Retrieve); with `staging`,
  // locations are readied over several iterations.
  LtmReadAhead* read_ahead = nullptr;
  RetrievalStaging* staging = nullptr;
  // Staged locations of a lower priority are searched first beside the next extraction.
  int priority = 0;
  // Leaves a staged location's search visits (memory.retrieval_kd_checks; 0: the dictionary's).
  // Staging needs T_time: a run with T_time off searches as the dictionary does.
  int staged_checks = 0;
  // Staged, memory.retrieval_ahead_unsearched: the neighbours that lie ahead of the place asked
  // for come first, nearest first (the newer ones when `newer_first`, the robot going the way the
  // map was made: TravelDirection; else the older ones), and their words that the iteration has
  // no room to search are not searched; they are compared at their retrieval with the words that
  // joined since.
  bool ahead_unsearched = false;
  bool newer_first = true;
  // Staged, memory.retrieval_recent_twins (-1: off): a location asked for whose words the
  // iteration has no room to search comes back now, its words compared only with those that
  // joined since the retrieval step this many images before (RetrievalStaging::JoinMarkBefore).
  int recent_twins = -1;
  // Staged, memory.retrieval_stage_deferred: a location asked for when no retrieval fits any more
  // is staged all the same when its rows were read ahead, so that the next extraction searches its
  // words and the next iterations carry it on.
  bool stage_deferred = false;
};

// Brings back at most `max_retrieved` LTM locations within `range` links of `highest` (nearest
// first, then oldest; staged, see RetrievalTime::ahead_unsearched). Their words still in the
// dictionary get a reference; words that left it are matched against it: a match replaces the old
// word (in the signature and everywhere in LTM, and the old word is removed), a non-match returns
// to the dictionary under its old id. Under T_time (memloop, issue 9; memory.retrieval_within_time)
// each location is retrieved only if it fits `time.location`: the paper bounds retrieval by count
// alone ("a maximum of two locations ... because this step is time consuming"), but re-matching one
// location's words costs about as much as quantizing an image. Deferred ones stay in LTM until an
// iteration has room (the highest hypothesis, and an appearance match, usually hold over several
// images). With `time.read_ahead` (memory.retrieval_read_ahead, T_time on), every LTM location of
// the neighbourhood is requested from the reader thread, nearest first, and one is retrieved only
// once its rows are read, waited for no longer than the deadline leaves, from the rows that thread
// read (the detector's thread does not read the file); otherwise it is deferred too, and the reader
// goes on reading it for a later iteration (a row not in the OS's cache: 50-150 ms).
// With `time.staging` too, a location's words are searched in chunks while `time.search_chunk`
// fits (leaving room for its end), over as many iterations as it takes (RetrievalStaging); it
// counts as deferred until they are all searched.
RetrievalOutcome Retrieve(LocationId highest, int max_retrieved, int range, Memory& memory,
                          LongTermMemory& ltm, const RetrievalTime& time = {});

// Staged locations wanted over the last RetrievalStaging::kCarryOnFor iterations but not this one
// (the place recognized by appearance one image may not stand out in the next) are carried on, the
// most recently wanted first, while time allows, at most `max_retrieved` of them retrieved.
RetrievalOutcome ContinueStaged(int max_retrieved, Memory& memory, LongTermMemory& ltm,
                                const RetrievalTime& time);

// The words of `location` that left the dictionary, re-matched as above (exposed for tests).
// With `rows` (read ahead for this location), word descriptors come from them when they hold them.
// With `searched`, a word's answer there is used when the word it names is still in the dictionary
// (or it matched none); the others are searched now.
RetrievalOutcome RematchWords(Location& location, Dictionary& dictionary, LongTermMemory& ltm,
                              const PrefetchedRows* rows = nullptr,
                              const WordMatches* searched = nullptr);

}  // namespace memloop
