#include "detector/signature_budget.h"

#include <algorithm>
#include <cmath>

namespace memloop {

bool TakeNextChunk(size_t taken, size_t min_rows, double elapsed_ms, double chunk_ms,
                   double deadline_ms) {
  return taken < min_rows || elapsed_ms + chunk_ms <= deadline_ms;
}

SignatureBudget::SignatureBudget(const MemoryOptions& memory, int search_threads,
                                 std::function<double()> elapsed_ms)
    : elapsed_ms_(std::move(elapsed_ms)),
      min_share_(memory.signature_min_share),
      search_threads_(std::max(1, search_threads)) {
  if (memory.signature_within_time && memory.time_limit_ms > 0) {
    target_ms_ = memory.time_target * memory.time_limit_ms;
  }
}

SearchGate SignatureBudget::Gate(size_t features, std::function<double()> elapsed_ms) const {
  if (!enabled()) return {};
  const auto min_rows = static_cast<size_t>(std::ceil(min_share_ * static_cast<double>(features)));
  // A chunk is expected to take what the last searches' chunks took, or what this search's have
  // taken so far when they are slower (the machine is slower now, or the other core busy).
  const double start_ms = elapsed_ms();
  return [min_rows, elapsed_ms = std::move(elapsed_ms), start_ms, chunk_ms = ChunkMs(),
          deadline_ms = DeadlineMs(), threads = search_threads_](size_t taken) {
    const double now_ms = elapsed_ms();
    const double so_far_ms = (now_ms - start_ms) * threads * WordIndex::kSearchChunk /
                             static_cast<double>(std::max<size_t>(taken, 1));
    return TakeNextChunk(taken, min_rows, now_ms, std::max(chunk_ms, so_far_ms), deadline_ms);
  };
}

void SignatureBudget::RecordQuantization(double ms, size_t rows) {
  // The threads share the rows: one row on one thread takes about threads x the wall time per row.
  if (enabled() && rows > 0) row_.Record(ms * search_threads_ / static_cast<double>(rows));
}

void SignatureBudget::RecordAfterQuantization(double ms) {
  if (enabled()) after_.Record(ms);
}

Signature SignatureBudget::Create(Features& features, Dictionary& dictionary, int* new_words,
                                  int* skipped) {
  const double start_ms = elapsed_ms_();
  double search_ms = 0;
  Signature signature = CreateSignature(features, dictionary, new_words,
                                        Gate(features.keypoints.size(), elapsed_ms_), &search_ms);
  Finish(start_ms, search_ms, signature.words.size(), features, skipped);
  return signature;
}

Signature SignatureBudget::Match(Features& features, const Dictionary& dictionary, int* skipped) {
  const double start_ms = elapsed_ms_();
  size_t searched = 0;
  Signature signature =
      MatchSignature(features, dictionary, Gate(features.keypoints.size(), elapsed_ms_), &searched);
  Finish(start_ms, elapsed_ms_() - start_ms, searched, features, skipped);
  return signature;
}

void SignatureBudget::Finish(double start_ms, double search_ms, size_t quantized,
                             Features& features, int* skipped) {
  RecordQuantization(search_ms, quantized);
  *skipped = static_cast<int>(features.keypoints.size() - quantized);
  KeepFirstFeatures(features, quantized);
  searched_at_ms_ = start_ms + search_ms;
}

void SignatureBudget::QuantizationOver() {
  RecordAfterQuantization(elapsed_ms_() - searched_at_ms_);
}

}  // namespace memloop
