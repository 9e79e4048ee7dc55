#include "vocabulary/appearance_index.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "memloop/errors.h"
#include "util/thread_name.h"
#include "util/thread_priority.h"

namespace memloop {

AppearanceIndex::AppearanceIndex(DescriptorKind kind, int descriptor_dim, int vocabulary_size,
                                 const DictionaryOptions& index_options, size_t max_postings)
    : kind_(kind),
      descriptor_dim_(descriptor_dim),
      vocabulary_size_(vocabulary_size),
      index_options_(index_options),
      max_postings_(max_postings),
      postings_(static_cast<size_t>(std::max(vocabulary_size, 0))),
      holders_(postings_.size(), 0),
      compacted_at_(postings_.size(), 0) {
  index_options_.rebuild_delay = 0;  // built once, when frozen, in a thread of its own (Freeze)
  // A coarse quantizer: one tree and few checks cost a third of the dictionary's search, and a
  // near-nearest entry describes a place as well.
  index_options_.kd_trees = 1;
  index_options_.kd_checks = 16;
  index_options_.rebuild_swap_when_ready = false;
}

int AppearanceIndex::CollectWords(const std::vector<WordId>& ids, const cv::Mat& descriptors) {
  int collected = 0;
  // The vocabulary's whole capacity at once: cv::Mat::push_back grows by half, and each time
  // copied every row so far (at ~20,000 rows, 28 ms inside one iteration; issue 37).
  if (vocabulary_.empty() && descriptors.rows > 0 && !frozen_) {
    vocabulary_.create(vocabulary_size_, descriptors.cols, descriptors.type());
    vocabulary_.resize(0);
  }
  for (size_t row = 0; row < ids.size() && !frozen_; ++row) {
    if (entry_of_word_.count(ids[row]) > 0) continue;
    entry_of_word_[ids[row]] = static_cast<AppearanceEntry>(vocabulary_words_.size());
    vocabulary_words_.push_back(ids[row]);
    vocabulary_.push_back(descriptors.row(static_cast<int>(row)));
    ++collected;
    if (static_cast<int>(vocabulary_words_.size()) >= vocabulary_size_) Freeze();
  }
  return collected;
}

void AppearanceIndex::Freeze() {
  frozen_ = true;
  switch_word_ = vocabulary_words_.back() + kSwitchWords;
  std::vector<WordId> ids(vocabulary_words_.size());
  for (size_t entry = 0; entry < ids.size(); ++entry) ids[entry] = static_cast<WordId>(entry + 1);
  // FLANN's builds take turns on its seed (flann_word_index.cc): the same index either way.
  auto build = [kind = kind_, dim = descriptor_dim_, options = index_options_, rows = vocabulary_,
                ids = std::move(ids)] {  // shared: frozen, never written
    NameThisThread("vocab");
    StepBelowRealTimePriority();  // behind the per-image threads (thread_priority.h)
    std::unique_ptr<WordIndex> search = WordIndex::Create(kind, dim, options);
    search->Add(ids, rows);
    return search;
  };
  search_.reset();
  building_ = std::async(std::launch::async, std::move(build));
}

bool AppearanceIndex::UseSearch(const std::vector<WordId>& words) const {
  WordId newest = kNoWord;
  for (WordId word : words) newest = std::max(newest, word);
  return newest == kNoWord || newest >= switch_word_;
}

void AppearanceIndex::Reload(const std::vector<WordId>& words, const cv::Mat& rows) {
  const int cv_type = kind_ == DescriptorKind::kFloat ? CV_32F : CV_8U;
  if (static_cast<int>(words.size()) != rows.rows ||
      static_cast<int>(words.size()) > vocabulary_size_ ||
      (rows.rows > 0 && (rows.cols != descriptor_dim_ || rows.type() != cv_type))) {
    throw Error("the appearance vocabulary does not match its words or the features");
  }
  vocabulary_words_.clear();
  vocabulary_ = cv::Mat();
  entry_of_word_.clear();
  frozen_ = false;
  if (building_.valid()) building_.wait();
  building_ = {};
  search_.reset();
  for (std::vector<LocationId>& posting : postings_) posting.clear();
  std::fill(holders_.begin(), holders_.end(), 0);
  searched_bits_.clear();
  searched_count_ = 0;
  leaves_ = 0;
  left_at_.clear();
  std::fill(compacted_at_.begin(), compacted_at_.end(), 0);
  appearances_.clear();
  if (CollectWords(words, rows) != rows.rows)
    throw Error("the appearance vocabulary repeats a word");
  if (building_.valid()) search_ = building_.get();  // a resumed map describes at once
}

Appearance AppearanceIndex::Describe(const std::vector<WordId>& words,
                                     const cv::Mat& descriptors) const {
  Appearance appearance;
  if (frozen_ && UseSearch(words)) {
    if (descriptors.rows == 0) return appearance;
    if (building_.valid()) search_ = building_.get();
    for (const auto& nearest : search_->Search(descriptors)) {
      if (nearest[0].word != kNoWord) appearance.push_back(nearest[0].word - 1);
    }
  } else {
    for (WordId word : words) {
      const auto entry = entry_of_word_.find(word);
      if (entry != entry_of_word_.end()) appearance.push_back(entry->second);
    }
  }
  std::sort(appearance.begin(), appearance.end());
  appearance.erase(std::unique(appearance.begin(), appearance.end()), appearance.end());
  return appearance;
}

void AppearanceIndex::Add(LocationId id, Appearance appearance) {
  for (AppearanceEntry entry : appearance) {
    if (entry >= postings_.size()) {
      throw Error("location " + std::to_string(id) + " is described by entry " +
                  std::to_string(entry) + ", out of the appearance vocabulary");
    }
  }
  const bool searched = Searched(id);
  if (searched) Leave(id);
  Purge(id);
  appearances_[id] = std::move(appearance);
  if (searched) Enter(id);
}

void AppearanceIndex::Erase(LocationId id) {
  Leave(id);
  Purge(id);
  appearances_.erase(id);
}

bool AppearanceIndex::Tombstone(LocationId id, AppearanceEntry entry) const {
  const auto slot = static_cast<size_t>(id);
  const uint64_t left = slot < left_at_.size() ? left_at_[slot] : 0;
  return left > 0 && compacted_at_[entry] < left;
}

void AppearanceIndex::Purge(LocationId id) {
  const Appearance* appearance = Find(id);
  if (appearance == nullptr || Searched(id)) return;
  for (AppearanceEntry entry : *appearance) {
    if (!Tombstone(id, entry)) continue;
    std::vector<LocationId>& posting = postings_[entry];
    posting.erase(std::lower_bound(posting.begin(), posting.end(), id));
  }
  if (static_cast<size_t>(id) < left_at_.size()) left_at_[static_cast<size_t>(id)] = 0;
}

void AppearanceIndex::SetSearched(LocationId id, bool searched) {
  const auto slot = static_cast<size_t>(id);
  if (slot / 64 >= searched_bits_.size()) {
    searched_bits_.resize(std::max(slot / 64 + 1, 2 * searched_bits_.size()), 0);
  }
  const uint64_t bit = uint64_t{1} << (slot % 64);
  searched_bits_[slot / 64] =
      searched ? searched_bits_[slot / 64] | bit : searched_bits_[slot / 64] & ~bit;
  searched_count_ = searched ? searched_count_ + 1 : searched_count_ - 1;
}

const Appearance* AppearanceIndex::Find(LocationId id) const {
  const auto found = appearances_.find(id);
  return found == appearances_.end() ? nullptr : &found->second;
}

void AppearanceIndex::Enter(LocationId id) {
  const Appearance* appearance = Find(id);
  if (appearance == nullptr || Searched(id)) return;
  for (AppearanceEntry entry : *appearance) {
    ++holders_[entry];
    if (Tombstone(id, entry)) continue;  // it revives, in place
    std::vector<LocationId>& posting = postings_[entry];
    if (posting.empty() || posting.back() < id) {
      posting.push_back(id);  // a location's first transfer: the newest id
    } else {
      posting.insert(std::lower_bound(posting.begin(), posting.end(), id), id);
    }
  }
  SetSearched(id, true);
  const auto slot = static_cast<size_t>(id);
  if (slot >= sizes_.size()) {
    sizes_.resize(std::max(slot + 1, 2 * sizes_.size()), 0);
  }
  sizes_[slot] = static_cast<uint32_t>(appearance->size());
}

void AppearanceIndex::Leave(LocationId id) {
  if (!Searched(id)) return;
  SetSearched(id, false);
  const auto slot = static_cast<size_t>(id);
  if (slot >= left_at_.size()) left_at_.resize(std::max(slot + 1, 2 * left_at_.size()), 0);
  left_at_[slot] = ++leaves_;
  // A posting with more tombstones than holders (and a few to spare) is compacted: a Leave's cost
  // is amortized over the tombstones it removes, and Best reads at most twice the live postings.
  constexpr size_t kSpareTombstones = 8;
  for (AppearanceEntry entry : appearances_.at(id)) {
    std::vector<LocationId>& posting = postings_[entry];
    --holders_[entry];
    if (posting.size() < 2 * size_t{holders_[entry]} + kSpareTombstones) continue;
    posting.erase(std::remove_if(posting.begin(), posting.end(),
                                 [this](LocationId held) { return !Searched(held); }),
                  posting.end());
    compacted_at_[entry] = leaves_;
  }
}

namespace {

// An entry's idf over `searched` locations; 0 when none holds it or more than half do (too common
// to tell places apart), so that it is ignored.
double EntryWeight(size_t holders, double searched) {
  if (holders == 0 || 2.0 * static_cast<double>(holders) > searched) return 0;
  return std::log(searched / static_cast<double>(holders));
}

// The weight of the entries a location shares with the query, over both descriptions' sizes.
double Normalized(double shared_weight, size_t query_size, size_t location_size) {
  return shared_weight /
         std::sqrt(static_cast<double>(query_size) * static_cast<double>(location_size));
}

}  // namespace

std::vector<std::pair<AppearanceEntry, double>> AppearanceIndex::SummedEntries(
    const Appearance& query, size_t extra) const {
  const double searched = static_cast<double>(searched_count_ + extra);
  std::vector<std::pair<AppearanceEntry, double>> summed;
  for (AppearanceEntry entry : query) {
    const double idf = EntryWeight(holders_[entry] + extra, searched);
    if (idf > 0) summed.emplace_back(entry, idf);
  }
  // The bound counts holders, not tombstones: the same entries on a resumed map.
  size_t postings = 0;
  for (const auto& [entry, idf] : summed) postings += holders_[entry];
  if (max_postings_ == 0 || postings <= max_postings_) return summed;
  // Rarest first (the highest idf), ties by entry: the same choice on a resumed map.
  std::sort(summed.begin(), summed.end(), [&](const auto& a, const auto& b) {
    const size_t held_a = holders_[a.first], held_b = holders_[b.first];
    return held_a != held_b ? held_a < held_b : a.first < b.first;
  });
  postings = 0;
  size_t kept = 0;
  for (; kept < summed.size(); ++kept) {
    postings += holders_[summed[kept].first];
    if (postings > max_postings_) break;
  }
  summed.resize(kept);
  return summed;
}

AppearanceMatch AppearanceIndex::Best(const Appearance& query) const {
  AppearanceMatch best;
  const double searched = static_cast<double>(searched_count_);
  if (query.empty() || searched == 0) return best;
  const std::vector<std::pair<AppearanceEntry, double>> summed = SummedEntries(query, 0);
  double sum = 0, sum_squares = 0;
  SumPostings(summed, [&](LocationId id, double shared_weight) {
    const double score = Normalized(shared_weight, query.size(), sizes_[id]);
    sum += score;
    sum_squares += score * score;
    if (score > best.score || (score == best.score && id < best.id)) {
      best.id = id;
      best.score = score;
    }
  });
  if (best.id == kNoLocation) return best;
  const double mean = sum / searched;  // locations sharing no entry score 0
  const double variance = std::max(0.0, sum_squares / searched - mean * mean);
  best.z = variance > 0 ? (best.score - mean) / std::sqrt(variance) : 0;
  return best;
}

template <typename Visit>
void AppearanceIndex::SumPostings(const std::vector<std::pair<AppearanceEntry, double>>& summed,
                                  Visit&& visit) const {
  // The ids are taken a block at a time: every posting (sorted by id) adds into the block's
  // scores (256 KB, in cache however large LTM is: at a million locations, scores indexed by
  // every id missed the cache for each posting, most of a bounded search's time). When the
  // postings are few against the locations, each also sets its id's bit, without a branch, and
  // the set bits give the touched ids in order; when they are many, most ids are touched and
  // the block's scores are walked instead (the bits cost more than they save there: 0.53 ->
  // 0.42 ms at 25,000 locations of the 8,192-entry vocabulary, BM_AppearanceBest). Weights are
  // summed in `summed`'s order and locations visited in id order, so a resumed map (its postings
  // entered in another order) gives the same z.
  constexpr size_t kBlockIds = size_t{1} << 15;
  struct Cursor {
    const LocationId* at;
    const LocationId* end;
    double idf;
  };
  std::vector<Cursor> cursors;
  cursors.reserve(summed.size());
  for (const auto& [entry, idf] : summed) {
    const std::vector<LocationId>& posting = postings_[entry];
    if (!posting.empty()) cursors.push_back({posting.data(), posting.data() + posting.size(), idf});
  }
  size_t postings = 0;
  for (const Cursor& cursor : cursors) postings += static_cast<size_t>(cursor.end - cursor.at);
  const bool walk_scores = postings * 4 >= sizes_.size();
  block_scores_.resize(kBlockIds, 0.0);
  touched_.resize(kBlockIds / 64, 0);
  while (true) {
    size_t first = std::numeric_limits<size_t>::max();
    for (const Cursor& cursor : cursors) {
      if (cursor.at != cursor.end) first = std::min(first, static_cast<size_t>(*cursor.at));
    }
    if (first == std::numeric_limits<size_t>::max()) return;
    const size_t base = first - first % kBlockIds;
    const size_t end = base + kBlockIds;
    for (Cursor& cursor : cursors) {
      for (; cursor.at != cursor.end && static_cast<size_t>(*cursor.at) < end; ++cursor.at) {
        const size_t slot = static_cast<size_t>(*cursor.at) - base;
        block_scores_[slot] += cursor.idf;
        if (!walk_scores) touched_[slot / 64] |= uint64_t{1} << (slot % 64);
      }
    }
    if (walk_scores) {
      const size_t slots = std::min(kBlockIds, sizes_.size() - base);
      for (size_t slot = 0; slot < slots; ++slot) {
        if (block_scores_[slot] == 0) continue;  // every summed entry weighs more than 0
        const auto id = static_cast<LocationId>(base + slot);
        if (Searched(id)) visit(id, block_scores_[slot]);  // else a tombstone's
        block_scores_[slot] = 0;
      }
      continue;
    }
    for (size_t word = 0; word < touched_.size(); ++word) {
      for (uint64_t bits = touched_[word]; bits != 0; bits &= bits - 1) {
        const size_t slot = 64 * word + static_cast<size_t>(__builtin_ctzll(bits));
        const auto id = static_cast<LocationId>(base + slot);
        if (Searched(id)) visit(id, block_scores_[slot]);
        block_scores_[slot] = 0;
      }
      touched_[word] = 0;
    }
  }
}

double AppearanceIndex::Score(const Appearance& query, LocationId id) const {
  const auto described = appearances_.find(id);
  if (query.empty() || described == appearances_.end()) return 0;
  const Appearance& location = described->second;
  // Not searched: counted as one more searched location, as Best would if it were.
  const size_t outside = Searched(id) ? 0 : 1;
  double score = 0;
  for (const auto& [entry, idf] : SummedEntries(query, outside)) {
    if (std::binary_search(location.begin(), location.end(), entry)) score += idf;
  }
  return Normalized(score, query.size(), location.size());
}

}  // namespace memloop
