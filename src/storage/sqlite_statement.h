// Minimal RAII over the SQLite C API: a connection and prepared statements that throw
// DatabaseError (naming the file) on failure.
#pragma once

#include <sqlite3.h>

#include <string>
#include <vector>

#include "storage/sql_connection.h"

namespace memloop {

class SqliteConnection : public SqlConnection {
 public:
  // flags: SQLITE_OPEN_* flags. `immutable` (read-only, for a file no other connection uses and
  // whose write-ahead log is absent or empty): SQLite reads the file alone and creates no -wal or
  // -shm beside it (URI parameter immutable=1), which also works on a read-only file system.
  SqliteConnection(const std::string& path, int flags, bool immutable = false);
  ~SqliteConnection() override;
  SqliteConnection(const SqliteConnection&) = delete;
  SqliteConnection& operator=(const SqliteConnection&) = delete;

  void Execute(const std::string& sql) override;
  std::unique_ptr<SqlStatement> Prepare(const std::string& sql) override;
  // Throws DatabaseError "<path>: <what>: <sqlite message>" when `code` is an error.
  void Check(int code, const std::string& what) const;
  sqlite3* handle() const { return db_; }
  const std::string& path() const override { return path_; }

 private:
  std::string path_;
  sqlite3* db_ = nullptr;
};

class SqliteStatement : public SqlStatement {
 public:
  SqliteStatement(const SqliteConnection& connection, const std::string& sql);
  ~SqliteStatement() override;
  SqliteStatement(const SqliteStatement&) = delete;
  SqliteStatement& operator=(const SqliteStatement&) = delete;

  SqliteStatement& Bind(int index, long long value) override;
  SqliteStatement& Bind(int index, double value) override;
  SqliteStatement& Bind(int index, const std::string& value) override;
  SqliteStatement& BindBlob(int index, const void* data, int bytes) override;
  SqliteStatement& BindNull(int index) override;
  // True while a row is available.
  bool Step() override;
  // Runs to completion and resets, for statements without result rows.
  void Run() override;
  void Reset() override;

  long long Int(int column) const override;
  double Double(int column) const override;
  bool IsNull(int column) const override;
  std::string Text(int column) const override;
  std::vector<unsigned char> Blob(int column) const override;

 private:
  const SqliteConnection& connection_;
  sqlite3_stmt* statement_ = nullptr;
};

}  // namespace memloop
