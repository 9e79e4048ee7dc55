// The Long-Term Memory (paper III): locations transferred out of WM, and the words only they
// refer to, on disk. Writes are asynchronous (paper III-F: "done asynchronously using a background
// thread"): they are queued, and a writer thread commits them in batched transactions. Until a
// write is committed, reads are answered from the queued copy, so the detector never waits for the
// disk except in Flush() and when retrieving a location that must be read from the file.
// All methods are called from the detector's thread; the writer thread is internal.
#pragma once

#include <condition_variable>
#include <deque>
#include <map>
#include <mutex>
#include <optional>
#include <set>
#include <string>
#include <thread>
#include <variant>
#include <vector>

#include "ltm_database.h"

namespace memloop {

class LongTermMemory {
 public:
  // Creates a new map at `path` (see LtmDatabase for what is refused).
  explicit LongTermMemory(const std::string& path);
  // Commits everything queued, then stops the writer.
  ~LongTermMemory();
  LongTermMemory(const LongTermMemory&) = delete;
  LongTermMemory& operator=(const LongTermMemory&) = delete;

  // Transfer (III-F): the location is in LTM from now on.
  void Store(const Location& location);
  // A word that left the dictionary while LTM locations refer to it: its descriptor row.
  void StoreWord(WordId id, const cv::Mat& descriptor);
  // Retrieval (III-E): the location goes back to WM (its rows stay until it is stored again).
  std::optional<Location> Retrieve(LocationId id);
  // The bytes of the word's descriptor row; nullopt when LTM does not hold it.
  std::optional<std::vector<unsigned char>> LoadWord(WordId id);
  // Links of a location in LTM, sorted; empty when it is not in LTM.
  std::vector<LocationId> LinksOf(LocationId id);
  bool Contains(LocationId id) const { return ids_.count(id) > 0; }
  size_t size() const { return ids_.size(); }

  void ReplaceWord(WordId old_id, WordId new_id);
  void RedirectLocation(LocationId absorbed, LocationId survivor);
  void RecordLoopClosure(const LoopClosureRecord& record);
  void WriteInfo(const std::string& key, const std::string& value);

  // Blocks until every queued write is committed. Rethrows a writer failure.
  void Flush();
  const std::string& path() const { return path_; }

 private:
  struct StoreLocation {
    Location location;
  };
  struct StoreWordOp {
    WordId id;
    std::vector<unsigned char> descriptor;
  };
  struct ReplaceWordOp {
    WordId old_id;
    WordId new_id;
  };
  struct RedirectOp {
    LocationId absorbed;
    LocationId survivor;
  };
  struct InfoOp {
    std::string key;
    std::string value;
  };
  using Operation = std::variant<StoreLocation, StoreWordOp, ReplaceWordOp, RedirectOp,
                                 LoopClosureRecord, InfoOp>;
  struct Queued {
    long long sequence;
    Operation operation;
  };

  void Enqueue(Operation operation);
  void WriterLoop();
  void Apply(LtmDatabase& database, const Operation& operation);
  void Forget(long long committed);
  void RethrowWriterFailure();
  std::optional<Location> ReadLocked(LocationId id, bool links_only);
  // Applies pending renames and redirections to a location read from the queue or the file.
  void Rewrite(Location& location) const;

  std::string path_;
  LtmDatabase reader_;
  std::set<LocationId> ids_;  // locations now in LTM

  mutable std::mutex mutex_;
  std::condition_variable wake_writer_;
  std::condition_variable committed_;
  std::deque<Queued> queue_;
  long long next_sequence_ = 1;
  long long committed_sequence_ = 0;
  // Queued, not yet committed: what reads must see. Values: (sequence of the write, data).
  std::map<LocationId, std::pair<long long, Location>> pending_locations_;
  std::map<WordId, std::pair<long long, std::vector<unsigned char>>> pending_words_;
  std::map<WordId, std::pair<long long, WordId>> pending_renames_;
  std::map<LocationId, std::pair<long long, LocationId>> pending_redirects_;
  bool stopping_ = false;
  std::string writer_failure_;
  std::thread writer_;
};

}  // namespace memloop
