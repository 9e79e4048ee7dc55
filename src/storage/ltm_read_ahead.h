// LTM rows read ahead of retrieval (memloop, issue 9): a thread of its own reads a location's rows
// and its words' descriptors from the map file, so that the OS holds them when the detector's
// thread retrieves it. A row that is not in the OS's cache takes the disk's time to read (50-150
// ms seen in the 50,000-image runs, against ~1 ms cached); under T_time the detector waits for a
// location's rows only as long as the iteration allows, and retrieves it at a later iteration
// otherwise. What is read here is only looked at and dropped: the detector's own read, through
// the LTM's queued writes, is the one that counts, so results never depend on this thread.
#pragma once

#include <condition_variable>
#include <deque>
#include <mutex>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include "detector/location.h"

namespace memloop {

class LtmReadAhead {
 public:
  // Reads the map at `path` through a read-only connection of its own, opened at the first
  // request (the map must exist by then). Requests that cannot be read (no such location, a
  // damaged row) count as read: the detector's own read reports the problem.
  explicit LtmReadAhead(std::string path);
  ~LtmReadAhead();
  LtmReadAhead(const LtmReadAhead&) = delete;
  LtmReadAhead& operator=(const LtmReadAhead&) = delete;

  // Queues `ids` to read, in this order, after those already queued. Ids queued or read already
  // keep their place. At most kMaxQueued wait: the oldest requests are dropped first.
  void Request(const std::vector<LocationId>& ids);
  // Requests `id` if needed, then waits at most `timeout_ms` (infinity: until read) for its rows.
  // True when they were read; the id is then forgotten, so that it is read again when next
  // requested (it may have left WM again by then, with rows written anew).
  bool WaitRead(LocationId id, double timeout_ms);
  // For tests: while held, nothing is read and WaitRead answers false at once, as when the disk
  // does not answer within the iteration.
  void SetHeld(bool held);
  long long rows_read() const;  // locations read since construction
  size_t queued() const;

  static constexpr size_t kMaxQueued = 256;
  static constexpr size_t kMaxRemembered = 1024;  // read and not asked for yet

 private:
  void Loop();
  void MarkReadLocked(LocationId id);

  std::string path_;
  mutable std::mutex mutex_;
  std::condition_variable wake_reader_;
  std::condition_variable read_;
  std::deque<LocationId> queue_;
  std::set<LocationId> queued_;
  std::deque<LocationId> read_order_;  // oldest first, to forget beyond kMaxRemembered
  std::set<LocationId> read_ids_;
  long long rows_read_ = 0;
  bool held_ = false;
  bool stopping_ = false;
  std::thread reader_;  // started at the first request
};

}  // namespace memloop
