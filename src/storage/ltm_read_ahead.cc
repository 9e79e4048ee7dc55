#include "storage/ltm_read_ahead.h"

#include <chrono>
#include <memory>

#include "storage/ltm_database.h"
#include "util/thread_name.h"

namespace memloop {
namespace {

// What the detector's retrieval reads (LongTermMemory::Retrieve, then LoadWord for the words
// that left the dictionary). Any word may be one that left: all are read. One read transaction:
// it begins after `committed` was taken, so it sees at least the writes up to it.
PrefetchedRows ReadRows(LtmDatabase& database, LocationId id, long long committed) {
  PrefetchedRows rows;
  rows.committed = committed;
  database.Begin();
  rows.location = database.ReadLocation(id);
  if (rows.location) rows.words = database.ReadSignatureDescriptors(id);
  database.Commit();
  return rows;
}

size_t BytesOf(const PrefetchedRows& rows) {
  size_t bytes = sizeof(PrefetchedRows) + (rows.location ? rows.location->ApproximateBytes() : 0);
  for (const auto& [word, descriptor] : rows.words) bytes += 48 + descriptor.size();
  return bytes;
}

}  // namespace

LtmReadAhead::LtmReadAhead(const LongTermMemory& ltm, size_t max_kept_bytes)
    : ltm_(ltm), read_(max_kept_bytes) {}

LtmReadAhead::~LtmReadAhead() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stopping_ = true;
  }
  wake_reader_.notify_one();
  if (reader_.joinable()) reader_.join();
}

void LtmReadAhead::Request(const std::vector<LocationId>& ids) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    for (LocationId id : ids) {
      if (id == reading_ || queued_.count(id) > 0 || read_.Contains(id)) continue;
      queue_.push_back(id);
      queued_.insert(id);
    }
    while (queue_.size() > kMaxQueued) {
      queued_.erase(queue_.front());
      queue_.pop_front();
    }
    if (!reader_.joinable()) reader_ = std::thread([this] { Loop(); });
  }
  wake_reader_.notify_one();
}

std::optional<PrefetchedRows> LtmReadAhead::WaitRead(LocationId id, double timeout_ms) {
  std::unique_lock<std::mutex> lock(mutex_);
  if (id != reading_ && !read_.Contains(id) && queued_.count(id) == 0) {
    queue_.push_front(id);  // needed now: before what was requested ahead
    queued_.insert(id);
    if (!reader_.joinable()) reader_ = std::thread([this] { Loop(); });
    wake_reader_.notify_one();
  }
  if (held_) return std::nullopt;
  const auto read = [this, id] { return read_.Contains(id); };
  if (timeout_ms > 1e12) {  // beyond a chrono time point's range: as long as it takes
    rows_read_signal_.wait(lock, read);
  } else if (!rows_read_signal_.wait_for(
                 lock, std::chrono::duration<double, std::milli>(timeout_ms), read)) {
    return std::nullopt;
  }
  return read_.Take(id);
}

void LtmReadAhead::SetHeld(bool held) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    held_ = held;
  }
  wake_reader_.notify_one();
}

long long LtmReadAhead::rows_read() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return rows_read_;
}

size_t LtmReadAhead::queued() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return queue_.size();
}

size_t LtmReadAhead::kept_bytes() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return read_.bytes();
}

void LtmReadAhead::Loop() {
  NameThisThread("reader");
  std::unique_ptr<LtmDatabase> database;
  bool unreadable = false;  // the map could not be opened: every request counts as read
  for (;;) {
    LocationId id = kNoLocation;
    {
      std::unique_lock<std::mutex> lock(mutex_);
      wake_reader_.wait(lock, [this] { return stopping_ || (!held_ && !queue_.empty()); });
      if (stopping_) return;
      id = queue_.front();
      queue_.pop_front();
      queued_.erase(id);
      reading_ = id;
    }
    PrefetchedRows rows;
    try {
      if (!database && !unreadable) {
        database = std::make_unique<LtmDatabase>(ltm_.path(), LtmDatabase::Mode::kPeek);
      }
      if (database) rows = ReadRows(*database, id, ltm_.committed_sequence());
    } catch (const std::exception&) {
      // Unopenable: never again. A bad row: the detector's read will say so; the connection is
      // opened anew, so that no read transaction stays open on an old state of the file.
      unreadable = unreadable || !database;
      database.reset();
      rows = PrefetchedRows();
    }
    {
      std::lock_guard<std::mutex> lock(mutex_);
      reading_ = kNoLocation;
      ++rows_read_;
      const size_t bytes = BytesOf(rows);
      read_.Add(id, std::move(rows), bytes);  // dropped ones are read again if asked for
    }
    rows_read_signal_.notify_all();
  }
}

}  // namespace memloop
