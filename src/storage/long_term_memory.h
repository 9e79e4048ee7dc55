// The Long-Term Memory (paper III): locations transferred out of WM, and the words only they
// refer to, on disk. Writes are asynchronous (paper III-F: "done asynchronously using a background
// thread"): they are queued, and a writer thread commits them in batched transactions. Until a
// write is committed, reads are answered through an overlay of the queued writes, so a read gives
// the same answer however far the writer is behind (the detector's determinism rests on it).
// All methods are called from the detector's thread; the writer thread is internal.
#pragma once

#include <condition_variable>
#include <deque>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <set>
#include <string>
#include <thread>
#include <unordered_map>
#include <variant>
#include <vector>

#include "storage/committed_writes.h"
#include "storage/ltm_database.h"
#include "storage/map_writer_lock.h"
#include "storage/oldest_first_cache.h"

namespace memloop {

// A location's rows as another thread read them from the map file ahead of its retrieval
// (LtmReadAhead), with the words of its signature the file held.
struct PrefetchedRows {
  long long committed = 0;           // LongTermMemory::committed_sequence() before the read
  std::optional<Location> location;  // nullopt: the file had no such location
  std::unordered_map<WordId, std::vector<unsigned char>> words;
};

struct LtmOptions {
  // Back-pressure: when queued writes hold more than this, the detector waits for the writer, so
  // RAM stays bounded whatever the disk's speed.
  size_t max_pending_bytes = size_t{64} << 20;
  // SQLite max_page_count of the writer's connection (0 = SQLite's default). Tests use a small
  // value to meet a full disk.
  long long max_page_count = 0;
  // Committed writes kept to bring prefetched rows up to date (committed_writes.h): mostly the
  // renames of retrieved locations' re-matched words, at most a few hundred an iteration; 24
  // bytes each (3 MB). Rows read before the oldest are read again.
  size_t max_replayed_writes = size_t{1} << 17;
  // Descriptors of the words stored last, kept after their commit up to this many bytes (32,768
  // SURF words of 64 floats): retrieval asks for a location's words that left the dictionary,
  // often soon after they left, and a read of the file may wait for the disk.
  size_t recent_word_bytes = size_t{8} << 20;
};

class LongTermMemory {
 public:
  // Opens the map at `path` (see LtmDatabase for what is refused in each mode). An opened map's
  // locations are all in LTM until Exclude() says otherwise. Mode::kRead (localization): nothing
  // is ever written and there is no writer thread; writes are kept in the overlay only, so reads
  // answer as if they had been written (the overlay holds at most one copy of each location and
  // word of the map), and Checkpoint and Flush do nothing.
  LongTermMemory(const std::string& path, LtmDatabase::Mode mode = LtmDatabase::Mode::kCreate,
                 const LtmOptions& options = {});
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
  // The same, from `rows` read earlier by another thread, brought up to date with the writes
  // committed since (CommittedWrites) and those still queued; read from the file as above when
  // that cannot be done (the location was stored again since, or the writes since are not all
  // kept). The same answer either way.
  std::optional<Location> Retrieve(LocationId id, const PrefetchedRows& rows);
  // The location as LTM holds it, without taking it out; nullopt when it is not in LTM.
  std::optional<Location> Peek(LocationId id);
  // True when rows read ahead can be used without reading the file: every write that changed
  // rows since their read, and every word stored since, are still kept. Older rows are better
  // read again on the read-ahead thread, where a wait for the disk does not stop the detector.
  bool Current(const PrefetchedRows& rows) const;
  // The bytes of the word's descriptor row; nullopt when LTM does not hold it.
  // Answered from memory when it can be (a descriptor never changes): queued, stored lately
  // (LtmOptions::recent_word_bytes) or, with `rows` (of a location Retrieve gave, asked for words
  // of its signature as retrieved), held by the file when they were read.
  std::optional<std::vector<unsigned char>> LoadWord(WordId id,
                                                     const PrefetchedRows* rows = nullptr);
  // Links of a location in LTM, sorted; empty when it is not in LTM. From LTM's link graph, held
  // in memory (issue 9): retrieval walks it at every iteration, and reading it from the file
  // waited 400 ms for the disk once the OS had dropped the file's pages from its cache. The same
  // answers as the file with the queued writes (CheckConsistency compares them).
  const std::vector<LocationId>& LinksOf(LocationId id) const;
  bool Contains(LocationId id) const { return ids_.count(id) > 0; }
  // Resuming: `id` is in memory (rows it has in the file are an older copy).
  void Exclude(LocationId id) {
    ids_.erase(id);
    links_.erase(id);
  }
  const std::set<LocationId>& ids() const { return ids_; }
  size_t size() const { return ids_.size(); }

  // Every reference to the word `old_id` becomes `new_id` (re-matched on retrieval, III-E).
  void ReplaceWord(WordId old_id, WordId new_id);
  // `absorbed` was merged into `survivor`: links to it now point to the survivor. `linked`: the
  // locations linked to `absorbed` when it was in memory (its Links()); LTM knows its own.
  void RedirectLocation(LocationId absorbed, LocationId survivor,
                        const std::vector<LocationId>& linked);
  // The LTM location `from` gains a link to `to` (a loop closure made in memory reached it).
  void AddLink(LocationId from, LocationId to, bool loop_closure);
  void RecordLoopClosure(const LoopClosureRecord& record);
  // A place of another robot imported into the map (fleet_places.h): where it came from.
  void RecordForeignPlace(const ForeignPlace& place);
  // An image Process() was given: its name, time stamp and session (ltm_images.cc).
  void RecordImage(const MapImage& image);
  // Retrieval by appearance: a new location's description, and new vocabulary entries from
  // `first_entry` on (rows: their descriptors, one after the other). Kept in the file for resuming.
  void StoreAppearance(LocationId id, std::vector<uint32_t> entries);
  void StoreAppearanceVocabulary(int first_entry, std::vector<WordId> words,
                                 std::vector<unsigned char> rows);
  void WriteInfo(const std::string& key, const std::string& value);

  // A resume checkpoint (checkpoint.h). From the first one on, the writer commits only whole
  // checkpoints: a transaction ends at a checkpoint, and writes queued after the last one wait
  // for the next (they are dropped if the LTM is destroyed first). At most one checkpoint is
  // uncommitted: this waits for the previous one, which bounds what a crash can lose.
  void Checkpoint(CheckpointData checkpoint);
  // True while the last checkpoint is not committed yet (Checkpoint would wait for it).
  bool CheckpointInFlight() const;
  // Blocks until every queued write is committed (up to the last checkpoint once checkpoints are
  // written). Rethrows a writer failure.
  void Flush();
  // Throws DatabaseError when the writer has failed (a full disk, a removed file): the map on
  // disk no longer follows memory, so the detector must stop.
  void CheckWriter();
  // A server's map: what the writer has to say since the last call (it lost the server, it
  // reconnected and caught up), one line each.
  std::vector<std::string> TakeNotices();
  // Closing (Detector::Close): the writer thread stops, and from now on the caller applies each
  // write at once, in one transaction with those still queued, which the next Checkpoint
  // commits (without one they are dropped at destruction, as before). Reads see these writes
  // through the same connection. Queued, a close's store of every WM word held two copies of
  // them (queue and overlay) until its checkpoint: +218 MB at 400,000 words (issue 9).
  void WriteDirectly();
  // For tests: while held, the writer commits nothing unless someone waits for it (a full queue,
  // Flush, destruction). Reads must give the same answers either way.
  void SetWriterHeld(bool held);
  // Milliseconds callers waited for the writer (the queue full, or a checkpoint waiting for the
  // previous one) since the last call: part of the caller's time that the map's disk sets.
  double TakeWriterWaitMs();
  // Milliseconds callers spent reading the map file (Retrieve, Peek, LoadWord: rows not in the
  // overlay) since the last call: a read the OS must fetch from the disk takes the disk's time.
  double TakeFileReadMs();
  size_t pending_bytes() const;
  // The sequence number of the last write committed: a read of the file that begins after this
  // call sees at least the writes up to it.
  long long committed_sequence() const;
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
  struct AddLinkOp {
    LocationId from;
    LocationId to;
    bool loop_closure;
  };
  struct InfoOp {
    std::string key;
    std::string value;
  };
  struct AppearanceOp {
    LocationId id;
    std::vector<uint32_t> entries;
  };
  struct VocabularyOp {
    int first_entry;
    std::vector<WordId> words;
    std::vector<unsigned char> rows;
  };
  using Operation = std::variant<StoreLocation, StoreWordOp, ReplaceWordOp, RedirectOp, AddLinkOp,
                                 LoopClosureRecord, InfoOp, CheckpointData, AppearanceOp,
                                 VocabularyOp, MapImage, ForeignPlace>;
  struct Queued {
    long long sequence;
    size_t bytes;
    Operation operation;
  };

  void Enqueue(Operation operation);
  void Overlay(long long sequence, const Operation& operation);
  void WriterLoop(LtmOptions options);
  // Commits `batch` (Begin ... Commit); on a server whose connection breaks, reconnects and
  // commits it again, unless its commit had gone through (its mark in the info rows says so).
  void CommitBatch(LtmDatabase& database, const std::deque<Queued>& batch);
  void Apply(LtmDatabase& database, const Operation& operation);
  void ApplyDirectly(const Operation& operation);
  // The writer committed `batch`: the overlay forgets it, CommittedWrites and recent_words_ keep
  // what they need.
  void Forget(const std::deque<Queued>& batch, size_t bytes);
  // `rows` brought up to date (Retrieve), or nullopt when that cannot be done.
  std::optional<Location> ReplayLocked(LocationId id, const PrefetchedRows& rows) const;
  // Takes the location read for Retrieve out of LTM; throws when it could not be read.
  std::optional<Location> TakeOut(LocationId id, std::optional<Location> location);
  void ThrowIfFailedLocked() const;
  // The error is reported under the map's name: its message without it if it has it already.
  static std::string WriteFailure(const std::string& path, const std::exception& error);
  // The last sequence the writer may commit now, and how many queued writes that is.
  long long CommittableSequenceLocked() const;
  size_t CommittableCountLocked() const;
  // Waits (mutex_ held by `lock`) until `done` or a writer failure, which it rethrows.
  template <typename Predicate>
  void WaitForWriterLocked(std::unique_lock<std::mutex>& lock, Predicate done);
  std::optional<Location> ReadLocked(LocationId id);
  // Applies queued renames, redirections and links to a location read from the queue or file.
  void Rewrite(Location& location) const;
  WordId Renamed(WordId word) const;
  LocationId Redirected(LocationId id) const;
  // links_[id] from the links `location` is stored with, as a read would give them.
  void SetLinks(const Location& location);

  std::string path_;
  bool read_only_;
  std::unique_ptr<MapWriterLock> writer_lock_;  // held while the map is open to write
  LtmDatabase reader_;
  std::set<LocationId> ids_;  // locations now in LTM
  // Their links (LinksOf), sorted: changed by the detector's thread only, as ids_.
  std::unordered_map<LocationId, std::vector<LocationId>> links_;

  mutable std::mutex mutex_;
  std::condition_variable wake_writer_;
  std::condition_variable committed_;
  std::deque<Queued> queue_;
  size_t max_pending_bytes_;
  long long max_page_count_;
  bool direct_ = false;       // WriteDirectly(): no writer, reader_ writes
  bool direct_open_ = false;  // a transaction of reader_ is open
  size_t pending_bytes_ = 0;
  int waiting_ = 0;            // threads waiting for the writer: a held writer then goes on
  double writer_wait_ms_ = 0;  // TakeWriterWaitMs
  double file_read_ms_ = 0;    // TakeFileReadMs
  bool held_ = false;
  long long next_sequence_ = 1;
  long long committed_sequence_ = 0;
  long long last_checkpoint_sequence_ = 0;  // 0: no checkpoint yet, every write is committable
  // The overlay: queued, not yet committed. Values: (sequence of the write, data). Renames and
  // redirections are kept resolved to their end (A->S then S->S2 gives A->S2), so one look-up
  // gives what the file will say once everything is committed.
  std::map<LocationId, std::pair<long long, Location>> pending_locations_;
  std::map<WordId, std::pair<long long, std::vector<unsigned char>>> pending_words_;
  std::map<WordId, std::pair<long long, WordId>> pending_renames_;
  std::map<LocationId, std::pair<long long, LocationId>> pending_redirects_;
  std::map<LocationId, std::vector<std::pair<long long, AddLinkOp>>> pending_links_;
  CommittedWrites committed_writes_;  // guarded by mutex_
  // A server's map: the descriptors of the words of the location read last (ReadLocked), read in
  // one round trip with it, for LoadWord; a word re-matched since is dropped. Guarded by mutex_.
  std::unordered_map<WordId, std::vector<unsigned char>> read_words_;
  // Descriptors of words whose store was committed lately (LtmOptions::recent_word_bytes), with
  // the sequence of the store; guarded by mutex_.
  OldestFirstCache<WordId, std::pair<long long, std::vector<unsigned char>>> recent_words_;
  long long recent_words_floor_ = 0;  // every word stored after it is kept (or renamed since)
  bool stopping_ = false;
  std::string writer_failure_;
  // A server's map whose connection broke: the writer waits for it to come back (queued writes
  // are then committed), checkpoints do not wait for each other meanwhile, and a full queue
  // stops the run (Enqueue) instead of waiting.
  bool server_lost_ = false;
  std::vector<std::string> notices_;  // TakeNotices
  std::thread writer_;
};

}  // namespace memloop
