// The Long-Term Memory's database, one per map: an SQLite file, or a robot's rows of a fleet's
// map on a PostgreSQL server (fleet_schema.h), in the same tables: locations with their signatures,
// links and images, the words they refer to that left the dictionary (with descriptors), and every
// accepted loop closure. Identified by PRAGMA application_id and versioned by user_version.
// One object per connection and thread.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

#include "detector/location.h"
#include "memloop/loop_closure_edits.h"
#include "memloop/map_info.h"
#include "storage/sql_connection.h"
#include "storage/sqlite_statement.h"

namespace memloop {

// An accepted loop closure as the map stores it (the public MapLoopClosure).
using LoopClosureRecord = MapLoopClosure;

// One resume checkpoint (checkpoint.h) as rows: the STM/WM locations and the dictionary's index
// points that changed since the previous checkpoint, and the detector's state blobs.
struct CheckpointData {
  bool full = false;  // replaces every location, index point and state entry the file holds
  std::vector<std::pair<LocationId, std::vector<unsigned char>>> locations;
  std::vector<LocationId> removed_locations;
  bool reset_index = false;  // the index was rebuilt: its old points go
  // The index points since the previous checkpoint (all of them after a rebuild): consecutive from
  // first_index_point, as word ids, and the descriptors of their words the file does not hold yet
  // (a word's descriptor never changes: it is written once).
  long long first_index_point = 0;
  std::vector<WordId> index_words;
  std::vector<std::pair<WordId, std::vector<unsigned char>>> index_descriptors;
  struct Point {  // an index point as read back, with its word's descriptor
    long long point;
    WordId word;
    std::vector<unsigned char> descriptor;
  };
  // Descriptors of words no index point names any more, deleted a few thousand per checkpoint.
  std::vector<WordId> forgotten_descriptors;
  std::vector<std::pair<std::string, std::vector<unsigned char>>> state;

  size_t bytes() const;
};

class LtmDatabase {
 public:
  static constexpr int kApplicationId = 0x4d4c4f50;  // "MLOP"
  // 1: LTM only. 2: adds the resume checkpoint (memory_locations, index_points, resume_state).
  // 3: index points as chunks of word ids (index_chunks); each word's descriptor once
  // (index_descriptors). 4: LTM's marks on the dictionary's words as bitmaps by chunks of word
  // ids (resume_state keys ltm_marks.N), only changed chunks written at each checkpoint.
  // 5: the images (name, time stamp, session) and each location's view image (location_views,
  // and at the end of a checkpoint's location). 6: the marks by chunks of 4,096 word ids
  // (resume_state keys word_marks.N). A map of format 4 or 5 is resumed and becomes format 6 with
  // its first checkpoint written.
  static constexpr int kFormatVersion = 6;
  static constexpr int kOldestResumable = 4;

  enum class Mode {
    kCreate,  // a new map: the file must be absent or empty
    kOpen,    // an existing memloop map, read and written
    kRead,    // an existing memloop map, read only (its file is never written; closed cleanly, it
              // gets no -wal or -shm beside it)
    kAttach,  // as kOpen, for a further connection to a map another one has just opened: its
              // identity is checked, not its integrity again (quick_check reads the whole file)
    kPeek,    // as kRead, for a further connection to a map another one has just opened
  };
  // Throws DatabaseError naming the file: not a regular file, not SQLite, not memloop's, newer
  // format, damaged header or content, or (kCreate) already holding a map. A refused file is never
  // written to: it is checked through a read-only connection first.
  // kOpen and kRead check the content too (map_integrity.h: once per unchanged file).
  // A server's map (`path` a postgresql:// URI, IsServerMap) is the connected robot's: kCreate
  // refuses a robot that has one, the others a robot that has none; kCreate and kOpen hold the
  // robot's lock on the server (one writer per robot) until the connection closes.
  LtmDatabase(const std::string& path, Mode mode);

  // SQLite max_page_count: writes past it fail as on a full disk (tests).
  void LimitPages(long long pages);
  void Begin();
  void Commit();
  // After ServerConnectionLost (a server's map): SqlConnection::Reconnect.
  double Reconnect() { return connection_->Reconnect(); }

  void WriteLocation(const Location& location);
  // A word's descriptor, as the bytes of its row (float or binary: the map's info says which).
  void WriteWord(WordId id, const std::vector<unsigned char>& descriptor);
  // Re-matched word (III-E): every reference to `old_id` becomes `new_id`; the old word goes.
  void ReplaceWord(WordId old_id, WordId new_id);
  // `absorbed` was merged into `survivor`: links to it now point to the survivor; its row goes.
  void RedirectLocation(LocationId absorbed, LocationId survivor);
  // A link of `from` (neighbour or loop closure) to `to`, kept when it exists already.
  void WriteLink(LocationId from, LocationId to, bool loop_closure);
  // With its pose (ltm_loop_closures.cc): maps made before the poses' table get it when opened
  // to write; read-only, their loop closures read with no pose estimated.
  void WriteLoopClosure(const LoopClosureRecord& record);
  void WriteInfo(const std::string& key, const std::string& value);
  void WriteCheckpoint(const CheckpointData& checkpoint);
  // Retrieval by appearance (appearance_index.h): a location's description, and vocabulary
  // entries from `first_entry` on (their words and descriptor rows, `row_bytes` each). Maps made
  // before these tables get them when opened to write; read-only, they read as empty.
  void WriteAppearance(LocationId id, const std::vector<uint32_t>& entries);
  void WriteAppearanceVocabulary(int first_entry, const std::vector<WordId>& words,
                                 const std::vector<unsigned char>& rows);

  // The map's images and sessions (ltm_images.cc). Maps made before the table get it when opened
  // to write; read-only, they read as empty.
  void WriteImage(const MapImage& image);
  std::vector<MapImage> ReadImages();
  // A fleet's map: robot `robot`'s images (none on a file).
  std::vector<MapImage> ReadImagesOf(const std::string& robot);
  std::vector<MapSession> ReadSessions();
  // The image of a location's signature (Signature::image), kNoImage when not recorded.
  void WriteView(const Location& location);
  ImageIndex ReadView(LocationId id);
  // Its whole-image descriptor (Signature::whole_image), empty when the map has none.
  void WriteWholeImage(const Location& location);
  std::vector<uint8_t> ReadWholeImage(LocationId id);
  long long CountWholeImages();  // LTM locations with one

  std::optional<Location> ReadLocation(LocationId id);
  std::optional<std::vector<unsigned char>> ReadWord(WordId id);
  // The descriptors the map holds of location `id`'s words (those that left the dictionary), in
  // one query: ReadWord for each word was a round trip each to a server (300 a location).
  std::unordered_map<WordId, std::vector<unsigned char>> ReadSignatureDescriptors(LocationId id);
  // Loop closures with a foreign place name its robot (match_robot; ltm_foreign_places.cc).
  std::vector<LoopClosureRecord> ReadLoopClosures();
  // Places imported from other robots (maps made before the table get it when opened to write;
  // read-only, they read as none).
  void WriteForeignPlace(const ForeignPlace& place);
  std::vector<ForeignPlace> ReadForeignPlaces();
  // Corrections of the loop closures (loop_closure_edits.h), in the order made; none before the
  // first.
  void CreateEditTable();
  long long WriteEdit(const LoopClosureEdit& edit);  // its id
  std::vector<LoopClosureEdit> ReadEdits();
  // The LTM location that holds `image` now, kNoLocation when none does.
  LocationId ReadHolder(ImageIndex image);
  // Every LTM image with the location that holds it, by image.
  std::vector<std::pair<ImageIndex, LocationId>> ReadHolders();
  std::string ReadInfo(const std::string& key);
  // Every info row whose key starts with `prefix`, sorted by key.
  std::vector<std::pair<std::string, std::string>> ReadInfoWithPrefix(const std::string& prefix);
  // The single number `sql` (a SELECT count(*) ...) yields.
  long long QueryNumber(const std::string& sql);
  // Every location id with rows in LTM, sorted.
  std::vector<LocationId> ReadLocationIds();
  // Every link (from, to) of the file, sorted, each once (a neighbour and a loop closure to the
  // same location are one link).
  std::vector<std::pair<LocationId, LocationId>> ReadAllLinks();
  // The checkpoint's rows: (id, blob) of memory locations and index points in point order.
  std::vector<std::pair<LocationId, std::vector<unsigned char>>> ReadMemoryLocations();
  std::vector<CheckpointData::Point> ReadIndexPoints();
  std::optional<std::vector<unsigned char>> ReadState(const std::string& key);
  // Every description, by location id; the vocabulary as (word, descriptor row) in entry order.
  std::vector<std::pair<LocationId, std::vector<uint32_t>>> ReadAppearances();
  std::vector<std::pair<WordId, std::vector<unsigned char>>> ReadAppearanceVocabulary();
  int format_version() const { return format_version_; }
  long long CountLocations();
  long long CountWords();

  const std::string& path() const { return connection_->path(); }
  bool on_server() const { return on_server_; }

 private:
  // The checks above; returns the map's format version (kFormatVersion for a new file).
  static int CheckMapFile(const std::string& path, Mode mode);
  static int CheckMapContent(const std::string& path, Mode mode);  // after the file's type
  // A map SQLite may read alone (immutable): closed cleanly, not being written.
  static bool ReadableAlone(const std::string& path);
  static std::unique_ptr<SqlConnection> Connect(const std::string& path, Mode mode);
  // The server's checks (ltm_server_map.cc); returns the map's format version.
  int OpenServerMap(Mode mode);
  void CreateSchema();
  void CreateAppearanceTables();
  void CreateImageTable();
  void CreateLoopClosurePoseTable();
  void CreateForeignPlaceTable();
  bool HasTable(const std::string& name);
  // Whether the map holds exactly `signature` as location `id`'s words (WriteLocation).
  bool StoredSignatureIs(LocationId id, const Signature& signature);
  // Appends location `id`'s words and keypoints, in rank order, to `signature`.
  void ReadSignatureWords(LocationId id, Signature& signature);
  SqlStatement& Cached(const std::string& sql);

  // The format version is also an info row, so that a damaged header is told from a newer map.
  static constexpr const char* kFormatKey = "format_version";

  int format_version_;  // before connection_: the file is checked before it is opened to write
  bool on_server_;
  std::unique_ptr<SqlConnection> connection_;
  std::vector<std::pair<std::string, std::unique_ptr<SqlStatement>>> statements_;
  std::optional<bool> has_views_;         // the location_views table, once looked for
  std::optional<bool> has_whole_images_;  // the whole_images table
  std::optional<bool> has_poses_;         // the loop_closure_poses table
  std::optional<bool> has_foreign_;       // the foreign_places table
};

}  // namespace memloop
