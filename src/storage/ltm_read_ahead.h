// LTM rows read ahead of retrieval (memloop, issue 9): a thread of its own reads a location's rows
// and its words' descriptors from the map file and hands them to the detector's thread, which
// then does not read the file itself. A row that is not in the OS's cache takes the disk's time
// to read (50-150 ms seen in the 50,000-image runs, against ~1.6 ms cached); under T_time the
// detector waits for a location's rows only as long as the iteration allows, and retrieves it at
// a later iteration otherwise. Rows read here may be older than the map: LongTermMemory brings
// them up to date with the writes committed since the read began (or reads again when it cannot),
// so what a retrieval gives never depends on when this thread read.
// An earlier version only read the rows to warm the OS's cache; the detector read them again, and
// once, 4,000 images after the warming read, that second read waited 56 ms for the disk.
#pragma once

#include <condition_variable>
#include <deque>
#include <mutex>
#include <optional>
#include <set>
#include <thread>
#include <vector>

#include "detector/location.h"
#include "storage/long_term_memory.h"
#include "storage/oldest_first_cache.h"

namespace memloop {

class LtmReadAhead {
 public:
  // Reads the map of `ltm` through a read-only connection of its own, opened at the first
  // request (the map must exist by then). Requests that cannot be read (no such location, a
  // damaged row) count as read, without a location: the detector's own read reports the problem.
  // Rows read and not asked for yet are kept up to `max_kept_bytes`, oldest dropped first.
  explicit LtmReadAhead(const LongTermMemory& ltm, size_t max_kept_bytes = kMaxKeptBytes);
  ~LtmReadAhead();
  LtmReadAhead(const LtmReadAhead&) = delete;
  LtmReadAhead& operator=(const LtmReadAhead&) = delete;

  // Queues `ids` to read, in this order, after those already queued. Ids queued or read already
  // keep their place. At most kMaxQueued wait: the oldest requests are dropped first.
  void Request(const std::vector<LocationId>& ids);
  // Requests `id` if needed, then waits at most `timeout_ms` (infinity: until read) for its rows,
  // for LongTermMemory::Retrieve(id, rows); nullopt when they were not read in time. Rows handed
  // over are forgotten, so that the id is read again when next requested.
  std::optional<PrefetchedRows> WaitRead(LocationId id, double timeout_ms);
  // For tests: while held, nothing is read and WaitRead answers nullopt at once, as when the disk
  // does not answer within the iteration.
  void SetHeld(bool held);
  long long rows_read() const;  // locations read since construction
  size_t queued() const;
  size_t kept_bytes() const;  // of rows read and not handed over yet

  static constexpr size_t kMaxQueued = 256;
  // ~65 KB a location of 200 SURF words: ~250 locations, of which retrieval takes at most 2 an
  // iteration (memory.max_retrieved) and requests the LTM part of a neighbourhood.
  static constexpr size_t kMaxKeptBytes = size_t{16} << 20;

 private:
  void Loop();

  const LongTermMemory& ltm_;
  mutable std::mutex mutex_;
  std::condition_variable wake_reader_;
  std::condition_variable rows_read_signal_;
  std::deque<LocationId> queue_;
  std::set<LocationId> queued_;
  // Being read: a request for it now would read it again once it is handed over, with rows of a
  // location then back in WM, which would only be found stale when it next leaves.
  LocationId reading_ = kNoLocation;
  OldestFirstCache<LocationId, PrefetchedRows> read_;  // read, not handed over yet
  long long rows_read_ = 0;
  bool held_ = false;
  bool stopping_ = false;
  std::thread reader_;  // started at the first request
};

}  // namespace memloop
