// Resume after a restart or a crash. Besides LTM, a map file holds a checkpoint of what the
// detector keeps in RAM: the STM and WM locations, the dictionary's words with the history of its
// kd-forest (replayed point by point, so searches give the same words as before), the filter's
// posterior, the past matches waiting to be absorbed and the detector's counters. A checkpoint
// is committed in the same transaction as every LTM write queued before it, and the writer
// commits only whole checkpoints (long_term_memory.h), so the file always holds one consistent
// moment of the run. Only what changed since the previous checkpoint is written.
#pragma once

#include <deque>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include "detector/bayes_filter.h"
#include "detector/map_editor.h"
#include "detector/memory.h"
#include "detector/transfer.h"
#include "storage/ltm_database.h"
#include "vocabulary/word_bitset.h"
#include "vocabulary/word_index.h"

namespace memloop {

struct DetectorCounters {
  ImageIndex last_image = kNoImage;  // the last image processed
  long long images_processed = 0;
  LocationId newest_location = kNoLocation;  // L_t-1 for the next image
  // The value the last image with a hypothesis compared with T_loop (filter.loop_ratio,
  // filter.cap_merged_images); 0 in a map written before it was kept (2026-12-05).
  double previous_hypothesis_value = 0;
};

// Everything a resumed detector starts from.
struct ResumeState {
  DetectorCounters counters;
  std::map<LocationId, Location> locations;  // STM and WM
  std::deque<LocationId> stm;                // oldest first
  LocationId next_location_id = 1;
  std::vector<WordId> words;  // the dictionary: the words of `locations`
  std::vector<WordId> words_referenced_by_ltm;
  WordId next_word_id = 1;
  IndexHistory index;
  IdMap<double> posterior;
  double virtual_place = 1;
  std::vector<PastMatch> past_matches;
  std::map<LocationId, long long> kept_last;  // RecentRetrievals of retrieved_kept_last_iterations
};

class CheckpointWriter {
 public:
  // What changed since the previous call (everything at the first call of this object).
  CheckpointData Next(const Memory& memory, const BayesFilter& filter,
                      const std::vector<PastMatch>& past_matches, const DetectorCounters& counters,
                      const RecentRetrievals& kept_last = RecentRetrievals(0));

 private:
  void AddState(CheckpointData& checkpoint, const std::string& key,
                std::vector<unsigned char> value);

  bool first_ = true;
  std::unordered_map<LocationId, size_t> location_hashes_;  // as last written
  std::unordered_map<std::string, size_t> state_hashes_;
  int index_build_count_ = -1;
  size_t index_points_written_ = 0;
  WordBitset descriptors_written_;                       // words whose descriptor the file holds
  WordBitset descriptors_to_forget_;                     // held, but named by no point any more
  std::pair<int, size_t> pending_words_written_{-1, 0};  // (build count, snapshot point)
};

// Reads the checkpoint of a map whose words are of `dictionary`'s kind. Throws DatabaseError
// naming the file when it holds none (a map of memloop format 1) or the checkpoint is damaged;
// its message says what could not be done: "cannot <use>" ("resume", "localize against it").
ResumeState ReadCheckpoint(LtmDatabase& database, const Dictionary& dictionary,
                           const std::string& use = "resume");

// Reads the checkpoint into `memory` (its dictionary included), `filter`, `editor`'s past
// matches and `kept_last`, and returns its counters. Throws DatabaseError naming the file when the
// checkpoint cannot be read or does not fit together.
DetectorCounters RestoreCheckpoint(LtmDatabase& database, Memory& memory, BayesFilter& filter,
                                   MapEditor& editor, RecentRetrievals& kept_last,
                                   const std::string& use = "resume");

// The counters of the map's last checkpoint alone (no dictionary needed); none when it holds no
// checkpoint. Throws DatabaseError naming the file when they are damaged.
std::optional<DetectorCounters> ReadCheckpointCounters(LtmDatabase& database);

// A map of this memloop's format with no checkpoint, no location and no image: what a run killed
// before its first checkpoint was committed leaves; resumed, it starts afresh. False for a map
// whose checkpoint cannot be read (resuming it says why).
bool MapHoldsNoImage(LtmDatabase& database);

// What is wrong with the map's resume checkpoint, read whole without the dictionary (inspect):
// empty when it reads back, or the map holds none or one of an older format.
std::string CheckpointProblem(LtmDatabase& database);

// The location as a checkpoint row, and back (throws Error when the bytes are not one).
std::vector<unsigned char> EncodeLocation(const Location& location);
Location DecodeLocation(const std::vector<unsigned char>& bytes);

}  // namespace memloop
