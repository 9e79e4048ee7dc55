// A PostgreSQL server's connection (libpq) for the Long-Term Memory's SQL (sql_connection.h):
// statements are prepared once on the server, numbers travel as text and blobs as bytes, and
// results come back in binary form. Statements without result rows (SqlStatement::Run) are sent
// without waiting for the server's answer (libpq's pipeline mode): a round trip each made the LTM
// writer 4x slower than the detector on the demo route. Their outcome is read before any
// statement with results, at each COMMIT (whose success is then known), and every
// kMaxUnanswered statements; an error is thrown then. Consecutive rows of one INSERT go as one
// statement of up to kBatchRows rows: the server's work per row, not the detector's, then bounds
// how fast a robot's map is written (x3 fewer of its CPU seconds per row).
#pragma once

#include <libpq-fe.h>

#include <map>
#include <string>
#include <vector>

#include "storage/sql_connection.h"

namespace memloop {

class PostgresConnection : public SqlConnection {
 public:
  // `uri`: libpq's connection URI (postgresql://[USER[:PASSWORD]@]HOST[:PORT]/DBNAME[?...]);
  // a password may also come from PGPASSWORD or ~/.pgpass, and TLS is used when the server
  // offers it (libpq's sslmode=prefer). Throws DatabaseError naming the URI without its
  // password, in one line: no server there, no such database, authentication refused.
  explicit PostgresConnection(const std::string& uri);
  ~PostgresConnection() override;

  void Execute(const std::string& sql) override;
  void Setup(const std::string& sql) override;
  double Reconnect() override;
  std::unique_ptr<SqlStatement> Prepare(const std::string& sql) override;
  const std::string& path() const override { return name_; }

  // The first line of the server's message for `result` (or of the connection's).
  std::string ErrorOf(const PGresult* result) const;
  // Throws DatabaseError "<uri>: <what> (PostgreSQL: <message>)" unless `result` succeeded;
  // ServerConnectionLost when the connection broke.
  void Check(const PGresult* result, const std::string& what) const;
  PGconn* handle() const { return connection_; }

  // For PostgresStatement: `name` with `values` (nullptr: NULL), sent without waiting
  // (Send), or run and answered (Query; the caller PQclears the result).
  void Send(const std::string& name, const std::vector<const char*>& values,
            const std::vector<int>& lengths, const std::vector<int>& binary);
  PGresult* Query(const std::string& name, const std::vector<const char*>& values,
                  const std::vector<int>& lengths, const std::vector<int>& binary);
  // Reads the answers of every statement sent; throws the first error among them.
  void Drain();
  // A row of the INSERT `sql` (SQLite's dialect, one VALUES tuple) prepared as `name`, with
  // its parameters: held back to go with the next rows of the same statement (FlushRows).
  void AddRow(const std::string& sql, const std::vector<std::string>& values,
              const std::vector<bool>& nulls, const std::vector<int>& binary);
  // BEGIN and COMMIT run: a statement with results is sent again after a reconnection only
  // outside a transaction (inside, what the transaction wrote is gone).
  void SetInTransaction(bool in_transaction) { in_transaction_ = in_transaction; }

  // How long Reconnect waits for the server: a restart takes seconds.
  static constexpr double kMaxOutageSeconds = 60;

 private:
  static constexpr int kMaxUnanswered = 1000;  // their answers stay far below a socket's buffer
  static constexpr int kBatchRows = 64;
  struct RowBatch {
    std::string sql;  // one row's statement; empty: no row held
    bool replaces = false;
    std::vector<std::string> values;  // the rows' parameters, one row after the other
    std::vector<bool> nulls;
    std::vector<int> binary;
    int rows = 0;
    std::vector<std::string> keys;  // INSERT OR REPLACE: the rows' first values
  };
  // Sends the rows held (as statements of 64, 32, ... 1 rows: few shapes to prepare).
  void FlushRows();
  void SendNow(const std::string& name, const std::vector<const char*>& values,
               const std::vector<int>& lengths, const std::vector<int>& binary);
  // The prepared statement of `rows` rows of `sql`.
  const std::string& RowsStatement(const std::string& sql, int rows);
  // Runs `work` (PQexec, PQprepare) out of pipeline mode, which refuses them.
  template <typename Work>
  PGresult* Synchronously(Work work);
  // Reads answers up to the pipeline's synchronisation point; the first error's message, or "".
  std::string ReadUntilSync();
  PGresult* QueryOnce(const std::string& name, const std::vector<const char*>& values,
                      const std::vector<int>& lengths, const std::vector<int>& binary);
  // Clears `result`; throws as Check when it failed.
  void Consume(PGresult* result, const std::string& what) const;
  // Throws ServerConnectionLost when the connection broke, else DatabaseError.
  [[noreturn]] void ThrowFailure(const std::string& what, const std::string& message) const;

  std::string name_;
  PGconn* connection_ = nullptr;
  int statements_ = 0;  // prepared so far: their names
  int unanswered_ = 0;  // sent, answers not read yet
  bool in_transaction_ = false;
  RowBatch batch_;
  std::map<std::pair<std::string, int>, std::string> row_statements_;
  std::string uri_;                                         // Reconnect's, with its password
  std::vector<std::string> setup_;                          // Setup's statements
  std::vector<std::pair<std::string, std::string>> texts_;  // prepared: name, text
};

// A statement in SQLite's dialect as PostgreSQL's: parameters ?, ?N become $N; INSERT OR IGNORE
// becomes ON CONFLICT DO NOTHING; INSERT OR REPLACE INTO t(key, c...) updates the row of
// (robot, key) on conflict (a fleet's tables are keyed by robot, then by the first column);
// last_insert_rowid() becomes lastval().
std::string ToPostgresDialect(const std::string& sql);

}  // namespace memloop
