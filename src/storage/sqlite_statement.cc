#include "storage/sqlite_statement.h"

#include <cctype>
#include <cstring>

#include "memloop/errors.h"

namespace memloop {

namespace {

// "file:" URI of a path (https://sqlite.org/uri.html): every byte but unreserved ones and '/'
// percent-encoded, so that '?', '#' and '%' in a file name stay part of it.
std::string ImmutableUri(const std::string& path) {
  std::string uri = "file:";
  for (const unsigned char c : path) {
    if (std::isalnum(c) || c == '/' || c == '-' || c == '_' || c == '.' || c == '~') {
      uri += static_cast<char>(c);
    } else {
      static const char kHex[] = "0123456789ABCDEF";
      uri += '%';
      uri += kHex[c >> 4];
      uri += kHex[c & 15];
    }
  }
  return uri + "?immutable=1";
}

}  // namespace

SqliteConnection::SqliteConnection(const std::string& path, int flags, bool immutable)
    : path_(path) {
  const int code = immutable ? sqlite3_open_v2(ImmutableUri(path).c_str(), &db_,
                                               flags | SQLITE_OPEN_URI, nullptr)
                             : sqlite3_open_v2(path.c_str(), &db_, flags, nullptr);
  if (code != SQLITE_OK) {
    const std::string message = db_ ? sqlite3_errmsg(db_) : sqlite3_errstr(code);
    sqlite3_close(db_);
    db_ = nullptr;
    throw DatabaseError(path, "cannot open the map database (" + message + ")");
  }
  sqlite3_busy_timeout(db_, 10000);  // the writer thread's transactions are short
}

SqliteConnection::~SqliteConnection() { sqlite3_close(db_); }

std::unique_ptr<SqlStatement> SqliteConnection::Prepare(const std::string& sql) {
  return std::make_unique<SqliteStatement>(*this, sql);
}

void SqliteConnection::Execute(const std::string& sql) {
  char* error = nullptr;
  const int code = sqlite3_exec(db_, sql.c_str(), nullptr, nullptr, &error);
  const std::string message = error ? error : "";
  sqlite3_free(error);
  // The SQL stays out of the message: it is the user's file, not the statement, that is at fault.
  if (code != SQLITE_OK) throw DatabaseError(path_, "SQLite: " + message);
}

void SqliteConnection::Check(int code, const std::string& what) const {
  if (code == SQLITE_OK || code == SQLITE_ROW || code == SQLITE_DONE) return;
  throw DatabaseError(path_, what + " (SQLite: " + sqlite3_errmsg(db_) + ")");
}

SqliteStatement::SqliteStatement(const SqliteConnection& connection, const std::string& sql)
    : connection_(connection) {
  connection_.Check(sqlite3_prepare_v2(connection.handle(), sql.c_str(), -1, &statement_, nullptr),
                    "cannot read the file");
}

SqliteStatement::~SqliteStatement() { sqlite3_finalize(statement_); }

SqliteStatement& SqliteStatement::Bind(int index, long long value) {
  connection_.Check(sqlite3_bind_int64(statement_, index, value), "bind");
  return *this;
}

SqliteStatement& SqliteStatement::Bind(int index, double value) {
  connection_.Check(sqlite3_bind_double(statement_, index, value), "bind");
  return *this;
}

SqliteStatement& SqliteStatement::Bind(int index, const std::string& value) {
  connection_.Check(sqlite3_bind_text(statement_, index, value.c_str(), -1, SQLITE_TRANSIENT),
                    "bind");
  return *this;
}

SqliteStatement& SqliteStatement::BindBlob(int index, const void* data, int bytes) {
  // An empty blob is a zero-length blob, not NULL (what sqlite3_bind_blob makes of a null pointer).
  const int code = bytes == 0 ? sqlite3_bind_zeroblob(statement_, index, 0)
                              : sqlite3_bind_blob(statement_, index, data, bytes, SQLITE_TRANSIENT);
  connection_.Check(code, "bind");
  return *this;
}

SqliteStatement& SqliteStatement::BindNull(int index) {
  connection_.Check(sqlite3_bind_null(statement_, index), "bind");
  return *this;
}

bool SqliteStatement::Step() {
  const int code = sqlite3_step(statement_);
  connection_.Check(code, "cannot read or write the file");
  return code == SQLITE_ROW;
}

void SqliteStatement::Run() {
  while (Step()) {
  }
  Reset();
}

void SqliteStatement::Reset() {
  sqlite3_reset(statement_);
  sqlite3_clear_bindings(statement_);
}

long long SqliteStatement::Int(int column) const {
  return sqlite3_column_int64(statement_, column);
}

double SqliteStatement::Double(int column) const {
  return sqlite3_column_double(statement_, column);
}

bool SqliteStatement::IsNull(int column) const {
  return sqlite3_column_type(statement_, column) == SQLITE_NULL;
}

std::string SqliteStatement::Text(int column) const {
  const unsigned char* text = sqlite3_column_text(statement_, column);
  return text ? reinterpret_cast<const char*>(text) : "";
}

std::vector<unsigned char> SqliteStatement::Blob(int column) const {
  const int bytes = sqlite3_column_bytes(statement_, column);
  std::vector<unsigned char> values(bytes);
  if (bytes > 0) std::memcpy(values.data(), sqlite3_column_blob(statement_, column), bytes);
  return values;
}

}  // namespace memloop
