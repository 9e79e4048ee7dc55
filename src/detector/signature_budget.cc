#include "detector/signature_budget.h"

#include <algorithm>
#include <cmath>

namespace memloop {

bool TakeNextChunk(size_t taken, size_t min_rows, double elapsed_ms, double chunk_ms,
                   double deadline_ms) {
  return taken < min_rows || elapsed_ms + chunk_ms <= deadline_ms;
}

SignatureBudget::SignatureBudget(const MemoryOptions& memory, int search_threads,
                                 std::function<double()> elapsed_ms, int kd_checks)
    : elapsed_ms_(std::move(elapsed_ms)),
      min_share_(memory.signature_min_share),
      search_threads_(std::max(1, search_threads)),
      kd_checks_(std::max(1, kd_checks)),
      min_checks_(std::min(memory.signature_min_checks, kd_checks_)) {
  if (memory.signature_within_time && memory.time_limit_ms > 0) {
    target_ms_ = memory.time_target * memory.time_limit_ms;
    limit_ms_ = memory.time_limit_ms;
    room_for_retrieval_ = memory.signature_room_for_retrieval != 0;
    over_time_goal_ = memory.over_time_goal;
  }
}

void SignatureBudget::RecordIteration(double ms) {
  if (!enabled() || over_time_goal_ <= 0) return;
  const bool over = ms > limit_ms_;
  target_scale_ += kTargetStep * (over ? -(1 - over_time_goal_) : over_time_goal_);
  target_scale_ = std::clamp(target_scale_, kMinTargetScale, 1.0);
}

SearchGate SignatureBudget::Gate(size_t features, std::function<double()> elapsed_ms,
                                 int checks) const {
  if (!enabled()) return {};
  const double leaves_share = checks > 0 ? static_cast<double>(checks) / kd_checks_ : 1.0;
  const auto min_rows = static_cast<size_t>(std::ceil(min_share_ * static_cast<double>(features)));
  // A chunk is expected to take what the last searches' chunks took, or what this search's have
  // taken so far when they are slower (the machine is slower now, or the other core busy).
  const double start_ms = elapsed_ms();
  return
      [min_rows, elapsed_ms = std::move(elapsed_ms), start_ms, chunk_ms = ChunkMs() * leaves_share,
       deadline_ms = DeadlineMs(), threads = search_threads_](size_t taken) {
        const double now_ms = elapsed_ms();
        const double so_far_ms = (now_ms - start_ms) * threads * WordIndex::kSearchChunk /
                                 static_cast<double>(std::max<size_t>(taken, 1));
        return TakeNextChunk(taken, min_rows, now_ms, std::max(chunk_ms, so_far_ms), deadline_ms);
      };
}

int SignatureBudget::Checks(size_t features, double now_ms) const {
  if (!enabled() || min_checks_ <= 0 || features == 0 || !row_.measured()) return 0;
  const double all_ms = row_.expected_ms() * static_cast<double>(features) / search_threads_;
  const double left_ms = DeadlineMs() - now_ms;
  if (all_ms <= left_ms) return 0;
  const int checks = static_cast<int>(kd_checks_ * std::max(0.0, left_ms) / all_ms);
  return checks >= kd_checks_ ? 0 : std::max(checks, min_checks_);
}

void SignatureBudget::RecordQuantization(double ms, size_t rows, int checks) {
  // The threads share the rows: one row on one thread takes about threads x the wall time per row.
  // A search of fewer leaves counts as the time it would have taken with all of them.
  if (!enabled() || rows == 0) return;
  const double leaves_share = checks > 0 ? static_cast<double>(checks) / kd_checks_ : 1.0;
  row_.Record(ms * search_threads_ / static_cast<double>(rows) / leaves_share);
}

SearchOptions SignatureBudget::Search(size_t features, int checks) const {
  return {Gate(features, elapsed_ms_, checks), false, checks};
}

void SignatureBudget::RecordAfterQuantization(double ms) {
  if (enabled()) after_.Record(ms);
}

Signature SignatureBudget::Create(Features& features, Dictionary& dictionary, int* new_words,
                                  int* skipped) {
  const double start_ms = elapsed_ms_();
  const int checks = Checks(features.keypoints.size(), start_ms);
  double search_ms = 0;
  Signature signature = CreateSignature(features, dictionary, new_words,
                                        Search(features.keypoints.size(), checks), &search_ms);
  Finish(start_ms, search_ms, signature.words.size(), checks, features, skipped);
  return signature;
}

Signature SignatureBudget::Match(Features& features, const Dictionary& dictionary, int* skipped) {
  const double start_ms = elapsed_ms_();
  const int checks = Checks(features.keypoints.size(), start_ms);
  size_t searched = 0;
  Signature signature =
      MatchSignature(features, dictionary, Search(features.keypoints.size(), checks), &searched);
  Finish(start_ms, elapsed_ms_() - start_ms, searched, checks, features, skipped);
  return signature;
}

void SignatureBudget::Finish(double start_ms, double search_ms, size_t quantized, int checks,
                             Features& features, int* skipped) {
  RecordQuantization(search_ms, quantized, checks);
  *skipped = static_cast<int>(features.keypoints.size() - quantized);
  KeepFirstFeatures(features, quantized);
  searched_at_ms_ = start_ms + search_ms;
  last_checks_ = checks;
}

void SignatureBudget::QuantizationOver() {
  RecordAfterQuantization(elapsed_ms_() - searched_at_ms_);
}

}  // namespace memloop
