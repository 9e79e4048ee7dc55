// The checks of a map file before it is opened (LtmDatabase::CheckMapFile): what cannot be a
// map is refused with the reason, and a refused file is never written to.
#include <sys/stat.h>
#include <unistd.h>

#include <cstring>
#include <filesystem>
#include <fstream>

#include "memloop/errors.h"
#include "storage/ltm_database.h"
#include "storage/map_integrity.h"
#include "storage/map_writer_lock.h"

namespace memloop {
namespace {

namespace fs = std::filesystem;

off_t FileSize(const std::string& path) {
  struct stat info {};
  return stat(path.c_str(), &info) == 0 ? info.st_size : 0;
}

// A map's rows may still be only in its write-ahead log (a run killed before SQLite folded it).
bool HoldsData(const std::string& path) {
  return FileSize(path) > 0 || FileSize(path + "-wal") > 0;
}

}  // namespace

// A file SQLite may read alone, leaving nothing beside it: no write-ahead log with content
// (a map closed cleanly), no rollback journal, and no process writing it.
bool LtmDatabase::ReadableAlone(const std::string& path) {
  return FileSize(path + "-wal") == 0 && !fs::exists(path + "-journal") && !MapOpenToWrite(path);
}

namespace {

// What cannot be a map file at all, said before SQLite says "disk I/O error" or "unable to open".
void CheckIsFileOrAbsent(const std::string& path, LtmDatabase::Mode mode) {
  struct stat info {};
  if (stat(path.c_str(), &info) == 0) {
    if (S_ISDIR(info.st_mode)) throw DatabaseError(path, "is a folder; a map is a file");
    if (!S_ISREG(info.st_mode)) {
      throw DatabaseError(path,
                          "is not a regular file (a device, pipe or socket); a map is a file");
    }
    return;
  }
  if (mode != LtmDatabase::Mode::kCreate) throw DatabaseError(path, "no such file");
  const std::string folder = fs::path(path).parent_path().string();
  if (!folder.empty() && !fs::is_directory(folder)) {
    throw DatabaseError(path, "cannot create the map: the folder " + folder + " does not exist");
  }
}

uint32_t BigEndian(const unsigned char* bytes, int count) {
  uint32_t value = 0;
  for (int i = 0; i < count; ++i) value = value << 8 | bytes[i];
  return value;
}

// An SQLite file shorter than its header says (a copy or download cut short): said as such, not
// as the "malformed" SQLite would report. The header's page count is valid when its
// version-valid-for number equals its change counter (https://sqlite.org/fileformat.html).
void CheckNotTruncated(const std::string& path) {
  unsigned char header[100] = {};
  std::ifstream in(path, std::ios::binary);
  if (!in.read(reinterpret_cast<char*>(header), sizeof(header))) return;
  if (std::memcmp(header, "SQLite format 3", 16) != 0) return;
  const uint32_t page_size = BigEndian(header + 16, 2) == 1 ? 65536 : BigEndian(header + 16, 2);
  if (BigEndian(header + 92, 4) != BigEndian(header + 24, 4)) return;
  const unsigned long long expected =
      static_cast<unsigned long long>(BigEndian(header + 28, 4)) * page_size;
  const auto size = static_cast<unsigned long long>(FileSize(path));
  if (size < expected) {
    throw DatabaseError(path, "the map is truncated: " + std::to_string(size) + " bytes of the " +
                                  std::to_string(expected) +
                                  " its header records (a copy cut short?)");
  }
}

int ReadInt(SqliteConnection& connection, const std::string& sql) {
  SqliteStatement query(connection, sql);
  return query.Step() ? static_cast<int>(query.Int(0)) : 0;
}

std::string ReadText(SqliteConnection& connection, const std::string& sql) {
  try {
    SqliteStatement query(connection, sql);
    return query.Step() ? query.Text(0) : "";
  } catch (const DatabaseError&) {
    return "";  // no such table: a map older than the row
  }
}

// A refused map keeps its folder as it was: the -shm index SQLite made to read its log goes
// (unless another process uses it).
class RemoveIndexIfRefused {
 public:
  explicit RemoveIndexIfRefused(const std::string& path)
      : index_(path + "-shm"), existed_(fs::exists(index_)), path_(path) {}
  ~RemoveIndexIfRefused() {
    if (!accepted_ && !existed_ && !MapOpenToWrite(path_)) {
      std::error_code ignored;
      fs::remove(index_, ignored);
    }
  }
  void Accept() { accepted_ = true; }

 private:
  std::string index_;
  bool existed_;
  std::string path_;
  bool accepted_ = false;
};

}  // namespace

int LtmDatabase::CheckMapFile(const std::string& path, Mode mode) {
  CheckIsFileOrAbsent(path, mode);
  RemoveIndexIfRefused index(path);
  const int version = CheckMapContent(path, mode);
  index.Accept();
  return version;
}

int LtmDatabase::CheckMapContent(const std::string& path, Mode mode) {
  if (!HoldsData(path)) {
    if (mode != Mode::kCreate) {
      throw DatabaseError(path,
                          "empty file: no memloop map in it (a run killed before its first "
                          "image was stored leaves one: run without --resume to start "
                          "the map afresh)");
    }
    return kFormatVersion;
  }
  // With a write-ahead log, a killed checkpoint may leave the file short of its new header; the
  // log still holds the pages.
  if (ReadableAlone(path)) CheckNotTruncated(path);
  // Read-only: a refused file keeps its bytes (a read-write connection would fold the WAL in),
  // and, read alone, gets no -wal or -shm beside it.
  SqliteConnection connection(path, SQLITE_OPEN_READONLY, ReadableAlone(path));
  int application_id = 0;
  int version = 0;
  try {
    application_id = ReadInt(connection, "PRAGMA application_id");
    version = ReadInt(connection, "PRAGMA user_version");
  } catch (const DatabaseError&) {
    const std::string folder =
        fs::path(path).parent_path().empty() ? "." : fs::path(path).parent_path().string();
    if (!ReadableAlone(path) && access(folder.c_str(), W_OK) != 0) {
      throw DatabaseError(path, "cannot read the map's write-ahead log (" + path +
                                    "-wal): SQLite needs to write its -shm file, and the folder " +
                                    folder +
                                    " is not writable; copy the map and its -wal "
                                    "somewhere writable");
    }
    throw DatabaseError(path, std::string("not a memloop map: not an SQLite database, or its "
                                          "header is damaged (") +
                                  sqlite3_errmsg(connection.handle()) + ")");
  }
  if (application_id != kApplicationId) {
    throw DatabaseError(path, "not a memloop map (an SQLite database of another application)");
  }
  if (version > kFormatVersion || version < 1) {
    // Every format writes its version in the info table too: a header that disagrees with it
    // was damaged, it is not a newer memloop's map.
    const std::string recorded =
        ReadText(connection, "SELECT value FROM info WHERE key='" + std::string(kFormatKey) + "'");
    if (version < 1 || recorded != std::to_string(version)) {
      throw DatabaseError(path, "the map's header is damaged (format version " +
                                    std::to_string(version) + " in the header, " +
                                    (recorded.empty() ? "none" : recorded) + " in the map)");
    }
    throw DatabaseError(path, "map format " + std::to_string(version) +
                                  " is newer than this memloop's (" +
                                  std::to_string(kFormatVersion) + "): upgrade memloop");
  }
  if (mode == Mode::kCreate) {
    throw DatabaseError(path,
                        "already holds a memloop map; a run starts a new map, so choose "
                        "another --db path (the existing map is left untouched)");
  }
  if (mode != Mode::kAttach && mode != Mode::kPeek) {
    const std::string problems = MapIntegrityProblems(connection, path);
    if (!problems.empty()) throw DatabaseError(path, "the map is damaged (" + problems + ")");
  }
  return version;
}

}  // namespace memloop
