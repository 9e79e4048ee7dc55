// Writes that change an LTM location's rows (its store, word renames, redirections, links), kept
// for a while after the writer commits them (memloop, issue 9). Rows another thread read from the
// map file before such a commit (LtmReadAhead) are brought up to date by replaying these writes
// on them, instead of being read again on the detector's thread: a row the OS no longer holds in
// its cache takes the disk's time (56 ms seen in a 50,000-image run, against a ~1.6 ms median).
#pragma once

#include <cstddef>
#include <deque>

#include "detector/location.h"

namespace memloop {

class CommittedWrites {
 public:
  enum class Kind {
    kStore,            // `from` was stored (its rows replaced)
    kRenameWord,       // every reference to word `from` became `to`
    kRedirect,         // location `from` was absorbed by `to`: links to it go to `to`
    kNeighbourLink,    // `from` gained a neighbour link to `to`
    kLoopClosureLink,  // `from` gained a loop-closure link to `to`
  };

  // Keeps the last `capacity` writes.
  explicit CommittedWrites(size_t capacity) : capacity_(capacity) {}

  // A write committed with this sequence number (increasing from call to call).
  void Add(long long sequence, Kind kind, int from, int to);
  // Replays on `location`, read from the file when it held every write up to sequence `since`,
  // the writes committed after `since`, in order (one the read saw already changes nothing: each
  // write is idempotent, and neither a renamed word nor an absorbed location comes back).
  // False, leaving `location` unspecified, when it cannot: the location was stored again after
  // `since` (the read has an older copy), or writes after `since` are no longer kept.
  bool ReplaySince(long long since, Location& location) const;
  size_t size() const { return writes_.size(); }
  // Every write committed after this sequence is kept.
  long long floor() const { return floor_; }

 private:
  struct Write {
    long long sequence;
    Kind kind;
    int from;
    int to;
  };

  size_t capacity_;
  std::deque<Write> writes_;  // by sequence
  long long floor_ = 0;       // every write committed after it is in writes_
};

}  // namespace memloop
