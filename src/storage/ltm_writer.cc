// The Long-Term Memory's writer thread (long_term_memory.h): it commits the queued writes in
// batched transactions, whole checkpoints at a time, and the overlay forgets what it committed.
#include <unistd.h>

#include <algorithm>

#include "storage/long_term_memory.h"
#include "util/thread_name.h"
#include "util/thread_priority.h"

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

void LongTermMemory::Apply(LtmDatabase& database, const Operation& operation) {
  if (const auto* store = std::get_if<StoreLocation>(&operation)) {
    database.WriteLocation(store->location);
  } else if (const auto* word = std::get_if<StoreWordOp>(&operation)) {
    database.WriteWord(word->id, word->descriptor);
  } else if (const auto* rename = std::get_if<ReplaceWordOp>(&operation)) {
    database.ReplaceWord(rename->old_id, rename->new_id);
  } else if (const auto* redirect = std::get_if<RedirectOp>(&operation)) {
    database.RedirectLocation(redirect->absorbed, redirect->survivor);
  } else if (const auto* link = std::get_if<AddLinkOp>(&operation)) {
    database.WriteLink(link->from, link->to, link->loop_closure);
  } else if (const auto* record = std::get_if<LoopClosureRecord>(&operation)) {
    database.WriteLoopClosure(*record);
  } else if (const auto* image = std::get_if<MapImage>(&operation)) {
    database.WriteImage(*image);
  } else if (const auto* place = std::get_if<ForeignPlace>(&operation)) {
    database.WriteForeignPlace(*place);
  } else if (const auto* info = std::get_if<InfoOp>(&operation)) {
    database.WriteInfo(info->key, info->value);
  } else if (const auto* checkpoint = std::get_if<CheckpointData>(&operation)) {
    database.WriteCheckpoint(*checkpoint);
  } else if (const auto* appearance = std::get_if<AppearanceOp>(&operation)) {
    database.WriteAppearance(appearance->id, appearance->entries);
  } else if (const auto* vocabulary = std::get_if<VocabularyOp>(&operation)) {
    database.WriteAppearanceVocabulary(vocabulary->first_entry, vocabulary->words,
                                       vocabulary->rows);
  }
}

void LongTermMemory::Forget(const std::deque<Queued>& batch, size_t bytes) {
  using Kind = CommittedWrites::Kind;
  std::lock_guard<std::mutex> lock(mutex_);
  for (const Queued& queued : batch) {
    const Operation& operation = queued.operation;
    if (const auto* store = std::get_if<StoreLocation>(&operation)) {
      committed_writes_.Add(queued.sequence, Kind::kStore, store->location.id, 0);
    } else if (const auto* word = std::get_if<StoreWordOp>(&operation)) {
      if (recent_words_.Contains(word->id)) continue;  // the same bytes
      recent_words_.Add(
          word->id, {queued.sequence, word->descriptor}, word->descriptor.size(),
          [this](WordId, const auto& dropped) { recent_words_floor_ = dropped.first; });
    } else if (const auto* rename = std::get_if<ReplaceWordOp>(&operation)) {
      recent_words_.Erase(rename->old_id);  // the file no longer has it
      committed_writes_.Add(queued.sequence, Kind::kRenameWord, rename->old_id, rename->new_id);
    } else if (const auto* redirect = std::get_if<RedirectOp>(&operation)) {
      committed_writes_.Add(queued.sequence, Kind::kRedirect, redirect->absorbed,
                            redirect->survivor);
    } else if (const auto* link = std::get_if<AddLinkOp>(&operation)) {
      committed_writes_.Add(queued.sequence,
                            link->loop_closure ? Kind::kLoopClosureLink : Kind::kNeighbourLink,
                            link->from, link->to);
    }
  }
  const long long committed = batch.back().sequence;
  committed_sequence_ = committed;
  pending_bytes_ -= bytes;
  EraseCommitted(pending_locations_, committed);
  EraseCommitted(pending_words_, committed);
  EraseCommitted(pending_renames_, committed);
  EraseCommitted(pending_redirects_, committed);
  for (auto entry = pending_links_.begin(); entry != pending_links_.end();) {
    auto& links = entry->second;
    links.erase(std::remove_if(links.begin(), links.end(),
                               [&](const auto& link) { return link.first <= committed; }),
                links.end());
    entry = links.empty() ? pending_links_.erase(entry) : std::next(entry);
  }
}

void LongTermMemory::CommitBatch(LtmDatabase& database, const std::deque<Queued>& batch) {
  // The batch's mark: this process and the batch's last write.
  const std::string mark = std::to_string(getpid()) + "/" +
                           std::to_string(reinterpret_cast<uintptr_t>(this)) + "/" +
                           std::to_string(batch.back().sequence);
  for (;;) {
    try {
      database.Begin();
      for (const Queued& queued : batch) Apply(database, queued.operation);
      if (database.on_server()) database.WriteInfo("writer.batch", mark);
      database.Commit();
      return;
    } catch (const ServerConnectionLost& lost) {
      {
        std::lock_guard<std::mutex> lock(mutex_);
        server_lost_ = true;
        notices_.push_back(std::string(lost.what()) +
                           ": waiting for the server; images go on, "
                           "their writes queued");
      }
      committed_.notify_all();  // a checkpoint waiting for the previous one goes on
      const double waited = database.Reconnect();
      {
        std::lock_guard<std::mutex> lock(mutex_);
        server_lost_ = false;
        char seconds[32];
        std::snprintf(seconds, sizeof(seconds), "%.1f", waited);
        notices_.push_back(WithoutPassword(path_) + ": reconnected to the server after " + seconds +
                           " s; committing the " + std::to_string(queue_.size() + batch.size()) +
                           " writes queued");
      }
      if (database.ReadInfo("writer.batch") == mark) return;  // the commit had gone through
    }
  }
}

std::vector<std::string> LongTermMemory::TakeNotices() {
  std::lock_guard<std::mutex> lock(mutex_);
  return std::exchange(notices_, {});
}

void LongTermMemory::WriterLoop(LtmOptions options) {
  NameThisThread("writer");
  StepBelowRealTimePriority();  // behind the per-image threads (thread_priority.h)
  try {
    LtmDatabase database(path_, LtmDatabase::Mode::kAttach);  // reader_ checked the file
    if (options.max_page_count > 0) database.LimitPages(options.max_page_count);
    for (;;) {
      std::deque<Queued> batch;
      {
        std::unique_lock<std::mutex> lock(mutex_);
        wake_writer_.wait(lock, [this] {
          return stopping_ || (CommittableCountLocked() > 0 && (!held_ || waiting_ > 0));
        });
        const size_t count = CommittableCountLocked();
        if (count == 0 && stopping_) return;  // writes after the last checkpoint are dropped
        batch.insert(batch.end(), std::make_move_iterator(queue_.begin()),
                     std::make_move_iterator(queue_.begin() + count));
        queue_.erase(queue_.begin(), queue_.begin() + count);
      }
      size_t bytes = 0;
      for (const Queued& queued : batch) bytes += queued.bytes;
      CommitBatch(database, batch);
      Forget(batch, bytes);
      committed_.notify_all();
    }
  } catch (const std::exception& error) {
    std::lock_guard<std::mutex> lock(mutex_);
    writer_failure_ = WriteFailure(path_, error);
    committed_.notify_all();
  }
}

}  // namespace memloop
