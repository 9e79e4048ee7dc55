// Copies the map's write-ahead log into the map file in a thread of its own (a SQLite WAL
// "checkpoint"), so that the LTM writer's commits never wait for a disk flush.
//
// SQLite's default has the connection that commits run the checkpoint inside the commit once the
// log holds 1,000 pages. With synchronous=NORMAL that checkpoint is the only step that flushes the
// disk (twice): the writer's commit then took 10-14 ms instead of its mean 0.4 ms, and at times
// hundreds of ms on a busy disk. The detector waits for that commit at its next checkpoint
// (LongTermMemory::Checkpoint), which put one 583 ms iteration in a 200-image run (issue 9). Here
// the writer only reports the log's size after each commit (sqlite3_wal_hook); a checkpoint runs
// beside it through another connection (PASSIVE: it never blocks the writer or a reader), and a
// commit is a write to the log alone.
#pragma once

#include <condition_variable>
#include <mutex>
#include <string>
#include <thread>

#include "storage/ltm_database.h"
#include "storage/sqlite_statement.h"

namespace memloop {

class WalCheckpointer {
 public:
  // Opens its own connection to the map at `path` (a memloop map another connection has opened).
  // A checkpoint starts when a commit leaves at least `frames` frames (pages) in the log.
  WalCheckpointer(const std::string& path, int frames);
  // Ends the checkpoint under way, if any, and stops (a checkpoint still due is left to SQLite,
  // which runs one when the map's last connection closes).
  ~WalCheckpointer();
  WalCheckpointer(const WalCheckpointer&) = delete;
  WalCheckpointer& operator=(const WalCheckpointer&) = delete;

  // Makes `database` report its commits here instead of checkpointing in them.
  void Watch(LtmDatabase& database);
  // A commit left `frames` frames in the log (called by the committing thread).
  void Committed(int frames);

  // For tests: while held, no checkpoint starts. WaitIdle returns once no checkpoint is due
  // or running (at once while held).
  void SetHeld(bool held);
  void WaitIdle();
  // Checkpoints done, and whether the last one copied every frame of the log.
  int checkpoints() const;
  bool last_was_complete() const;

 private:
  void Loop();

  SqliteConnection connection_;
  int frames_;
  mutable std::mutex mutex_;
  std::condition_variable wake_;
  std::condition_variable idle_;
  bool due_ = false;
  bool running_ = false;
  bool held_ = false;
  bool stopping_ = false;
  int checkpoints_ = 0;
  bool last_complete_ = false;
  std::thread thread_;
};

}  // namespace memloop
