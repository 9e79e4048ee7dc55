// What the Long-Term Memory's SQL needs of a database, whichever holds the map: the SQLite file
// of one robot (sqlite_statement.h) or a PostgreSQL server that a fleet shares
// (postgres_connection.h). Statements are written in SQLite's dialect; the server's connection
// translates the few forms that differ.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "memloop/errors.h"

namespace memloop {

class SqlStatement {
 public:
  virtual ~SqlStatement() = default;
  // Parameters count from 1, columns from 0, as in SQLite.
  virtual SqlStatement& Bind(int index, long long value) = 0;
  virtual SqlStatement& Bind(int index, double value) = 0;
  virtual SqlStatement& Bind(int index, const std::string& value) = 0;
  virtual SqlStatement& BindBlob(int index, const void* data, int bytes) = 0;
  virtual SqlStatement& BindNull(int index) = 0;
  // True while a row is available.
  virtual bool Step() = 0;
  // Runs to completion and resets, for statements without result rows.
  virtual void Run() = 0;
  virtual void Reset() = 0;

  virtual long long Int(int column) const = 0;
  virtual double Double(int column) const = 0;
  virtual bool IsNull(int column) const = 0;
  virtual std::string Text(int column) const = 0;
  virtual std::vector<unsigned char> Blob(int column) const = 0;
};

// The connection to a map's server broke (the server restarted, the network went): what was not
// committed is lost, and Reconnect() may bring the connection back.
class ServerConnectionLost : public DatabaseError {
 public:
  using DatabaseError::DatabaseError;
};

class SqlConnection {
 public:
  virtual ~SqlConnection() = default;
  // One or more statements without parameters or results.
  virtual void Execute(const std::string& sql) = 0;
  // A statement that sets up the session (a setting, a lock): run now, and again by Reconnect.
  virtual void Setup(const std::string& sql) { Execute(sql); }
  // After ServerConnectionLost: connects again, waiting for the server up to a bound, with the
  // session set up and the statements prepared as before; returns the seconds it waited. Throws
  // DatabaseError when the server does not come back (or, for a file, at once).
  virtual double Reconnect() { throw DatabaseError(path(), "the map's connection broke"); }
  virtual std::unique_ptr<SqlStatement> Prepare(const std::string& sql) = 0;
  // How errors name the map: a file's path, or a server's URI without its password.
  virtual const std::string& path() const = 0;
};

// True when `map` names a map on a PostgreSQL server (a libpq URI) rather than a file.
inline bool IsServerMap(const std::string& map) {
  return map.rfind("postgresql://", 0) == 0 || map.rfind("postgres://", 0) == 0;
}

}  // namespace memloop
