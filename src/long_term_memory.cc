#include "long_term_memory.h"

#include <algorithm>

#include "memloop/errors.h"

namespace memloop {
namespace {

// Erases entries of `pending` whose write is committed (sequence <= committed).
template <typename Map>
void EraseCommitted(Map& pending, long long committed) {
  for (auto entry = pending.begin(); entry != pending.end();) {
    entry = entry->second.first <= committed ? pending.erase(entry) : std::next(entry);
  }
}

}  // namespace

LongTermMemory::LongTermMemory(const std::string& path)
    : path_(path), reader_(path, LtmDatabase::Mode::kCreate) {
  writer_ = std::thread([this] { WriterLoop(); });
}

LongTermMemory::~LongTermMemory() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stopping_ = true;
  }
  wake_writer_.notify_one();
  writer_.join();
}

void LongTermMemory::Enqueue(Operation operation) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    const long long sequence = next_sequence_++;
    if (auto* store = std::get_if<StoreLocation>(&operation)) {
      pending_locations_[store->location.id] = {sequence, store->location};
    } else if (auto* word = std::get_if<StoreWordOp>(&operation)) {
      pending_words_[word->id] = {sequence, word->descriptor};
    } else if (auto* rename = std::get_if<ReplaceWordOp>(&operation)) {
      pending_words_.erase(rename->old_id);
      pending_renames_[rename->old_id] = {sequence, rename->new_id};
    } else if (auto* redirect = std::get_if<RedirectOp>(&operation)) {
      pending_locations_.erase(redirect->absorbed);
      pending_redirects_[redirect->absorbed] = {sequence, redirect->survivor};
    }
    queue_.push_back({sequence, std::move(operation)});
  }
  wake_writer_.notify_one();
}

void LongTermMemory::Store(const Location& location) {
  ids_.insert(location.id);
  Enqueue(StoreLocation{location});
}

void LongTermMemory::StoreWord(WordId id, const cv::Mat& descriptor) {
  const cv::Mat row = descriptor.isContinuous() ? descriptor : descriptor.clone();
  const unsigned char* bytes = row.ptr<unsigned char>();
  Enqueue(StoreWordOp{id, std::vector<unsigned char>(bytes, bytes + row.total() * row.elemSize())});
}

void LongTermMemory::ReplaceWord(WordId old_id, WordId new_id) {
  Enqueue(ReplaceWordOp{old_id, new_id});
}

void LongTermMemory::RedirectLocation(LocationId absorbed, LocationId survivor) {
  ids_.erase(absorbed);
  Enqueue(RedirectOp{absorbed, survivor});
}

void LongTermMemory::RecordLoopClosure(const LoopClosureRecord& record) { Enqueue(record); }

void LongTermMemory::WriteInfo(const std::string& key, const std::string& value) {
  Enqueue(InfoOp{key, value});
}

void LongTermMemory::Rewrite(Location& location) const {
  for (WordId& word : location.signature.words) {
    const auto renamed = pending_renames_.find(word);
    if (renamed != pending_renames_.end()) word = renamed->second.second;
  }
  for (auto* links : {&location.neighbours, &location.loop_closures}) {
    std::set<LocationId> rewritten;
    for (LocationId link : *links) {
      const auto redirected = pending_redirects_.find(link);
      rewritten.insert(redirected == pending_redirects_.end() ? link : redirected->second.second);
    }
    rewritten.erase(location.id);
    *links = std::move(rewritten);
  }
}

std::optional<Location> LongTermMemory::ReadLocked(LocationId id, bool links_only) {
  // Called with mutex_ held, from the pending copy to the file: the writer forgets a committed
  // rename or redirection only under mutex_, so none can slip between this read and Rewrite().
  std::optional<Location> location;
  const auto pending = pending_locations_.find(id);
  if (pending != pending_locations_.end()) {
    location = pending->second.second;
  } else if (links_only) {
    location.emplace();
    location->id = id;
    for (LocationId link : reader_.ReadLinks(id)) location->neighbours.insert(link);
  } else {
    location = reader_.ReadLocation(id);
  }
  if (location) Rewrite(*location);
  return location;
}

std::optional<Location> LongTermMemory::Retrieve(LocationId id) {
  if (!Contains(id)) return std::nullopt;
  RethrowWriterFailure();
  std::optional<Location> location;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    location = ReadLocked(id, /*links_only=*/false);
  }
  if (!location) throw DatabaseError(path_, "location " + std::to_string(id) + " is missing");
  ids_.erase(id);
  return location;
}

std::optional<std::vector<unsigned char>> LongTermMemory::LoadWord(WordId id) {
  std::lock_guard<std::mutex> lock(mutex_);
  const auto pending = pending_words_.find(id);
  if (pending != pending_words_.end()) return pending->second.second;
  if (pending_renames_.count(id)) return std::nullopt;
  return reader_.ReadWord(id);
}

std::vector<LocationId> LongTermMemory::LinksOf(LocationId id) {
  if (!Contains(id)) return {};
  std::lock_guard<std::mutex> lock(mutex_);
  const std::optional<Location> location = ReadLocked(id, /*links_only=*/true);
  return location ? location->Links() : std::vector<LocationId>();
}

void LongTermMemory::Flush() {
  std::unique_lock<std::mutex> lock(mutex_);
  committed_.wait(lock, [this] {
    return committed_sequence_ >= next_sequence_ - 1 || !writer_failure_.empty();
  });
  lock.unlock();
  RethrowWriterFailure();
}

void LongTermMemory::RethrowWriterFailure() {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!writer_failure_.empty()) throw DatabaseError(path_, writer_failure_);
}

void LongTermMemory::Apply(LtmDatabase& database, const Operation& operation) {
  if (const auto* store = std::get_if<StoreLocation>(&operation)) {
    database.WriteLocation(store->location);
  } else if (const auto* word = std::get_if<StoreWordOp>(&operation)) {
    database.WriteWord(word->id, word->descriptor);
  } else if (const auto* rename = std::get_if<ReplaceWordOp>(&operation)) {
    database.ReplaceWord(rename->old_id, rename->new_id);
  } else if (const auto* redirect = std::get_if<RedirectOp>(&operation)) {
    database.RedirectLocation(redirect->absorbed, redirect->survivor);
  } else if (const auto* record = std::get_if<LoopClosureRecord>(&operation)) {
    database.WriteLoopClosure(*record);
  } else if (const auto* info = std::get_if<InfoOp>(&operation)) {
    database.WriteInfo(info->key, info->value);
  }
}

void LongTermMemory::Forget(long long committed) {
  std::lock_guard<std::mutex> lock(mutex_);
  committed_sequence_ = committed;
  EraseCommitted(pending_locations_, committed);
  EraseCommitted(pending_words_, committed);
  EraseCommitted(pending_renames_, committed);
  EraseCommitted(pending_redirects_, committed);
}

void LongTermMemory::WriterLoop() {
  try {
    LtmDatabase database(path_, LtmDatabase::Mode::kOpen);
    for (;;) {
      std::deque<Queued> batch;
      {
        std::unique_lock<std::mutex> lock(mutex_);
        wake_writer_.wait(lock, [this] { return stopping_ || !queue_.empty(); });
        if (queue_.empty() && stopping_) return;
        batch.swap(queue_);
      }
      database.Begin();
      for (const Queued& queued : batch) Apply(database, queued.operation);
      database.Commit();
      Forget(batch.back().sequence);
      committed_.notify_all();
    }
  } catch (const std::exception& error) {
    std::lock_guard<std::mutex> lock(mutex_);
    writer_failure_ = std::string("writing the map failed: ") + error.what();
    committed_.notify_all();
  }
}

}  // namespace memloop
