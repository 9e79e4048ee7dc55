// The signature step within the time target (memloop, issue 37; memory.signature_within_time).
// Quantizing an image's features (III-A) is most of an iteration: each feature is a kd-forest
// search, shared between two threads, and when the second thread finds the other core busy (the
// LTM writer, a background rebuild, another program) the search takes twice as long. Under a
// tight T_time that alone broke the bound, and a smaller WM cannot make up for it. So the search
// takes its chunks strongest features first, and stops taking them once the iteration, with one
// chunk more and what the steps after the quantization are expected to take, would pass the time
// target; the weaker features left are dropped from the image. Before that, when the features
// would not all fit at the search's usual cost, each is searched visiting fewer leaves, in
// proportion to the time left, down to memory.signature_min_checks: a feature searched coarsely
// still votes for its place, a dropped one does not. At least memory.signature_min_share of the
// features is quantized, however late. With T_time off, or the parameter off (the paper), every
// feature is, visiting dictionary.kd_checks leaves. After an iteration that deferred a retrieval,
// the next image's quantization also leaves the deferred locations room before T_time
// (LeaveRoom, memory.signature_room_for_retrieval).
#pragma once

#include <algorithm>
#include <cstddef>
#include <functional>

#include "detector/step_deadline.h"
#include "memloop/feature_extractor.h"
#include "memloop/options.h"
#include "vocabulary/dictionary.h"
#include "vocabulary/signature.h"
#include "vocabulary/word_index.h"

namespace memloop {

// Whether the quantization takes one more chunk, `taken` features quantized or being quantized:
// always below `min_rows`; else when a chunk started now (`chunk_ms` on one thread) would end by
// `deadline_ms` on the iteration's clock (`elapsed_ms`).
bool TakeNextChunk(size_t taken, size_t min_rows, double elapsed_ms, double chunk_ms,
                   double deadline_ms);

class SignatureBudget {
 public:
  // `elapsed_ms`: the iteration's clock; `kd_checks`: the dictionary's leaves per search.
  SignatureBudget(const MemoryOptions& memory, int search_threads,
                  std::function<double()> elapsed_ms = {},
                  int kd_checks = DictionaryOptions().kd_checks);

  // III-A's quantization of `features` within the budget (CreateSignature, MatchSignature):
  // features the search did not reach leave `features` too (KeepFirstFeatures), so that what
  // else reads them sees the signature's; `skipped` receives how many.
  Signature Create(Features& features, Dictionary& dictionary, int* new_words, int* skipped);
  Signature Match(Features& features, const Dictionary& dictionary, int* skipped);
  // Retrieval starts: the steps since the quantization's search are measured.
  void QuantizationOver();

  bool enabled() const { return target_ms_ > 0; }
  // The last image's features were searched visiting fewer leaves than kd_checks (Checks).
  bool searched_coarsely() const { return last_checks_ > 0; }
  // The gate of an image's quantization (none when disabled), `features` of them, on the
  // iteration's clock; made when the search starts. A chunk is expected to take the larger of
  // ChunkMs() and what this search's chunks have taken so far.
  // `checks` leaves per feature (0: kd_checks) scale the expected chunk.
  SearchGate Gate(size_t features, std::function<double()> elapsed_ms, int checks = 0) const;
  // The leaves each of `features` features is searched with, `now_ms` on the iteration's clock:
  // 0 (the dictionary's) when they all fit before DeadlineMs() at the expected cost, else
  // kd_checks x the share of that cost that fits, at least memory.signature_min_checks (a
  // search's time grows about as the leaves it visits).
  int Checks(size_t features, double now_ms) const;
  // The search of `rows` features took `ms` (wall time, the threads sharing it), visiting
  // `checks` leaves each (0: kd_checks); recorded as the time at kd_checks.
  void RecordQuantization(double ms, size_t rows, int checks = 0);
  // The steps from the end of the search to retrieval (the new words' insertion in the forest,
  // the rest of the signature step, rehearsal, the filter and selection) took `ms`.
  void RecordAfterQuantization(double ms);

  // The next image's quantization also leaves `ms` before T_time after the steps that follow it
  // (memory.signature_room_for_retrieval: deferred retrievals and the transfer after them); 0 =
  // the time target alone. Ignored when disabled.
  void LeaveRoom(double ms) { room_ms_ = room_for_retrieval_ ? ms : 0; }

  // The whole iteration took `ms`: the time target moves towards the share of iterations over
  // T_time that memory.over_time_goal allows (TargetMs).
  void RecordIteration(double ms);

  // The time target as the iterations over T_time have moved it: memory.time_target x T_time x
  // a scale in [kMinTargetScale, 1], lowered by kTargetStep x (1 - goal) after each iteration
  // over T_time and raised by kTargetStep x goal after each within (1 when the goal is 0). The
  // scale then settles where a share `goal` of the iterations passes T_time: a stochastic
  // approximation of that quantile of the iteration's time, whatever makes it vary (other
  // programs, a busy core, the steps' own spread).
  double TargetMs() const { return target_ms_ * target_scale_; }
  double target_scale() const { return target_scale_; }
  static constexpr double kTargetStep = 0.1;
  static constexpr double kMinTargetScale = 0.5;

  // The last feature may be taken by then: the time target, or T_time less the room asked for
  // when that is earlier, minus what the steps after the quantization are expected to take.
  double DeadlineMs() const {
    return std::min(TargetMs(), limit_ms_ - room_ms_) - after_.expected_ms();
  }
  // One chunk's expected time on one thread.
  double ChunkMs() const { return row_.expected_ms() * WordIndex::kSearchChunk; }

 private:
  void Finish(double start_ms, double search_ms, size_t quantized, int checks, Features& features,
              int* skipped);
  SearchOptions Search(size_t features, int checks) const;

  std::function<double()> elapsed_ms_;
  double searched_at_ms_ = 0;  // on the iteration's clock: the end of the last search
  double target_ms_ = 0;       // 0: disabled
  double limit_ms_ = 0;        // T_time
  double room_ms_ = 0;         // LeaveRoom
  double over_time_goal_ = 0;  // memory.over_time_goal
  double target_scale_ = 1;    // TargetMs
  bool room_for_retrieval_ = false;
  double min_share_ = 1;
  int search_threads_ = 1;
  int kd_checks_ = 0;
  int min_checks_ = 0;   // 0: never fewer leaves
  int last_checks_ = 0;  // the last search's (Checks)
  StepCost row_;         // one feature's quantization on one thread
  StepCost after_;       // the steps after the quantization, up to retrieval
};

}  // namespace memloop
