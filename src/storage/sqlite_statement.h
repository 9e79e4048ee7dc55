// Minimal RAII over the SQLite C API: a connection and prepared statements that throw
// DatabaseError (naming the file) on failure.
#pragma once

#include <sqlite3.h>

#include <string>
#include <vector>

namespace memloop {

class SqliteConnection {
 public:
  // flags: SQLITE_OPEN_* flags. `immutable` (read-only, for a file no other connection uses and
  // whose write-ahead log is absent or empty): SQLite reads the file alone and creates no -wal or
  // -shm beside it (URI parameter immutable=1), which also works on a read-only file system.
  SqliteConnection(const std::string& path, int flags, bool immutable = false);
  ~SqliteConnection();
  SqliteConnection(const SqliteConnection&) = delete;
  SqliteConnection& operator=(const SqliteConnection&) = delete;

  void Execute(const std::string& sql);
  // Throws DatabaseError "<path>: <what>: <sqlite message>" when `code` is an error.
  void Check(int code, const std::string& what) const;
  sqlite3* handle() const { return db_; }
  const std::string& path() const { return path_; }

 private:
  std::string path_;
  sqlite3* db_ = nullptr;
};

class SqliteStatement {
 public:
  SqliteStatement(const SqliteConnection& connection, const std::string& sql);
  ~SqliteStatement();
  SqliteStatement(const SqliteStatement&) = delete;
  SqliteStatement& operator=(const SqliteStatement&) = delete;

  SqliteStatement& Bind(int index, long long value);
  SqliteStatement& Bind(int index, double value);
  SqliteStatement& Bind(int index, const std::string& value);
  SqliteStatement& BindBlob(int index, const void* data, int bytes);
  SqliteStatement& BindNull(int index);
  // True while a row is available.
  bool Step();
  // Runs to completion and resets, for statements without result rows.
  void Run();
  void Reset();

  long long Int(int column) const;
  double Double(int column) const;
  bool IsNull(int column) const;
  std::string Text(int column) const;
  std::vector<unsigned char> Blob(int column) const;

 private:
  const SqliteConnection& connection_;
  sqlite3_stmt* statement_ = nullptr;
};

}  // namespace memloop
