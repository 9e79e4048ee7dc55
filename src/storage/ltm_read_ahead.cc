#include "storage/ltm_read_ahead.h"

#include <chrono>
#include <memory>

#include "storage/ltm_database.h"

namespace memloop {
namespace {

// What the detector's retrieval reads (LongTermMemory::Retrieve, then LoadWord for the words
// that left the dictionary), read and dropped. Any word may be one that left: all are read.
void ReadRows(LtmDatabase& database, LocationId id) {
  const std::optional<Location> location = database.ReadLocation(id);
  if (!location) return;
  const std::set<WordId> words(location->signature.words.begin(), location->signature.words.end());
  for (WordId word : words) database.ReadWord(word);
}

}  // namespace

LtmReadAhead::LtmReadAhead(std::string path) : path_(std::move(path)) {}

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
      if (queued_.count(id) > 0 || read_ids_.count(id) > 0) continue;
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

bool LtmReadAhead::WaitRead(LocationId id, double timeout_ms) {
  std::unique_lock<std::mutex> lock(mutex_);
  if (read_ids_.count(id) == 0 && queued_.count(id) == 0) {
    queue_.push_front(id);  // needed now: before what was requested ahead
    queued_.insert(id);
    if (!reader_.joinable()) reader_ = std::thread([this] { Loop(); });
    wake_reader_.notify_one();
  }
  if (held_) return false;
  const auto read = [this, id] { return read_ids_.count(id) > 0; };
  if (timeout_ms > 1e12) {  // beyond a chrono time point's range: as long as it takes
    read_.wait(lock, read);
  } else if (!read_.wait_for(lock, std::chrono::duration<double, std::milli>(timeout_ms), read)) {
    return false;
  }
  read_ids_.erase(id);
  return true;
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

void LtmReadAhead::MarkReadLocked(LocationId id) {
  ++rows_read_;
  if (!read_ids_.insert(id).second) return;
  read_order_.push_back(id);
  while (read_order_.size() > kMaxRemembered) {
    read_ids_.erase(read_order_.front());  // at worst one read again
    read_order_.pop_front();
  }
}

void LtmReadAhead::Loop() {
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
    }
    try {
      if (!database && !unreadable) {
        database = std::make_unique<LtmDatabase>(path_, LtmDatabase::Mode::kPeek);
      }
      if (database) ReadRows(*database, id);
    } catch (const std::exception&) {
      unreadable = unreadable || !database;  // a bad row: the detector's read will say so
    }
    {
      std::lock_guard<std::mutex> lock(mutex_);
      MarkReadLocked(id);
    }
    read_.notify_all();
  }
}

}  // namespace memloop
