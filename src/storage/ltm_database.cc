#include "storage/ltm_database.h"

#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <unordered_map>

#include "memloop/errors.h"
#include "storage/map_integrity.h"
#include "storage/map_writer_lock.h"
#include "storage/postgres_connection.h"

namespace memloop {
namespace {

constexpr int kLinkNeighbour = 0;
constexpr int kLinkLoopClosure = 1;

}  // namespace

std::unique_ptr<SqlConnection> LtmDatabase::Connect(const std::string& path, Mode mode) {
  if (IsServerMap(path)) return std::make_unique<PostgresConnection>(path);
  return std::make_unique<SqliteConnection>(
      path,
      mode == Mode::kCreate                        ? SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE
      : mode == Mode::kRead || mode == Mode::kPeek ? SQLITE_OPEN_READONLY
                                                   : SQLITE_OPEN_READWRITE,
      // kPeek reads beside a writer: it must see the log
      mode == Mode::kRead && ReadableAlone(path));
}

LtmDatabase::LtmDatabase(const std::string& path, Mode mode)
    : format_version_(IsServerMap(path) ? kFormatVersion : CheckMapFile(path, mode)),
      on_server_(IsServerMap(path)),
      connection_(Connect(path, mode)) {
  if (on_server_) {
    format_version_ = OpenServerMap(mode);
    return;
  }
  if (mode == Mode::kRead || mode == Mode::kPeek) return;
  // WAL: the writer thread and readers do not block each other; synchronous=NORMAL keeps every
  // committed transaction through a crash of the process (not of the OS, by design of WAL).
  connection_->Execute(
      "PRAGMA journal_mode=WAL; PRAGMA synchronous=NORMAL;"
      "PRAGMA foreign_keys=OFF;");
  if (mode == Mode::kCreate) CreateSchema();
  CreateAppearanceTables();
  CreateImageTable();
  CreateLoopClosurePoseTable();
  CreateForeignPlaceTable();
}

void LtmDatabase::CreateAppearanceTables() {
  connection_->Execute(
      "CREATE TABLE IF NOT EXISTS appearances(location_id INTEGER PRIMARY KEY,"
      " entries BLOB NOT NULL);"
      "CREATE TABLE IF NOT EXISTS appearance_vocabulary(entry INTEGER PRIMARY KEY,"
      " word_id INTEGER NOT NULL, descriptor BLOB NOT NULL);");
}

void LtmDatabase::WriteAppearance(LocationId id, const std::vector<uint32_t>& entries) {
  Cached("INSERT OR REPLACE INTO appearances(location_id, entries) VALUES(?,?)")
      .Bind(1, static_cast<long long>(id))
      .BindBlob(2, entries.data(), static_cast<int>(entries.size() * sizeof(uint32_t)))
      .Run();
}

void LtmDatabase::WriteAppearanceVocabulary(int first_entry, const std::vector<WordId>& words,
                                            const std::vector<unsigned char>& rows) {
  if (words.empty()) return;
  const size_t row_bytes = rows.size() / words.size();
  auto& insert = Cached(
      "INSERT OR REPLACE INTO appearance_vocabulary(entry, word_id, descriptor) VALUES(?,?,?)");
  for (size_t i = 0; i < words.size(); ++i) {
    insert.Bind(1, static_cast<long long>(first_entry + i))
        .Bind(2, static_cast<long long>(words[i]))
        .BindBlob(3, rows.data() + i * row_bytes, static_cast<int>(row_bytes))
        .Run();
  }
}

std::vector<std::pair<LocationId, std::vector<uint32_t>>> LtmDatabase::ReadAppearances() {
  std::vector<std::pair<LocationId, std::vector<uint32_t>>> rows;
  if (!HasTable("appearances")) return rows;  // a read-only map made before the table
  auto& query = Cached("SELECT location_id, entries FROM appearances ORDER BY location_id");
  while (query.Step()) {
    const std::vector<unsigned char> blob = query.Blob(1);
    std::vector<uint32_t> entries(blob.size() / sizeof(uint32_t));
    if (!entries.empty())
      std::memcpy(entries.data(), blob.data(), entries.size() * sizeof(uint32_t));
    rows.emplace_back(static_cast<LocationId>(query.Int(0)), std::move(entries));
  }
  query.Reset();
  return rows;
}

std::vector<std::pair<WordId, std::vector<unsigned char>>> LtmDatabase::ReadAppearanceVocabulary() {
  std::vector<std::pair<WordId, std::vector<unsigned char>>> rows;
  if (!HasTable("appearance_vocabulary")) return rows;
  auto& query = Cached("SELECT word_id, descriptor FROM appearance_vocabulary ORDER BY entry");
  while (query.Step()) rows.emplace_back(static_cast<WordId>(query.Int(0)), query.Blob(1));
  query.Reset();
  return rows;
}

bool LtmDatabase::HasTable(const std::string& name) {
  if (on_server_) return true;  // a fleet's map has every table (fleet_schema.h)
  auto& query = Cached("SELECT count(*) FROM sqlite_master WHERE type='table' AND name=?");
  query.Bind(1, name);
  const bool found = query.Step() && query.Int(0) > 0;
  query.Reset();
  return found;
}

void LtmDatabase::CreateSchema() {
  connection_->Execute(
      "BEGIN;"
      "PRAGMA application_id=" +
      std::to_string(kApplicationId) +
      ";"
      "PRAGMA user_version=" +
      std::to_string(kFormatVersion) +
      ";"
      "CREATE TABLE info(key TEXT PRIMARY KEY, value TEXT NOT NULL);"
      "CREATE TABLE locations(id INTEGER PRIMARY KEY, weight INTEGER NOT NULL);"
      "CREATE TABLE location_images(location_id INTEGER NOT NULL, rank INTEGER NOT NULL,"
      " image INTEGER NOT NULL, PRIMARY KEY(location_id, rank)) WITHOUT ROWID;"
      "CREATE TABLE links(from_id INTEGER NOT NULL, to_id INTEGER NOT NULL,"
      " type INTEGER NOT NULL, PRIMARY KEY(from_id, to_id, type)) WITHOUT ROWID;"
      "CREATE INDEX links_to ON links(to_id);"
      "CREATE TABLE signature_words(location_id INTEGER NOT NULL, rank INTEGER NOT NULL,"
      " word_id INTEGER NOT NULL, x REAL, y REAL, size REAL, angle REAL, response REAL,"
      " octave INTEGER, PRIMARY KEY(location_id, rank)) WITHOUT ROWID;"
      "CREATE INDEX signature_words_word ON signature_words(word_id);"
      "CREATE TABLE words(id INTEGER PRIMARY KEY, descriptor BLOB NOT NULL);"
      "CREATE TABLE loop_closures(query_image INTEGER NOT NULL, match_image INTEGER NOT NULL,"
      " query_location INTEGER NOT NULL, match_location INTEGER NOT NULL, probability REAL);"
      "CREATE TABLE memory_locations(id INTEGER PRIMARY KEY, data BLOB NOT NULL);"
      "CREATE TABLE index_chunks(first_point INTEGER PRIMARY KEY, words BLOB NOT NULL);"
      "CREATE TABLE index_descriptors(word_id INTEGER PRIMARY KEY, descriptor BLOB NOT NULL);"
      "CREATE TABLE resume_state(key TEXT PRIMARY KEY, value BLOB NOT NULL);"
      "INSERT INTO info(key, value) VALUES('" +
      std::string(kFormatKey) + "', '" + std::to_string(kFormatVersion) +
      "');"
      "COMMIT;");
}

SqlStatement& LtmDatabase::Cached(const std::string& sql) {
  for (auto& [text, statement] : statements_) {
    if (text == sql) return *statement;
  }
  statements_.emplace_back(sql, connection_->Prepare(sql));
  return *statements_.back().second;
}

void LtmDatabase::Begin() { Cached("BEGIN").Run(); }
void LtmDatabase::Commit() { Cached("COMMIT").Run(); }

void LtmDatabase::WriteLocation(const Location& location) {
  const long long id = location.id;
  for (const char* sql : {"DELETE FROM locations WHERE id=?", "DELETE FROM links WHERE from_id=?",
                          "DELETE FROM location_images WHERE location_id=?"}) {
    Cached(sql).Bind(1, id).Run();
  }
  Cached("INSERT INTO locations(id, weight) VALUES(?,?)")
      .Bind(1, id)
      .Bind(2, static_cast<long long>(location.weight))
      .Run();
  auto& link = Cached("INSERT OR IGNORE INTO links(from_id, to_id, type) VALUES(?,?,?)");
  for (LocationId to : location.neighbours) {
    link.Bind(1, id).Bind(2, static_cast<long long>(to)).Bind(3, 0LL + kLinkNeighbour).Run();
  }
  for (LocationId to : location.loop_closures) {
    link.Bind(1, id).Bind(2, static_cast<long long>(to)).Bind(3, 0LL + kLinkLoopClosure).Run();
  }
  auto& image = Cached("INSERT INTO location_images(location_id, rank, image) VALUES(?,?,?)");
  for (size_t rank = 0; rank < location.images.size(); ++rank) {
    image.Bind(1, id)
        .Bind(2, static_cast<long long>(rank))
        .Bind(3, static_cast<long long>(location.images[rank]))
        .Run();
  }
  WriteView(location);
  WriteWholeImage(location);
  // A location stored again (retrieved, then transferred back) mostly has the signature the map
  // holds: its rows, and their entries in the word index on pages all over a large map, are then
  // left as they are (issue 39: storing a location took 0.43 -> 0.85 ms in a 1.9 GB map).
  if (StoredSignatureIs(id, location.signature)) return;
  Cached("DELETE FROM signature_words WHERE location_id=?").Bind(1, id).Run();
  auto& word = Cached(
      "INSERT INTO signature_words(location_id, rank, word_id, x, y, size, angle, response,"
      " octave) VALUES(?,?,?,?,?,?,?,?,?)");
  const Signature& signature = location.signature;
  for (size_t rank = 0; rank < signature.words.size(); ++rank) {
    const cv::KeyPoint& keypoint = signature.keypoints[rank];
    word.Bind(1, id)
        .Bind(2, static_cast<long long>(rank))
        .Bind(3, static_cast<long long>(signature.words[rank]))
        .Bind(4, double{keypoint.pt.x})
        .Bind(5, double{keypoint.pt.y})
        .Bind(6, double{keypoint.size})
        .Bind(7, double{keypoint.angle})
        .Bind(8, double{keypoint.response})
        .Bind(9, static_cast<long long>(keypoint.octave))
        .Run();
  }
}

void LtmDatabase::WriteWord(WordId id, const std::vector<unsigned char>& descriptor) {
  Cached("INSERT OR REPLACE INTO words(id, descriptor) VALUES(?,?)")
      .Bind(1, static_cast<long long>(id))
      .BindBlob(2, descriptor.data(), static_cast<int>(descriptor.size()))
      .Run();
}

void LtmDatabase::ReplaceWord(WordId old_id, WordId new_id) {
  Cached("UPDATE signature_words SET word_id=? WHERE word_id=?")
      .Bind(1, static_cast<long long>(new_id))
      .Bind(2, static_cast<long long>(old_id))
      .Run();
  Cached("DELETE FROM words WHERE id=?").Bind(1, static_cast<long long>(old_id)).Run();
}

void LtmDatabase::RedirectLocation(LocationId absorbed, LocationId survivor) {
  // A link that would then exist twice stays as it was (and goes below).
  Cached(on_server_ ? "UPDATE links SET to_id=? WHERE to_id=? AND NOT EXISTS (SELECT 1 FROM links"
                      " twin WHERE twin.from_id=links.from_id AND twin.to_id=?1 AND"
                      " twin.type=links.type)"
                    : "UPDATE OR IGNORE links SET to_id=? WHERE to_id=?")
      .Bind(1, static_cast<long long>(survivor))
      .Bind(2, static_cast<long long>(absorbed))
      .Run();
  for (const char* sql :
       {"DELETE FROM links WHERE to_id=? OR from_id=?1", "DELETE FROM locations WHERE id=?",
        "DELETE FROM location_images WHERE location_id=?",
        "DELETE FROM signature_words WHERE location_id=?",
        "DELETE FROM appearances WHERE location_id=?",
        "DELETE FROM location_views WHERE location_id=?",
        "DELETE FROM whole_images WHERE location_id=?"}) {
    Cached(sql).Bind(1, static_cast<long long>(absorbed)).Run();
  }
  // A survivor linked to itself through the redirection keeps no such link.
  Cached("DELETE FROM links WHERE from_id=? AND to_id=?1")
      .Bind(1, static_cast<long long>(survivor))
      .Run();
}

void LtmDatabase::WriteLink(LocationId from, LocationId to, bool loop_closure) {
  Cached("INSERT OR IGNORE INTO links(from_id, to_id, type) VALUES(?,?,?)")
      .Bind(1, static_cast<long long>(from))
      .Bind(2, static_cast<long long>(to))
      .Bind(3, 0LL + (loop_closure ? kLinkLoopClosure : kLinkNeighbour))
      .Run();
}

void LtmDatabase::LimitPages(long long pages) {
  if (on_server_) return;  // the server's disk is the server's
  connection_->Execute("PRAGMA max_page_count=" + std::to_string(pages));
}

void LtmDatabase::WriteInfo(const std::string& key, const std::string& value) {
  Cached("INSERT OR REPLACE INTO info(key, value) VALUES(?,?)").Bind(1, key).Bind(2, value).Run();
}

size_t CheckpointData::bytes() const {
  size_t total = 64;
  for (const auto& [id, data] : locations) total += data.size() + 16;
  total += index_words.size() * sizeof(WordId);
  for (const auto& [word, descriptor] : index_descriptors) total += descriptor.size() + 16;
  for (const auto& [key, value] : state) total += key.size() + value.size();
  return total + removed_locations.size() * sizeof(LocationId);
}

void LtmDatabase::WriteCheckpoint(const CheckpointData& checkpoint) {
  if (format_version_ < kFormatVersion) {  // its checkpoint is now this format's
    connection_->Execute("PRAGMA user_version=" + std::to_string(kFormatVersion));
    WriteInfo(kFormatKey, std::to_string(kFormatVersion));
    format_version_ = kFormatVersion;
  }
  if (checkpoint.full) Cached("DELETE FROM memory_locations").Run();
  if (checkpoint.full) Cached("DELETE FROM index_descriptors").Run();
  if (checkpoint.full) Cached("DELETE FROM resume_state").Run();
  if (checkpoint.full || checkpoint.reset_index) Cached("DELETE FROM index_chunks").Run();
  for (LocationId id : checkpoint.removed_locations) {
    Cached("DELETE FROM memory_locations WHERE id=?").Bind(1, static_cast<long long>(id)).Run();
  }
  auto& location = Cached("INSERT OR REPLACE INTO memory_locations(id, data) VALUES(?,?)");
  for (const auto& [id, data] : checkpoint.locations) {
    location.Bind(1, static_cast<long long>(id))
        .BindBlob(2, data.data(), static_cast<int>(data.size()))
        .Run();
  }
  // The index points of this checkpoint (consecutive) as one row of word ids: a rebuild rewrites
  // one blob, not a row per point.
  static_assert(sizeof(WordId) == sizeof(int32_t));
  if (!checkpoint.index_words.empty()) {
    Cached("INSERT OR REPLACE INTO index_chunks(first_point, words) VALUES(?,?)")
        .Bind(1, checkpoint.first_index_point)
        .BindBlob(2, checkpoint.index_words.data(),
                  static_cast<int>(checkpoint.index_words.size() * sizeof(int32_t)))
        .Run();
  }
  auto& forget = Cached("DELETE FROM index_descriptors WHERE word_id=?");
  for (WordId word : checkpoint.forgotten_descriptors) {
    forget.Bind(1, static_cast<long long>(word)).Run();
  }
  auto& descriptor =
      Cached("INSERT OR REPLACE INTO index_descriptors(word_id, descriptor) VALUES(?,?)");
  for (const auto& [word, bytes] : checkpoint.index_descriptors) {
    descriptor.Bind(1, static_cast<long long>(word))
        .BindBlob(2, bytes.data(), static_cast<int>(bytes.size()))
        .Run();
  }
  auto& state = Cached("INSERT OR REPLACE INTO resume_state(key, value) VALUES(?,?)");
  for (const auto& [key, value] : checkpoint.state) {
    state.Bind(1, key).BindBlob(2, value.data(), static_cast<int>(value.size())).Run();
  }
}

std::vector<LocationId> LtmDatabase::ReadLocationIds() {
  auto& query = Cached("SELECT id FROM locations ORDER BY id");
  std::vector<LocationId> ids;
  while (query.Step()) ids.push_back(static_cast<LocationId>(query.Int(0)));
  query.Reset();
  return ids;
}

std::vector<std::pair<LocationId, LocationId>> LtmDatabase::ReadAllLinks() {
  auto& query = Cached("SELECT DISTINCT from_id, to_id FROM links ORDER BY from_id, to_id");
  std::vector<std::pair<LocationId, LocationId>> links;
  while (query.Step()) {
    links.emplace_back(static_cast<LocationId>(query.Int(0)),
                       static_cast<LocationId>(query.Int(1)));
  }
  query.Reset();
  return links;
}

std::vector<std::pair<LocationId, std::vector<unsigned char>>> LtmDatabase::ReadMemoryLocations() {
  auto& query = Cached("SELECT id, data FROM memory_locations ORDER BY id");
  std::vector<std::pair<LocationId, std::vector<unsigned char>>> rows;
  while (query.Step()) rows.emplace_back(static_cast<LocationId>(query.Int(0)), query.Blob(1));
  query.Reset();
  return rows;
}

std::vector<CheckpointData::Point> LtmDatabase::ReadIndexPoints() {
  std::vector<CheckpointData::Point> rows;
  auto& chunks = Cached("SELECT first_point, words FROM index_chunks ORDER BY first_point");
  while (chunks.Step()) {
    const long long first = chunks.Int(0);
    const std::vector<unsigned char> bytes = chunks.Blob(1);
    if (first != static_cast<long long>(rows.size()) || bytes.size() % sizeof(int32_t) != 0) {
      chunks.Reset();
      throw DatabaseError(
          path(), "the checkpoint's index chunk at point " + std::to_string(first) + " is damaged");
    }
    for (size_t k = 0; k < bytes.size() / sizeof(int32_t); ++k) {
      int32_t word = 0;
      std::memcpy(&word, bytes.data() + k * sizeof(int32_t), sizeof(int32_t));
      rows.push_back({static_cast<long long>(rows.size()), word, {}});
    }
  }
  chunks.Reset();
  auto& descriptor = Cached("SELECT descriptor FROM index_descriptors WHERE word_id=?");
  std::unordered_map<WordId, std::vector<unsigned char>> descriptors;
  for (CheckpointData::Point& row : rows) {
    auto found = descriptors.find(row.word);
    if (found == descriptors.end()) {
      descriptor.Bind(1, static_cast<long long>(row.word));
      found = descriptors
                  .emplace(row.word,
                           descriptor.Step() ? descriptor.Blob(0) : std::vector<unsigned char>())
                  .first;
      descriptor.Reset();
    }
    row.descriptor = found->second;  // empty when missing: the reader refuses it
  }
  return rows;
}

std::optional<std::vector<unsigned char>> LtmDatabase::ReadState(const std::string& key) {
  auto& query = Cached("SELECT value FROM resume_state WHERE key=?");
  query.Bind(1, key);
  std::optional<std::vector<unsigned char>> value;
  if (query.Step()) value = query.Blob(0);
  query.Reset();
  return value;
}

bool LtmDatabase::StoredSignatureIs(LocationId id, const Signature& signature) {
  Signature stored;
  ReadSignatureWords(id, stored);
  // Read back as WriteLocation stored them (floats through doubles): exact.
  const auto same_keypoint = [](const cv::KeyPoint& a, const cv::KeyPoint& b) {
    return a.pt == b.pt && a.size == b.size && a.angle == b.angle && a.response == b.response &&
           a.octave == b.octave;
  };
  return stored.words == signature.words &&
         std::equal(stored.keypoints.begin(), stored.keypoints.end(), signature.keypoints.begin(),
                    signature.keypoints.end(), same_keypoint);
}

void LtmDatabase::ReadSignatureWords(LocationId id, Signature& signature) {
  auto& words = Cached(
      "SELECT word_id, x, y, size, angle, response, octave FROM signature_words"
      " WHERE location_id=? ORDER BY rank");
  words.Bind(1, static_cast<long long>(id));
  while (words.Step()) {
    signature.words.push_back(static_cast<WordId>(words.Int(0)));
    signature.keypoints.emplace_back(
        cv::Point2f(static_cast<float>(words.Double(1)), static_cast<float>(words.Double(2))),
        static_cast<float>(words.Double(3)), static_cast<float>(words.Double(4)),
        static_cast<float>(words.Double(5)), static_cast<int>(words.Int(6)));
  }
  words.Reset();
}

std::optional<Location> LtmDatabase::ReadLocation(LocationId id) {
  auto& row = Cached("SELECT weight FROM locations WHERE id=?");
  row.Bind(1, static_cast<long long>(id));
  if (!row.Step()) {
    row.Reset();
    return std::nullopt;
  }
  Location location;
  location.id = id;
  location.weight = static_cast<int>(row.Int(0));
  row.Reset();
  auto& links = Cached("SELECT to_id, type FROM links WHERE from_id=? ORDER BY to_id");
  links.Bind(1, static_cast<long long>(id));
  while (links.Step()) {
    auto& set = links.Int(1) == kLinkNeighbour ? location.neighbours : location.loop_closures;
    set.insert(static_cast<LocationId>(links.Int(0)));
  }
  links.Reset();
  auto& images = Cached("SELECT image FROM location_images WHERE location_id=? ORDER BY rank");
  images.Bind(1, static_cast<long long>(id));
  while (images.Step()) location.images.push_back(static_cast<ImageIndex>(images.Int(0)));
  images.Reset();
  ReadSignatureWords(id, location.signature);
  location.signature.image = ReadView(id);
  location.signature.whole_image = ReadWholeImage(id);
  return location;
}

std::optional<std::vector<unsigned char>> LtmDatabase::ReadWord(WordId id) {
  auto& query = Cached("SELECT descriptor FROM words WHERE id=?");
  query.Bind(1, static_cast<long long>(id));
  std::optional<std::vector<unsigned char>> descriptor;
  if (query.Step()) descriptor = query.Blob(0);
  query.Reset();
  return descriptor;
}

std::unordered_map<WordId, std::vector<unsigned char>> LtmDatabase::ReadSignatureDescriptors(
    LocationId id) {
  auto& query = Cached(
      "SELECT w.id, w.descriptor FROM signature_words s JOIN words w ON w.id = s.word_id"
      " WHERE s.location_id=?");
  query.Bind(1, static_cast<long long>(id));
  std::unordered_map<WordId, std::vector<unsigned char>> descriptors;
  while (query.Step()) descriptors.emplace(static_cast<WordId>(query.Int(0)), query.Blob(1));
  query.Reset();
  return descriptors;
}

std::string LtmDatabase::ReadInfo(const std::string& key) {
  auto& query = Cached("SELECT value FROM info WHERE key=?");
  query.Bind(1, key);
  const std::string value = query.Step() ? query.Text(0) : "";
  query.Reset();
  return value;
}

std::vector<std::pair<std::string, std::string>> LtmDatabase::ReadInfoWithPrefix(
    const std::string& prefix) {
  auto& query = Cached("SELECT key, value FROM info WHERE substr(key, 1, ?)=? ORDER BY key");
  query.Bind(1, static_cast<long long>(prefix.size())).Bind(2, prefix);
  std::vector<std::pair<std::string, std::string>> rows;
  while (query.Step()) rows.emplace_back(query.Text(0), query.Text(1));
  query.Reset();
  return rows;
}

long long LtmDatabase::QueryNumber(const std::string& sql) {
  auto& query = Cached(sql);
  const long long number = query.Step() ? query.Int(0) : 0;
  query.Reset();
  return number;
}

long long LtmDatabase::CountLocations() { return QueryNumber("SELECT count(*) FROM locations"); }

long long LtmDatabase::CountWords() { return QueryNumber("SELECT count(*) FROM words"); }

}  // namespace memloop
