#include "storage/long_term_memory.h"

#include <algorithm>
#include <utility>

#include "detector/stopwatch.h"
#include "memloop/errors.h"
#include "memloop/map_info.h"

namespace memloop {
namespace {

// A rename or redirection `from -> to` queued after others: those that ended at `from` now end at
// `to`, and stay in the overlay until this one is committed too.
template <typename Map, typename Id>
void ResolveChains(Map& pending, Id from, Id to, long long sequence) {
  for (auto& [key, entry] : pending) {
    if (entry.second == from) entry = {sequence, to};
  }
  pending[from] = {sequence, to};
}

// `links` (a location's, sorted) gains `target` unless it holds it already or it is `self`.
void AddSortedLink(std::vector<LocationId>& links, LocationId target, LocationId self) {
  const auto place = std::lower_bound(links.begin(), links.end(), target);
  if (target != self && (place == links.end() || *place != target)) links.insert(place, target);
}

// A map is written by one process at a time, and read (localization) while none writes it: its
// locations are read on demand, and a writer would change them between two reads.
std::unique_ptr<MapWriterLock> LockUnlessReadOnly(const std::string& path, LtmDatabase::Mode mode) {
  if (mode != LtmDatabase::Mode::kRead) return std::make_unique<MapWriterLock>(path);
  ThrowIfBeingWritten(path, "localize against it");
  return nullptr;
}

}  // namespace

std::string LongTermMemory::WriteFailure(const std::string& path, const std::exception& error) {
  std::string what = error.what();
  if (what.rfind(path + ": ", 0) == 0) what.erase(0, path.size() + 2);
  return "writing the map failed: " + what;
}

LongTermMemory::LongTermMemory(const std::string& path, LtmDatabase::Mode mode,
                               const LtmOptions& options)
    : path_(path),
      read_only_(mode == LtmDatabase::Mode::kRead),
      writer_lock_(LockUnlessReadOnly(path, mode)),
      reader_(path, mode),
      max_pending_bytes_(options.max_pending_bytes),
      max_page_count_(options.max_page_count),
      committed_writes_(options.max_replayed_writes),
      recent_words_(options.recent_word_bytes) {
  if (writer_lock_) writer_lock_->Adopt();  // the map is open: its lock file goes with it
  for (LocationId id : reader_.ReadLocationIds()) ids_.insert(id);
  for (const auto& [from, to] : reader_.ReadAllLinks()) {
    if (Contains(from)) links_[from].push_back(to);
  }
  if (!read_only_) writer_ = std::thread([this, options] { WriterLoop(options); });
}

LongTermMemory::~LongTermMemory() {
  if (direct_) {
    // As the writer would: without checkpoints every write is kept, with them only whole ones
    // (an open transaction is rolled back when the connection closes).
    try {
      Flush();
    } catch (const std::exception&) {  // a destructor cannot report; Flush() and calls before do
    }
    return;
  }
  if (read_only_) return;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stopping_ = true;
  }
  wake_writer_.notify_one();
  writer_.join();
}

void LongTermMemory::ThrowIfFailedLocked() const {
  if (!writer_failure_.empty()) throw DatabaseError(path_, writer_failure_);
}

void LongTermMemory::Overlay(long long sequence, const Operation& operation) {
  if (const auto* store = std::get_if<StoreLocation>(&operation)) {
    pending_locations_[store->location.id] = {sequence, store->location};
  } else if (const auto* word = std::get_if<StoreWordOp>(&operation)) {
    pending_words_[word->id] = {sequence, word->descriptor};
  } else if (const auto* rename = std::get_if<ReplaceWordOp>(&operation)) {
    pending_words_.erase(rename->old_id);
    ResolveChains(pending_renames_, rename->old_id, rename->new_id, sequence);
  } else if (const auto* redirect = std::get_if<RedirectOp>(&operation)) {
    pending_locations_.erase(redirect->absorbed);
    pending_links_.erase(redirect->absorbed);
    ResolveChains(pending_redirects_, redirect->absorbed, redirect->survivor, sequence);
  } else if (const auto* link = std::get_if<AddLinkOp>(&operation)) {
    pending_links_[link->from].emplace_back(sequence, *link);
  }
}

long long LongTermMemory::CommittableSequenceLocked() const {
  return last_checkpoint_sequence_ > 0 ? last_checkpoint_sequence_ : next_sequence_ - 1;
}

size_t LongTermMemory::CommittableCountLocked() const {
  const long long last = CommittableSequenceLocked();
  if (queue_.empty() || last < queue_.front().sequence) return 0;
  return static_cast<size_t>(last - queue_.front().sequence + 1);
}

template <typename Predicate>
void LongTermMemory::WaitForWriterLocked(std::unique_lock<std::mutex>& lock, Predicate done) {
  ++waiting_;
  wake_writer_.notify_one();
  if (!done() && writer_failure_.empty()) {  // counted only when there is something to wait for
    const Stopwatch waited;
    committed_.wait(lock, [&] { return done() || !writer_failure_.empty(); });
    writer_wait_ms_ += waited.ElapsedMs();
  }
  --waiting_;
  ThrowIfFailedLocked();
}

void LongTermMemory::Enqueue(Operation operation) {
  size_t bytes = 64;
  if (const auto* store = std::get_if<StoreLocation>(&operation)) {
    bytes += store->location.ApproximateBytes();
  } else if (const auto* word = std::get_if<StoreWordOp>(&operation)) {
    bytes += word->descriptor.size();
  } else if (const auto* checkpoint = std::get_if<CheckpointData>(&operation)) {
    bytes += checkpoint->bytes();
  } else if (const auto* appearance = std::get_if<AppearanceOp>(&operation)) {
    bytes += appearance->entries.size() * sizeof(uint32_t);
  } else if (const auto* vocabulary = std::get_if<VocabularyOp>(&operation)) {
    bytes += vocabulary->rows.size();
  } else if (const auto* image = std::get_if<MapImage>(&operation)) {
    bytes += image->name.size();
  }
  if (read_only_) {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!std::holds_alternative<CheckpointData>(operation)) Overlay(next_sequence_++, operation);
    return;
  }
  if (direct_) return ApplyDirectly(operation);
  bool committable = false;
  {
    std::unique_lock<std::mutex> lock(mutex_);
    ThrowIfFailedLocked();
    // Back-pressure: wait for the writer when it has something it may commit (with checkpoints,
    // writes after the last one cannot be committed before the next).
    const auto can_free = [&] { return CommittableSequenceLocked() > committed_sequence_; };
    if (pending_bytes_ + bytes > max_pending_bytes_ && can_free()) {
      WaitForWriterLocked(lock, [&] {
        return pending_bytes_ + bytes <= max_pending_bytes_ || !can_free() || server_lost_;
      });
    }
    if (pending_bytes_ + bytes > max_pending_bytes_ && server_lost_) {
      throw DatabaseError(path_, "the server has been away while " +
                                     std::to_string(pending_bytes_ >> 20) +
                                     " MB of writes queued, the bound: the run stops at its "
                                     "last committed checkpoint (--resume goes on from it)");
    }
    const long long sequence = next_sequence_++;
    if (std::holds_alternative<CheckpointData>(operation)) last_checkpoint_sequence_ = sequence;
    Overlay(sequence, operation);
    pending_bytes_ += bytes;
    queue_.push_back({sequence, bytes, std::move(operation)});
    committable = CommittableCountLocked() > 0;
  }
  // With checkpoints, what follows the last one cannot be committed yet: waking the writer for
  // each of a transferred location's ~200 words cost a futex call and a context switch each.
  if (committable) wake_writer_.notify_one();
}

void LongTermMemory::Store(const Location& location) {
  ids_.insert(location.id);
  Enqueue(StoreLocation{location});
  SetLinks(location);
}

void LongTermMemory::SetLinks(const Location& location) {
  Location links_only;
  links_only.id = location.id;
  links_only.neighbours = location.neighbours;
  links_only.loop_closures = location.loop_closures;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    Rewrite(links_only);
  }
  links_[location.id] = links_only.Links();
}

void LongTermMemory::StoreWord(WordId id, const cv::Mat& descriptor) {
  const cv::Mat row = descriptor.isContinuous() ? descriptor : descriptor.clone();
  const unsigned char* bytes = row.ptr<unsigned char>();
  Enqueue(StoreWordOp{id, std::vector<unsigned char>(bytes, bytes + row.total() * row.elemSize())});
}

void LongTermMemory::ReplaceWord(WordId old_id, WordId new_id) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    read_words_.erase(old_id);  // the word goes from the map
  }
  Enqueue(ReplaceWordOp{old_id, new_id});
}

void LongTermMemory::RedirectLocation(LocationId absorbed, LocationId survivor,
                                      const std::vector<LocationId>& linked) {
  ids_.erase(absorbed);
  Enqueue(RedirectOp{absorbed, survivor});
  // Links are symmetric: only the locations linked to `absorbed` can name it. An LTM location
  // knows them itself; one in memory, whose links LTM does not hold, is told them (`linked`).
  // Looking at every entry instead cost 5 ms a Rehearsal merge at 24,000 LTM locations.
  std::vector<LocationId> named = linked;
  if (const auto own = links_.find(absorbed); own != links_.end()) {
    named.insert(named.end(), own->second.begin(), own->second.end());
    links_.erase(own);
  }
  for (LocationId id : named) {
    const auto entry = links_.find(id);
    if (entry == links_.end()) continue;
    std::vector<LocationId>& links = entry->second;
    const auto link = std::lower_bound(links.begin(), links.end(), absorbed);
    if (link == links.end() || *link != absorbed) continue;
    links.erase(link);
    AddSortedLink(links, survivor, id);
  }
}

void LongTermMemory::AddLink(LocationId from, LocationId to, bool loop_closure) {
  Enqueue(AddLinkOp{from, to, loop_closure});
  const auto links = links_.find(from);
  if (links == links_.end()) return;
  LocationId target = to;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    target = Redirected(to);
  }
  AddSortedLink(links->second, target, from);
}

void LongTermMemory::RecordLoopClosure(const LoopClosureRecord& record) { Enqueue(record); }
void LongTermMemory::RecordImage(const MapImage& image) { Enqueue(image); }
void LongTermMemory::RecordForeignPlace(const ForeignPlace& place) { Enqueue(place); }

void LongTermMemory::StoreAppearance(LocationId id, std::vector<uint32_t> entries) {
  Enqueue(AppearanceOp{id, std::move(entries)});
}

void LongTermMemory::StoreAppearanceVocabulary(int first_entry, std::vector<WordId> words,
                                               std::vector<unsigned char> rows) {
  Enqueue(VocabularyOp{first_entry, std::move(words), std::move(rows)});
}

void LongTermMemory::WriteInfo(const std::string& key, const std::string& value) {
  Enqueue(InfoOp{key, value});
}

WordId LongTermMemory::Renamed(WordId word) const {
  const auto renamed = pending_renames_.find(word);
  return renamed == pending_renames_.end() ? word : renamed->second.second;
}

LocationId LongTermMemory::Redirected(LocationId id) const {
  const auto redirected = pending_redirects_.find(id);
  return redirected == pending_redirects_.end() ? id : redirected->second.second;
}

void LongTermMemory::Rewrite(Location& location) const {
  for (WordId& word : location.signature.words) word = Renamed(word);
  const auto links = pending_links_.find(location.id);
  if (links != pending_links_.end()) {
    for (const auto& [sequence, link] : links->second) {
      (link.loop_closure ? location.loop_closures : location.neighbours).insert(link.to);
    }
  }
  for (auto* set : {&location.neighbours, &location.loop_closures}) {
    std::set<LocationId> rewritten;
    for (LocationId link : *set) rewritten.insert(Redirected(link));
    rewritten.erase(location.id);
    *set = std::move(rewritten);
  }
}

std::optional<Location> LongTermMemory::ReadLocked(LocationId id) {
  // Called with mutex_ held. The writer may commit during the read, but it forgets a committed
  // write only under mutex_, so the overlay still holds it and applying it twice is harmless.
  std::optional<Location> location;
  const auto pending = pending_locations_.find(id);
  if (pending != pending_locations_.end()) {
    location = pending->second.second;
  } else {
    const Stopwatch read;
    location = reader_.ReadLocation(id);
    if (location && reader_.on_server()) read_words_ = reader_.ReadSignatureDescriptors(id);
    file_read_ms_ += read.ElapsedMs();
  }
  if (location) Rewrite(*location);
  return location;
}

std::optional<Location> LongTermMemory::Peek(LocationId id) {
  if (!Contains(id)) return std::nullopt;
  std::lock_guard<std::mutex> lock(mutex_);
  return ReadLocked(id);
}

std::optional<Location> LongTermMemory::Retrieve(LocationId id) {
  if (!Contains(id)) return std::nullopt;
  std::lock_guard<std::mutex> lock(mutex_);
  ThrowIfFailedLocked();
  return TakeOut(id, ReadLocked(id));
}

std::optional<Location> LongTermMemory::Retrieve(LocationId id, const PrefetchedRows& rows) {
  if (!Contains(id)) return std::nullopt;
  std::lock_guard<std::mutex> lock(mutex_);
  ThrowIfFailedLocked();
  std::optional<Location> location = ReplayLocked(id, rows);
  return TakeOut(id, location ? std::move(location) : ReadLocked(id));
}

std::optional<Location> LongTermMemory::TakeOut(LocationId id, std::optional<Location> location) {
  if (!location) throw DatabaseError(path_, "location " + std::to_string(id) + " is missing");
  ids_.erase(id);
  links_.erase(id);
  return location;
}

std::optional<Location> LongTermMemory::ReplayLocked(LocationId id,
                                                     const PrefetchedRows& rows) const {
  // A queued store holds the location as it is now; in direct mode (closing) writes are not
  // committed until the next checkpoint, so the committed ones do not say what changed.
  if (direct_ || !rows.location || rows.location->id != id || pending_locations_.count(id) > 0) {
    return std::nullopt;
  }
  std::optional<Location> location = rows.location;
  if (!committed_writes_.ReplaySince(rows.committed, *location)) return std::nullopt;
  Rewrite(*location);  // the writes still queued
  return location;
}

bool LongTermMemory::Current(const PrefetchedRows& rows) const {
  std::lock_guard<std::mutex> lock(mutex_);
  return rows.committed >= committed_writes_.floor() && rows.committed >= recent_words_floor_;
}

std::optional<std::vector<unsigned char>> LongTermMemory::LoadWord(WordId id,
                                                                   const PrefetchedRows* rows) {
  std::lock_guard<std::mutex> lock(mutex_);
  const auto pending = pending_words_.find(id);
  if (pending != pending_words_.end()) return pending->second.second;
  if (pending_renames_.count(id)) return std::nullopt;
  if (const auto* recent = recent_words_.Find(id)) return recent->second;
  if (const auto read = read_words_.find(id); read != read_words_.end()) return read->second;
  if (rows != nullptr) {
    const auto word = rows->words.find(id);
    if (word != rows->words.end()) return word->second;
  }
  const Stopwatch read;
  auto word = reader_.ReadWord(id);
  file_read_ms_ += read.ElapsedMs();
  return word;
}

const std::vector<LocationId>& LongTermMemory::LinksOf(LocationId id) const {
  static const std::vector<LocationId> kNone;
  const auto links = links_.find(id);
  return links == links_.end() ? kNone : links->second;
}

void LongTermMemory::Checkpoint(CheckpointData checkpoint) {
  if (direct_) return ApplyDirectly(checkpoint);
  {
    std::unique_lock<std::mutex> lock(mutex_);
    ThrowIfFailedLocked();
    // While the server is away, checkpoints queue (Enqueue bounds them): the first committed
    // after it returns is the robot's latest.
    WaitForWriterLocked(
        lock, [this] { return committed_sequence_ >= last_checkpoint_sequence_ || server_lost_; });
  }
  Enqueue(std::move(checkpoint));
}

bool LongTermMemory::CheckpointInFlight() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return committed_sequence_ < last_checkpoint_sequence_;
}

void LongTermMemory::Flush() {
  if (read_only_) return;
  if (direct_) {
    ThrowIfFailedLocked();
    if (last_checkpoint_sequence_ == 0 && direct_open_) {
      reader_.Commit();
      direct_open_ = false;
    }
    return;
  }
  std::unique_lock<std::mutex> lock(mutex_);
  WaitForWriterLocked(lock, [this] { return committed_sequence_ >= CommittableSequenceLocked(); });
}

void LongTermMemory::WriteDirectly() {
  if (read_only_ || direct_) return;
  Flush();  // everything up to the last checkpoint; what follows it stays queued
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stopping_ = true;
  }
  wake_writer_.notify_one();
  writer_.join();  // from here on this is the only thread: no lock needed
  if (max_page_count_ > 0) reader_.LimitPages(max_page_count_);
  direct_ = true;
  for (const Queued& queued : queue_) ApplyDirectly(queued.operation);
  queue_.clear();
  pending_bytes_ = 0;
  // reader_ now sees every write: the overlay has nothing left to add.
  pending_locations_.clear();
  pending_words_.clear();
  pending_renames_.clear();
  pending_redirects_.clear();
  pending_links_.clear();
}

void LongTermMemory::ApplyDirectly(const Operation& operation) {
  ThrowIfFailedLocked();
  try {
    if (!direct_open_) {
      reader_.Begin();
      direct_open_ = true;
    }
    Apply(reader_, operation);
    if (std::holds_alternative<CheckpointData>(operation)) {
      reader_.Commit();
      direct_open_ = false;
    }
  } catch (const std::exception& error) {
    writer_failure_ = WriteFailure(path_, error);
    throw DatabaseError(path_, writer_failure_);
  }
}

void LongTermMemory::CheckWriter() {
  std::lock_guard<std::mutex> lock(mutex_);
  ThrowIfFailedLocked();
}

void LongTermMemory::SetWriterHeld(bool held) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    held_ = held;
  }
  wake_writer_.notify_one();
}

double LongTermMemory::TakeWriterWaitMs() {
  std::lock_guard<std::mutex> lock(mutex_);
  return std::exchange(writer_wait_ms_, 0.0);
}

double LongTermMemory::TakeFileReadMs() {
  std::lock_guard<std::mutex> lock(mutex_);
  return std::exchange(file_read_ms_, 0.0);
}

long long LongTermMemory::committed_sequence() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return committed_sequence_;
}

size_t LongTermMemory::pending_bytes() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return pending_bytes_;
}

}  // namespace memloop
