#include <algorithm>
#include <cassert>
#include <chrono>
#include <cmath>
#include <deque>
#include <future>
#include <unordered_map>

#include "memloop/errors.h"
#include "util/background_threads.h"
#include "util/thread_name.h"
#include "util/thread_priority.h"
#include "util/work_team.h"
#include "vocabulary/flann_deterministic.h"
#include "vocabulary/index_history.h"
#include "vocabulary/point_map.h"
#include "vocabulary/word_index.h"

namespace memloop {
namespace {

float TrueDistance(const flann::L2<float>&, float squared) {
  return std::sqrt(std::max(0.0f, squared));
}
float TrueDistance(const flann::Hamming<unsigned char>&, unsigned int bits) {
  return static_cast<float>(bits);
}

// FLANN index over the words, with the words' descriptors owned here: FLANN keeps pointers into
// the points it is given, so they live in `buffers_` until the next rebuild compacts them.
template <typename Distance>
class FlannWordIndex : public WordIndex {
 public:
  using Element = typename Distance::ElementType;
  using Index = flann::Index<Distance>;

  FlannWordIndex(DescriptorKind kind, int dim, const DictionaryOptions& options)
      : WordIndex(kind, dim), options_(options), search_team_(options.search_threads) {}
  // A build running in the background reads buffers_: it ends before they go.
  ~FlannWordIndex() override {
    background_.JoinAll();
    pending_.reset();
  }

  void Add(const std::vector<WordId>& ids, const cv::Mat& descriptors) override {
    assert(descriptors.type() == cv_type() && descriptors.cols == dim());
    assert(static_cast<int>(ids.size()) == descriptors.rows);
    if (ids.empty()) return;
    buffers_.emplace_back(ids.size() * dim());
    std::vector<Element>& buffer = buffers_.back();
    for (int row = 0; row < descriptors.rows; ++row) {
      std::copy_n(descriptors.ptr<Element>(row), dim(), buffer.data() + row * dim());
    }
    flann::Matrix<Element> points(buffer.data(), ids.size(), dim());
    const size_t first_point = next_point_;  // FLANN names points in order, never reusing one
    next_point_ += ids.size();
    batch_starts_.push_back(first_point);
    if (index_) {
      index_->addPoints(points, /*rebuild_threshold=*/1.0f);  // <= 1: never rebuild by itself
    } else {
      Build(points);
    }
    for (size_t i = 0; i < ids.size(); ++i) {
      points_.Set(ids[i], first_point + i);
      point_words_.push_back(ids[i]);
    }
    if (first_point == 0) {  // this Add built the index
      size_at_build_ = ids.size();
      return;
    }
    changes_since_build_ += ids.size();
    if (pending_) {
      ++pending_->age;
      if (!pending_->catching_up && CatchUpDue()) {
        StartCatchUp();
      } else if (pending_->catching_up) {
        KeepCatchingUp();
      }
      if (pending_->catching_up && SwapDue() && !CatchUpAgain()) FinishBuild();
      // Still pending at or past its swap: late (a late catch-up alone is not: it adds the same
      // points one by one, in other batches, and the new forest is the same, KeepCatchingUp).
      if (pending_ && pending_->age >= SwapDelay(pending_->words.size())) ++late_steps_;
    } else if (changes_since_build_ >
               options_.rebuild_fraction * std::max<size_t>(size_at_build_, 1)) {
      if (options_.rebuild_delay > 0 && points_.size() > 0) {
        StartBuild();
      } else {
        Rebuild();
      }
    }
  }

  void Remove(WordId id) override {
    const size_t point = points_.PointOf(id);
    if (point == PointMap::kNoPoint) return;
    index_->removePoint(point);
    points_.Erase(id);
    ++changes_since_build_;
    if (pending_) removed_since_snapshot_.push_back(id);
  }

  bool Contains(WordId id) const override { return points_.Contains(id); }
  size_t size() const override { return points_.size(); }
  int build_count() const override { return build_count_; }
  int late_steps() const override { return late_steps_; }
  void SetSwapWait(std::function<double()> budget_ms) override {
    swap_wait_ms_ = std::move(budget_ms);
  }

  cv::Mat Descriptor(WordId id) const override {
    const Element* data = Point(id);
    if (data == nullptr) return {};
    return cv::Mat(1, dim(), cv_type(), const_cast<Element*>(data)).clone();
  }

  cv::Mat PointDescriptor(size_t point) const override {
    assert(point < next_point_);
    return cv::Mat(1, dim(), cv_type(), const_cast<Element*>(index_->getPoint(point))).clone();
  }

  std::vector<WordId> PendingWords() const override {
    return pending_ ? pending_->words : std::vector<WordId>();
  }

  IndexHistory History(size_t from_point, bool complete) const override {
    IndexHistory history;
    history.build_count = build_count_;
    history.size_at_build = size_at_build_;
    history.changes_since_build = changes_since_build_;
    history.batch_starts = batch_starts_;
    history.point_count = next_point_;
    history.first_point = std::min(from_point, next_point_);
    history.point_words.assign(point_words_.begin() + history.first_point, point_words_.end());
    if (complete) {
      history.descriptors.create(static_cast<int>(next_point_ - history.first_point), dim(),
                                 cv_type());
    }
    for (size_t point = history.first_point; complete && point < next_point_; ++point) {
      std::copy_n(index_->getPoint(point), dim(),
                  history.descriptors.ptr<Element>(static_cast<int>(point - history.first_point)));
    }
    if (pending_) {
      history.pending = true;
      if (complete) history.pending_words = pending_->words;
      history.pending_point = pending_->snapshot_point;
      history.pending_age = pending_->age;
    }
    return history;
  }

  void Replay(const IndexHistory& history, const std::vector<WordId>& live_words) override {
    CheckIndexHistory(history, dim(), cv_type());
    background_.JoinAll();  // a build reads buffers_
    pending_.reset();
    index_.reset();
    buffers_.clear();
    points_.Clear();
    for (size_t batch = 0; batch < history.batch_starts.size(); ++batch) {
      const size_t begin = history.batch_starts[batch];
      const size_t end = batch + 1 < history.batch_starts.size() ? history.batch_starts[batch + 1]
                                                                 : history.point_count;
      buffers_.emplace_back((end - begin) * dim());
      for (size_t point = begin; point < end; ++point) {
        std::copy_n(history.descriptors.ptr<Element>(static_cast<int>(point)), dim(),
                    buffers_.back().data() + (point - begin) * dim());
      }
      flann::Matrix<Element> points(buffers_.back().data(), end - begin, dim());
      if (index_) {
        index_->addPoints(points, /*rebuild_threshold=*/1.0f);
      } else {
        Build(points);
      }
    }
    const LatestPoints latest = LatestPointsOf(history);
    for (WordId word : live_words) {
      const auto found = latest.overall.find(word);
      if (found == latest.overall.end()) {
        throw Error("word " + std::to_string(word) + " is not in the dictionary's index history");
      }
      points_.Set(word, found->second);
    }
    for (size_t point = 0; point < history.point_count; ++point) {
      if (points_.WordOf(point) == kNoWord) index_->removePoint(point);
    }
    point_words_ = history.point_words;
    batch_starts_ = history.batch_starts;
    next_point_ = history.point_count;
    size_at_build_ = history.size_at_build;
    changes_since_build_ = history.changes_since_build;
    build_count_ = history.build_count;
    if (history.pending) ReplayPendingBuild(history, latest.before_pending);
  }

  std::vector<std::array<Neighbour, 2>> Search(const cv::Mat& queries,
                                               const SearchOptions& search) const override {
    assert(queries.type() == cv_type() && queries.cols == dim());
    std::vector<std::array<Neighbour, 2>> result(queries.rows);
    const size_t k = std::min<size_t>(2, size());
    if (k == 0 || queries.rows == 0) return result;
    cv::Mat contiguous = queries.isContinuous() ? queries : queries.clone();
    flann::Matrix<Element> query_matrix(contiguous.ptr<Element>(), queries.rows, dim());
    using DistanceType = typename Distance::ResultType;
    std::vector<size_t> indices(queries.rows * k, static_cast<size_t>(-1));
    std::vector<DistanceType> distances(queries.rows * k);
    flann::Matrix<size_t> index_matrix(indices.data(), queries.rows, k);
    flann::Matrix<DistanceType> distance_matrix(distances.data(), queries.rows, k);
    flann::SearchParams params(search.checks > 0 ? search.checks : options_.kd_checks);
    params.cores = 1;  // threads are search_team_'s: the caller works too (work_team.h)
    // Each query is searched alone and writes only its own rows: the same answers whatever the
    // number of threads.
    // No helper: Run works on the caller's thread and keeps no state, so one is shared by every
    // index and thread.
    static WorkTeam alone(1);
    const size_t searched =
        (search.caller_only ? alone : search_team_)
            .Run(
                queries.rows, kSearchChunk,
                [&](size_t begin, size_t end) {
                  const size_t rows = end - begin;
                  flann::Matrix<Element> chunk_queries(query_matrix[begin], rows, dim());
                  flann::Matrix<size_t> chunk_indices(index_matrix[begin], rows, k);
                  flann::Matrix<DistanceType> chunk_distances(distance_matrix[begin], rows, k);
                  index_->knnSearch(chunk_queries, chunk_indices, chunk_distances, k, params);
                },
                search.gate);
    result.resize(searched);
    for (size_t row = 0; row < searched; ++row) {
      for (size_t n = 0; n < k; ++n) {
        const WordId word = points_.WordOf(index_matrix[row][n]);
        if (word == kNoWord) continue;  // fewer than k found
        result[row][n] = {word, TrueDistance(Distance(), distance_matrix[row][n])};
      }
    }
    return result;
  }

 private:
  const Element* Point(WordId id) const {
    const size_t point = points_.PointOf(id);
    return point == PointMap::kNoPoint ? nullptr : index_->getPoint(point);
  }

  void Build(const flann::Matrix<Element>& points) {
    index_ = BuildIndex<Distance>(points, options_);
    ++build_count_;
  }

  // What the background thread makes: the index over the snapshot and its point <-> word map.
  struct Built {
    std::unique_ptr<Index> index;
    PointMap points;
  };
  struct PendingBuild {
    std::vector<WordId> words;  // sorted: point k of the new index is words[k]
    size_t snapshot_point = 0;  // next_point_ when it started
    int age = 0;                // Adds since
    std::vector<Element> buffer;
    std::future<Built> built;
    // The catch-up (StartCatchUp, CatchUpAgain): the points from the snapshot to catch_up_point,
    // added to the new index in the background, in rounds; their descriptors are copied there
    // into catch_up_buffers, one per round (a deque: a round's buffer does not move while the
    // next ones are added).
    bool catching_up = false;
    int late_rounds = 0;  // CatchUpAgain's
    size_t catch_up_point = 0;
    std::deque<std::vector<Element>> catch_up_buffers;
    std::future<Built> caught_up;
  };

  // Half-way to its use (a fixed age, so that the same history gives the same index), the
  // points added since the snapshot are added to the new index in the background: the swap then
  // adds only those that came after. With T_time on the same ages hold, but a build not done by
  // then is not waited for: its step moves to the first Add at which it is done. A machine fast
  // enough for the schedule then gives the index T_time off gives (issue 35: three default runs
  // of gp_walk_a accepted 67, 65 and 68 loop closures when the forest was used as soon as built).
  bool CatchUpDue() const {
    if (pending_->age < CatchUpAge()) return false;
    return !options_.rebuild_swap_when_ready || DoneWithin(pending_->built);
  }
  bool SwapDue() const {
    if (pending_->age < SwapDelay(pending_->words.size())) return false;
    return !options_.rebuild_swap_when_ready || DoneWithin(pending_->caught_up);
  }
  // Done, or done within what the iteration can spare (SetSwapWait): the build thread runs at a
  // lower priority, so on a loaded machine it is late unless the detector's thread gives it time.
  template <typename T>
  bool DoneWithin(const std::future<T>& step) const {
    const double wait_ms = swap_wait_ms_ ? std::max(0.0, swap_wait_ms_()) : 0.0;
    return step.wait_for(std::chrono::duration<double, std::milli>(wait_ms)) ==
           std::future_status::ready;
  }
  // T_time on, a step that came late: the schedule no longer holds.
  bool Late() const {
    return options_.rebuild_swap_when_ready && pending_->age > SwapDelay(pending_->words.size());
  }
  int CatchUpAge() const { return SwapDelay(pending_->words.size()) / 2; }

  // next_point_ when the age was CatchUpAge() (the end of that Add), also when a resumed map
  // replays a build whose catch-up had started. T_time on: now (the same when on time).
  size_t CatchUpPoint() const {
    if (options_.rebuild_swap_when_ready && pending_->age > CatchUpAge()) return next_point_;
    const auto first_batch =
        std::lower_bound(batch_starts_.begin(), batch_starts_.end(), pending_->snapshot_point);
    const size_t batch = static_cast<size_t>(first_batch - batch_starts_.begin()) + CatchUpAge();
    return batch < batch_starts_.size() ? batch_starts_[batch] : next_point_;
  }

  void StartCatchUp() {
    PendingBuild& pending = *pending_;
    pending.catching_up = true;
    pending.catch_up_point = pending.snapshot_point;
    CatchUpTo(CatchUpPoint(), std::move(pending.built));
  }

  // Between the catch-up and the swap: when a round has ended, the points that came meanwhile are
  // caught up in another, so that the swap adds only the last Add or two itself (on time it added
  // the half delay's points: 2,300-2,500 in 12-30 ms under load, issue 37). Not in the Add before
  // the swap, so that a round has an image's time to end. Whether a round has ended depends on the
  // machine, but only where the batches split: FLANN adds points one by one, so the index (and
  // every answer) is the same as with one round.
  void KeepCatchingUp() {
    PendingBuild& pending = *pending_;
    if (pending.age >= SwapDelay(pending.words.size()) - 1 ||
        next_point_ - pending.catch_up_point < kRoundMinPoints ||
        pending.caught_up.wait_for(std::chrono::seconds(0)) != std::future_status::ready) {
      return;
    }
    CatchUpTo(next_point_, std::move(pending.caught_up));
  }

  // T_time on, late: when a round ends, the points that came meanwhile are caught up in another
  // round, until few enough came for the swap to add them itself (kSwapMaxPoints) or kMaxRounds
  // late rounds. Each round is shorter than the one before: the background adds points faster
  // than images bring them. The index is the same as with one round (KeepCatchingUp).
  bool CatchUpAgain() {
    PendingBuild& pending = *pending_;
    if (!Late() || pending.late_rounds >= kMaxRounds ||
        next_point_ - pending.catch_up_point <= kSwapMaxPoints) {
      return false;
    }
    ++pending.late_rounds;
    CatchUpTo(next_point_, std::move(pending.caught_up));
    return true;
  }

  // Adds the points from catch_up_point to `end` to the index `built` will give, in the
  // background. Their rows are where Add put them (buffers_, freed only by the swap that ends
  // this build); the copy is made there too, off the iteration (tens of megabytes at the first
  // round: it took up to 27 ms here).
  void CatchUpTo(size_t end, std::future<Built> built) {
    PendingBuild& pending = *pending_;
    std::vector<const Element*> rows;
    rows.reserve(end - pending.catch_up_point);
    for (size_t point = pending.catch_up_point; point < end; ++point) {
      rows.push_back(index_->getPoint(point));
    }
    pending.catch_up_point = end;
    std::vector<Element>* buffer = &pending.catch_up_buffers.emplace_back();
    pending.caught_up = background_.Start(
        [buffer, rows = std::move(rows), dim = dim(), built = std::move(built)]() mutable {
          NameThisThread("catchup");
          LowerThisThreadsPriority();
          Built index = built.get();
          *buffer = CopyRows(rows, dim);
          if (!rows.empty()) {
            index.index->addPoints(flann::Matrix<Element>(buffer->data(), rows.size(), dim),
                                   /*rebuild_threshold=*/1.0f);
          }
          return index;
        });
  }

  // The live words in id order (so that the same history gives the same index) and where their
  // descriptors are: what a full build is made from.
  std::pair<std::vector<WordId>, std::vector<const Element*>> LiveRows() const {
    std::vector<WordId> words;
    std::vector<const Element*> rows;
    words.reserve(points_.size());
    rows.reserve(points_.size());
    points_.ForEachLive([&](WordId word, size_t point) {
      words.push_back(word);
      rows.push_back(index_->getPoint(point));
    });
    return {std::move(words), std::move(rows)};
  }

  // The rows' descriptors, one after the other.
  static std::vector<Element> CopyRows(const std::vector<const Element*>& rows, int dim) {
    std::vector<Element> buffer(rows.size() * dim);
    for (size_t i = 0; i < rows.size(); ++i) std::copy_n(rows[i], dim, buffer.data() + i * dim);
    return buffer;
  }

  // The build copies the rows itself, off the iteration (tens of megabytes at a few hundred
  // thousand words). They stay valid while it runs: buffers are freed only by the swap that ends
  // this build, or by Replay, which waits for it first.
  void StartBuild() {
    auto [words, rows] = LiveRows();
    LaunchBuild(std::move(words), {}, std::move(rows), next_point_, 0);
  }

  // A build over `words` in the background, from `buffer` (their descriptors, row by row) or, when
  // it is empty, from copies of the `rows` it makes there.
  void LaunchBuild(std::vector<WordId> words, std::vector<Element> buffer,
                   std::vector<const Element*> rows, size_t snapshot_point, int age) {
    pending_ = std::make_unique<PendingBuild>();
    removed_since_snapshot_.clear();
    pending_->words = std::move(words);
    pending_->snapshot_point = snapshot_point;
    pending_->age = age;
    pending_->buffer = std::move(buffer);  // its rows stay where they are for the new index
    std::vector<Element>* points = &pending_->buffer;               // written there, then read-only
    const std::vector<WordId>* words_of_points = &pending_->words;  // read-only while it runs
    pending_->built = background_.Start(
        [points, rows = std::move(rows), words_of_points, dim = dim(), options = options_] {
          NameThisThread("build");
          LowerThisThreadsPriority();  // the per-image thread comes first (thread_priority.h)
          if (!rows.empty()) *points = CopyRows(rows, dim);
          Built built;
          built.index = BuildIndex<Distance>(
              flann::Matrix<Element>(points->data(), words_of_points->size(), dim), options);
          // Room for the words and points the swap adds, so that it does not reallocate.
          const size_t count = words_of_points->size();
          built.points.Reserve(count == 0 ? 0 : 2 * static_cast<size_t>(words_of_points->back()),
                               2 * count);
          for (size_t point = 0; point < count; ++point) {
            built.points.Set((*words_of_points)[point], point);
          }
          return built;
        });
  }

  // The snapshot of a checkpoint's pending build: each word's descriptor as it was then.
  void ReplayPendingBuild(const IndexHistory& history,
                          const std::unordered_map<WordId, size_t>& latest_point_before) {
    std::vector<Element> buffer(history.pending_words.size() * dim());
    for (size_t i = 0; i < history.pending_words.size(); ++i) {
      const auto found = latest_point_before.find(history.pending_words[i]);
      if (found == latest_point_before.end()) {
        throw Error("word " + std::to_string(history.pending_words[i]) +
                    " of the pending rebuild is not in the dictionary's index history");
      }
      std::copy_n(history.descriptors.ptr<Element>(static_cast<int>(found->second)), dim(),
                  buffer.data() + i * dim());
    }
    LaunchBuild(history.pending_words, std::move(buffer), {}, history.pending_point,
                history.pending_age);
    for (WordId word : history.pending_words) {  // live at the snapshot, removed since
      if (!points_.Contains(word)) removed_since_snapshot_.push_back(word);
    }
  }

  // The new index replaces the old one, brought up to date: it holds the snapshot (batch 0), then
  // every point since the snapshot in order, those up to the catch-up point added in the
  // background (batch 1), the rest here (batch 2); points whose word left or came again later are
  // removed. A replay of the history (these batches, then the removal of every point but each
  // live word's latest) builds the same index. Work here is in the changes since the catch-up
  // started (and one look-up per change since the snapshot): the maps were made in the
  // background, the old index is freed there too.
  void FinishBuild() {
    std::unique_ptr<PendingBuild> pending = std::move(pending_);
    Built built = pending->caught_up.get();  // waits when not ready yet
    const size_t snapshot_size = pending->words.size();
    const size_t snapshot_point = pending->snapshot_point;
    const size_t caught_up = pending->catch_up_point - snapshot_point;  // over all rounds
    const size_t later = next_point_ - pending->catch_up_point;
    std::vector<Element> later_buffer(later * dim());
    for (size_t i = 0; i < later; ++i) {
      std::copy_n(index_->getPoint(pending->catch_up_point + i), dim(),
                  later_buffer.data() + i * dim());
    }
    if (later > 0) {
      built.index->addPoints(flann::Matrix<Element>(later_buffer.data(), later, dim()),
                             /*rebuild_threshold=*/1.0f);
    }
    // Snapshot points whose word left, or came back after the snapshot: only words removed or
    // added since can be such.
    std::vector<WordId> changed = std::move(removed_since_snapshot_);
    removed_since_snapshot_.clear();
    changed.insert(changed.end(), point_words_.begin() + snapshot_point,
                   point_words_.begin() + next_point_);
    std::sort(changed.begin(), changed.end());
    changed.erase(std::unique(changed.begin(), changed.end()), changed.end());
    size_t removed = 0;
    for (WordId word : changed) {
      const size_t in_snapshot = built.points.PointOf(word);
      if (in_snapshot == PointMap::kNoPoint) continue;
      const size_t live = points_.PointOf(word);
      if (live != PointMap::kNoPoint && live < snapshot_point) continue;
      built.index->removePoint(in_snapshot);
      built.points.Erase(word);
      ++removed;
    }
    // Points since the snapshot: point q is point snapshot_size + (q - snapshot_point) of the new
    // index, kept when it is its word's live point.
    for (size_t point = snapshot_point; point < next_point_; ++point) {
      const WordId word = point_words_[point];
      const size_t new_point = snapshot_size + (point - snapshot_point);
      if (points_.PointOf(word) == point) {
        built.points.Set(word, new_point);
      } else {
        built.index->removePoint(new_point);
        ++removed;
      }
    }
    std::deque<std::vector<Element>> buffers;
    buffers.push_back(std::move(pending->buffer));
    batch_starts_ = {0};
    size_t batch_start = snapshot_size;
    for (std::vector<Element>& round : pending->catch_up_buffers) {
      if (round.empty()) continue;
      const size_t points = round.size() / dim();
      buffers.push_back(std::move(round));
      batch_starts_.push_back(batch_start);
      batch_start += points;
    }
    if (later > 0) {
      buffers.push_back(std::move(later_buffer));
      batch_starts_.push_back(snapshot_size + caught_up);
    }
    Retire();
    index_.swap(built.index);
    buffers_.swap(buffers);
    std::swap(points_, built.points);
    // The old forest, map and buffers are freed off the iteration: in the task's body, for what it
    // captured is destroyed with the future, by whoever releases it last (Retire: this thread).
    retired_ =
        background_.Start([old = std::move(built), old_buffers = std::move(buffers)]() mutable {
          NameThisThread("free");
          LowerThisThreadsPriority();
          old = Built();
          old_buffers.clear();
        });
    std::vector<WordId> words = std::move(pending->words);
    words.insert(words.end(), point_words_.begin() + snapshot_point,
                 point_words_.begin() + next_point_);
    point_words_ = std::move(words);
    next_point_ = point_words_.size();
    size_at_build_ = snapshot_size;
    changes_since_build_ = caught_up + later + removed;
    ++build_count_;
  }

  // Insertions between the start of a build and its use when T_time is off: rebuild_delay, or one
  // per 10,000 words of the snapshot when that is more, so that a large forest (a million words
  // take about 3 s to build on 2 cores) is ready when its turn comes instead of being waited for.
  int SwapDelay(size_t snapshot_words) const {
    return std::max(options_.rebuild_delay, static_cast<int>(snapshot_words / 10000));
  }

  // Waits for the previous old forest to be freed (long done, in practice: when its captures
  // were freed here, this took 15-37 ms at 400,000-900,000 words).
  void Retire() {
    if (retired_.valid()) retired_.get();
  }

  // A new index over the live points, in word order so the same history gives the same index.
  void Rebuild() {
    const auto [ids, rows] = LiveRows();
    std::vector<Element> buffer = CopyRows(rows, dim());
    index_.reset();
    buffers_.clear();
    points_.Clear();
    size_at_build_ = ids.size();
    next_point_ = ids.size();
    changes_since_build_ = 0;
    point_words_ = ids;
    batch_starts_.clear();
    if (ids.empty()) return;
    batch_starts_.push_back(0);
    buffers_.push_back(std::move(buffer));
    Build(flann::Matrix<Element>(buffers_.back().data(), ids.size(), dim()));
    for (size_t i = 0; i < ids.size(); ++i) points_.Set(ids[i], i);
  }

  DictionaryOptions options_;
  // The most points the swap adds itself (about 2 ms; 10,000-20,000 took 45-62 ms), and the most
  // late catch-up rounds (CatchUpAgain) before it adds what is left anyway.
  static constexpr size_t kSwapMaxPoints = 1000;
  static constexpr int kMaxRounds = 8;
  // The fewest points a round between the catch-up and the swap takes (KeepCatchingUp): a round
  // costs the detector's thread a pointer per point and a thread start.
  static constexpr size_t kRoundMinPoints = 100;
  mutable WorkTeam search_team_;  // Search is const: it only reads the index
  BackgroundThreads background_;  // builds, catch-ups and frees: joined before buffers_ go
  std::unique_ptr<PendingBuild> pending_;
  std::vector<WordId> removed_since_snapshot_;  // words Remove()d while a build is pending
  std::future<void> retired_;                   // the old forest being freed after a swap
  std::function<double()> swap_wait_ms_;        // SetSwapWait
  int late_steps_ = 0;                          // late_steps()
  std::unique_ptr<Index> index_;
  std::deque<std::vector<Element>> buffers_;
  PointMap points_;                   // live words <-> their points
  std::vector<WordId> point_words_;   // every point since the build (History)
  std::vector<size_t> batch_starts_;  // first point of each Add since the build
  size_t next_point_ = 0;
  size_t size_at_build_ = 0;
  size_t changes_since_build_ = 0;
  int build_count_ = 0;
};

}  // namespace

std::unique_ptr<WordIndex> WordIndex::Create(DescriptorKind kind, int dim,
                                             const DictionaryOptions& options) {
  if (kind == DescriptorKind::kBinary) {
    return std::make_unique<FlannWordIndex<flann::Hamming<unsigned char>>>(kind, dim, options);
  }
  return std::make_unique<FlannWordIndex<flann::L2<float>>>(kind, dim, options);
}

}  // namespace memloop
