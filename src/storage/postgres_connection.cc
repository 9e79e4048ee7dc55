#include "storage/postgres_connection.h"

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <regex>
#include <thread>

#include "memloop/errors.h"

namespace memloop {
namespace {

// PostgreSQL's type oids (pg_type.h) of the columns memloop reads.
constexpr Oid kBool = 16;
constexpr Oid kInt8 = 20;
constexpr Oid kInt2 = 21;
constexpr Oid kInt4 = 23;
constexpr Oid kFloat4 = 700;
constexpr Oid kFloat8 = 701;

std::string FirstLine(const char* message) {
  std::string line = message == nullptr ? "" : message;
  const size_t end = line.find('\n');
  if (end != std::string::npos) line.erase(end);
  if (line.rfind("ERROR:  ", 0) == 0 || line.rfind("FATAL:  ", 0) == 0) line.erase(0, 8);
  while (!line.empty() && std::isspace(static_cast<unsigned char>(line.back()))) line.pop_back();
  return line;
}

// A binary result's number: network byte order.
uint64_t BigEndian(const char* bytes, int count) {
  uint64_t value = 0;
  for (int i = 0; i < count; ++i) value = value << 8 | static_cast<unsigned char>(bytes[i]);
  return value;
}

class PostgresStatement : public SqlStatement {
 public:
  PostgresStatement(PostgresConnection& connection, std::string name, int parameters,
                    const std::string& sql)
      : connection_(connection),
        name_(std::move(name)),
        sql_(sql),
        batched_(sql.rfind("INSERT", 0) == 0 &&
                 sql.find("last_insert_rowid") == std::string::npos &&
                 sql.find(" VALUES(") != std::string::npos && sql.back() == ')'),
        begins_(sql == "BEGIN"),
        commits_(sql == "COMMIT"),
        values_(parameters),
        null_(parameters, true),
        binary_(parameters, 0) {}
  ~PostgresStatement() override { PQclear(result_); }

  SqlStatement& Bind(int index, long long value) override {
    return Set(index, std::to_string(value), false);
  }
  SqlStatement& Bind(int index, double value) override {
    char text[40];
    std::snprintf(text, sizeof(text), "%.17g", value);  // exact through text
    return Set(index, text, false);
  }
  SqlStatement& Bind(int index, const std::string& value) override {
    return Set(index, value, false);
  }
  SqlStatement& BindBlob(int index, const void* data, int bytes) override {
    return Set(index, std::string(static_cast<const char*>(data), bytes), true);
  }
  SqlStatement& BindNull(int index) override {
    Reset();
    null_.at(index - 1) = true;
    return *this;
  }

  bool Step() override {
    if (result_ == nullptr) Execute();
    return ++row_ < PQntuples(result_);
  }
  void Run() override {
    Reset();
    if (batched_) return connection_.AddRow(sql_, values_, null_, binary_);
    const Parameters parameters = Gather();
    connection_.Send(name_, parameters.values, lengths_, binary_);
    if (begins_) connection_.SetInTransaction(true);
    if (commits_) {
      connection_.Drain();  // the writer must know its transaction is in
      connection_.SetInTransaction(false);
    }
  }
  void Reset() override {
    PQclear(result_);
    result_ = nullptr;
    row_ = -1;
  }

  long long Int(int column) const override {
    const char* value = PQgetvalue(result_, row_, column);
    switch (PQftype(result_, column)) {
      case kInt8:
        return static_cast<long long>(BigEndian(value, 8));
      case kInt4:
        return static_cast<int32_t>(BigEndian(value, 4));
      case kInt2:
        return static_cast<int16_t>(BigEndian(value, 2));
      case kBool:
        return value[0] != 0;
      default:
        return static_cast<long long>(Double(column));
    }
  }
  double Double(int column) const override {
    const char* value = PQgetvalue(result_, row_, column);
    switch (PQftype(result_, column)) {
      case kFloat8: {
        const uint64_t bits = BigEndian(value, 8);
        double number;
        std::memcpy(&number, &bits, sizeof(number));
        return number;
      }
      case kFloat4: {
        const auto bits = static_cast<uint32_t>(BigEndian(value, 4));
        float number;
        std::memcpy(&number, &bits, sizeof(number));
        return number;
      }
      case kInt8:
      case kInt4:
      case kInt2:
      case kBool:
        return static_cast<double>(Int(column));
      default:
        throw DatabaseError(connection_.path(), "a column of an unexpected type (oid " +
                                                    std::to_string(PQftype(result_, column)) + ")");
    }
  }
  bool IsNull(int column) const override { return PQgetisnull(result_, row_, column) != 0; }
  std::string Text(int column) const override {
    return std::string(PQgetvalue(result_, row_, column), PQgetlength(result_, row_, column));
  }
  std::vector<unsigned char> Blob(int column) const override {
    const auto* bytes = reinterpret_cast<const unsigned char*>(PQgetvalue(result_, row_, column));
    return std::vector<unsigned char>(bytes, bytes + PQgetlength(result_, row_, column));
  }

 private:
  SqlStatement& Set(int index, std::string value, bool binary) {
    Reset();  // as sqlite3_bind after a step: the statement starts again
    values_.at(index - 1) = std::move(value);
    null_.at(index - 1) = false;
    binary_.at(index - 1) = binary ? 1 : 0;
    return *this;
  }
  struct Parameters {
    std::vector<const char*> values;
  };
  Parameters Gather() {
    Parameters parameters;
    lengths_.resize(values_.size());
    for (size_t i = 0; i < values_.size(); ++i) {
      parameters.values.push_back(null_[i] ? nullptr : values_[i].data());
      lengths_[i] = static_cast<int>(values_[i].size());
    }
    return parameters;
  }
  void Execute() {
    Reset();
    const Parameters parameters = Gather();
    result_ = connection_.Query(name_, parameters.values, lengths_, binary_);
  }

  PostgresConnection& connection_;
  std::string name_;
  std::string sql_;
  bool batched_;
  bool begins_;
  bool commits_;
  std::vector<int> lengths_;
  std::vector<std::string> values_;
  std::vector<bool> null_;
  std::vector<int> binary_;
  PGresult* result_ = nullptr;
  int row_ = -1;
};

// Parameters: '?' is the next number, '?N' is N (as SQLite numbers them). Quoted text is kept.
std::string NumberParameters(const std::string& sql, int& count) {
  std::string out;
  bool quoted = false;
  count = 0;
  for (size_t i = 0; i < sql.size(); ++i) {
    const char c = sql[i];
    if (c == '\'') quoted = !quoted;
    if (c != '?' || quoted) {
      out += c;
      continue;
    }
    size_t end = i + 1;
    while (end < sql.size() && std::isdigit(static_cast<unsigned char>(sql[end]))) ++end;
    int number = ++count;
    if (end > i + 1) {
      number = std::stoi(sql.substr(i + 1, end - i - 1));
      count = std::max(count - 1, number);
    }
    out += "$" + std::to_string(number);
    i = end - 1;
  }
  return out;
}

}  // namespace

std::string ToPostgresDialect(const std::string& sql) {
  int count = 0;
  std::string out = NumberParameters(sql, count);
  static const std::regex kIgnore(R"(^INSERT OR IGNORE INTO (.*)$)");
  static const std::regex kReplace(R"(^INSERT OR REPLACE INTO (\w+)\(([^)]*)\)(.*)$)");
  std::smatch match;
  if (std::regex_match(out, match, kIgnore)) {
    out = "INSERT INTO " + match[1].str() + " ON CONFLICT DO NOTHING";
  } else if (std::regex_match(out, match, kReplace)) {
    std::vector<std::string> columns;
    const std::string list = match[2].str();
    for (size_t begin = 0; begin <= list.size();) {
      size_t end = list.find(',', begin);
      if (end == std::string::npos) end = list.size();
      std::string column = list.substr(begin, end - begin);
      column.erase(0, column.find_first_not_of(' '));
      columns.push_back(column);
      begin = end + 1;
    }
    out = "INSERT INTO " + match[1].str() + "(" + list + ")" + match[3].str() +
          " ON CONFLICT (robot, " + columns[0] + ") DO UPDATE SET ";
    for (size_t k = 1; k < columns.size(); ++k) {
      out += (k > 1 ? ", " : "") + columns[k] + "=EXCLUDED." + columns[k];
    }
  }
  static const std::regex kLastRow(R"(last_insert_rowid\(\))");
  return std::regex_replace(out, kLastRow, "lastval()");
}

PostgresConnection::PostgresConnection(const std::string& uri)
    : name_(WithoutPassword(uri)), uri_(uri) {
  connection_ = PQconnectdb(uri.c_str());
  if (PQstatus(connection_) != CONNECTION_OK) {
    std::string message = PQerrorMessage(connection_);
    PQfinish(connection_);
    connection_ = nullptr;
    // libpq: 'connection to server on socket "..." failed: <why>'; the why is the news.
    const size_t failed = message.find("failed: ");
    if (failed != std::string::npos) message.erase(0, failed + 8);
    throw DatabaseError(name_, "cannot connect to the server: " + FirstLine(message.c_str()));
  }
  PQsetNoticeProcessor(
      connection_, [](void*, const char*) {}, nullptr);  // "already exists"
  PQenterPipelineMode(connection_);
}

PostgresConnection::~PostgresConnection() { PQfinish(connection_); }

template <typename Work>
PGresult* PostgresConnection::Synchronously(Work work) {
  Drain();
  PQexitPipelineMode(connection_);
  PGresult* result = work();
  PQenterPipelineMode(connection_);
  return result;
}

void PostgresConnection::AddRow(const std::string& sql, const std::vector<std::string>& values,
                                const std::vector<bool>& nulls, const std::vector<int>& binary) {
  // A row of another statement, or (INSERT OR REPLACE) of a key held: ON CONFLICT cannot update
  // a row twice in one statement.
  const bool replaces = sql.rfind("INSERT OR REPLACE", 0) == 0;
  if (batch_.rows > 0 &&
      (batch_.sql != sql || (replaces && std::find(batch_.keys.begin(), batch_.keys.end(),
                                                   values[0]) != batch_.keys.end()))) {
    FlushRows();
  }
  batch_.sql = sql;
  batch_.replaces = replaces;
  batch_.values.insert(batch_.values.end(), values.begin(), values.end());
  batch_.nulls.insert(batch_.nulls.end(), nulls.begin(), nulls.end());
  batch_.binary.insert(batch_.binary.end(), binary.begin(), binary.end());
  if (replaces) batch_.keys.push_back(values[0]);
  if (++batch_.rows == kBatchRows) FlushRows();
}

const std::string& PostgresConnection::RowsStatement(const std::string& sql, int rows) {
  auto found = row_statements_.find({sql, rows});
  if (found != row_statements_.end()) return found->second;
  const std::string tuple = sql.substr(sql.find(" VALUES(") + 7);
  std::string text = sql;
  for (int row = 1; row < rows; ++row) text += "," + tuple;
  const std::string name = "memloop_" + std::to_string(statements_++);
  const std::string translated = ToPostgresDialect(text);
  Consume(Synchronously(
              [&] { return PQprepare(connection_, name.c_str(), translated.c_str(), 0, nullptr); }),
          "the server refused a statement");
  texts_.emplace_back(name, translated);
  return row_statements_.emplace(std::make_pair(sql, rows), name).first->second;
}

void PostgresConnection::FlushRows() {
  if (batch_.rows == 0) return;
  const RowBatch batch = std::move(batch_);  // RowsStatement drains: it must find none held
  batch_ = RowBatch();
  const size_t per_row = batch.values.size() / batch.rows;
  for (int done = 0; done < batch.rows;) {
    int rows = kBatchRows;
    while (rows > batch.rows - done) rows /= 2;
    const std::string& name = RowsStatement(batch.sql, rows);
    std::vector<const char*> values;
    std::vector<int> lengths;
    const size_t first = done * per_row;
    const size_t end = first + rows * per_row;
    for (size_t k = first; k < end; ++k) {
      values.push_back(batch.nulls[k] ? nullptr : batch.values[k].data());
      lengths.push_back(static_cast<int>(batch.values[k].size()));
    }
    const std::vector<int> binary(batch.binary.begin() + first, batch.binary.begin() + end);
    SendNow(name, values, lengths, binary);
    done += rows;
  }
}

void PostgresConnection::Send(const std::string& name, const std::vector<const char*>& values,
                              const std::vector<int>& lengths, const std::vector<int>& binary) {
  FlushRows();
  SendNow(name, values, lengths, binary);
}

void PostgresConnection::SendNow(const std::string& name, const std::vector<const char*>& values,
                                 const std::vector<int>& lengths, const std::vector<int>& binary) {
  if (PQsendQueryPrepared(connection_, name.c_str(), static_cast<int>(values.size()), values.data(),
                          lengths.data(), binary.data(), 1) == 0) {
    ThrowFailure("cannot send a statement", ErrorOf(nullptr));
  }
  if (++unanswered_ >= kMaxUnanswered) Drain();
}

PGresult* PostgresConnection::Query(const std::string& name, const std::vector<const char*>& values,
                                    const std::vector<int>& lengths,
                                    const std::vector<int>& binary) {
  try {
    return QueryOnce(name, values, lengths, binary);
  } catch (const ServerConnectionLost&) {
    if (in_transaction_) throw;  // the transaction's writes are gone: its owner redoes them
    Reconnect();
    return QueryOnce(name, values, lengths, binary);
  }
}

PGresult* PostgresConnection::QueryOnce(const std::string& name,
                                        const std::vector<const char*>& values,
                                        const std::vector<int>& lengths,
                                        const std::vector<int>& binary) {
  Drain();  // the rows held, then every answer
  if (PQsendQueryPrepared(connection_, name.c_str(), static_cast<int>(values.size()), values.data(),
                          lengths.data(), binary.data(), 1) == 0 ||
      PQpipelineSync(connection_) == 0) {
    ThrowFailure("cannot send a statement", ErrorOf(nullptr));
  }
  PGresult* result = PQgetResult(connection_);
  ReadUntilSync();  // the end of its results, then the synchronisation point
  try {
    Check(result, "a statement failed");
  } catch (...) {
    PQclear(result);
    throw;
  }
  return result;
}

std::string PostgresConnection::ReadUntilSync() {
  std::string first_error;
  while (PQstatus(connection_) != CONNECTION_BAD) {
    PGresult* result = PQgetResult(connection_);
    if (result == nullptr) continue;  // the end of one statement's results
    const ExecStatusType status = PQresultStatus(result);
    if (status == PGRES_FATAL_ERROR && first_error.empty()) first_error = ErrorOf(result);
    PQclear(result);
    if (status == PGRES_PIPELINE_SYNC) break;
  }
  if (PQstatus(connection_) == CONNECTION_BAD && first_error.empty()) {
    first_error = ErrorOf(nullptr);
  }
  return first_error;
}

void PostgresConnection::Drain() {
  FlushRows();
  if (unanswered_ == 0) return;
  unanswered_ = 0;
  if (PQpipelineSync(connection_) == 0) ThrowFailure("cannot reach the server", ErrorOf(nullptr));
  const std::string first_error = ReadUntilSync();
  if (!first_error.empty()) ThrowFailure("a statement failed", first_error);
}

void PostgresConnection::ThrowFailure(const std::string& what, const std::string& message) const {
  const std::string text = what + " (PostgreSQL: " + message + ")";
  if (PQstatus(connection_) == CONNECTION_BAD) throw ServerConnectionLost(name_, text);
  throw DatabaseError(name_, text);
}

double PostgresConnection::Reconnect() {
  const auto start = std::chrono::steady_clock::now();
  const auto waited = [&start] {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  };
  unanswered_ = 0;
  in_transaction_ = false;
  batch_ = RowBatch();  // the transaction they were part of is gone
  for (;;) {
    PQreset(connection_);
    if (PQstatus(connection_) == CONNECTION_OK) break;
    if (waited() > kMaxOutageSeconds) {
      throw DatabaseError(name_, "the server has been unreachable for " +
                                     std::to_string(static_cast<int>(kMaxOutageSeconds)) + " s (" +
                                     ErrorOf(nullptr) + ")");
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
  }
  PQsetNoticeProcessor(
      connection_, [](void*, const char*) {}, nullptr);
  PQenterPipelineMode(connection_);
  const std::vector<std::string> setup = std::move(setup_);
  for (const std::string& sql : setup) Setup(sql);
  for (const auto& [name, text] : texts_) {
    Consume(Synchronously(
                [&] { return PQprepare(connection_, name.c_str(), text.c_str(), 0, nullptr); }),
            "cannot prepare a statement again");
  }
  return waited();
}

std::string PostgresConnection::ErrorOf(const PGresult* result) const {
  const char* message = result ? PQresultErrorMessage(result) : PQerrorMessage(connection_);
  return FirstLine(message != nullptr && *message ? message : PQerrorMessage(connection_));
}

void PostgresConnection::Check(const PGresult* result, const std::string& what) const {
  const ExecStatusType status = result ? PQresultStatus(result) : PGRES_FATAL_ERROR;
  if (status == PGRES_COMMAND_OK || status == PGRES_TUPLES_OK) return;
  ThrowFailure(what, ErrorOf(result));
}

void PostgresConnection::Setup(const std::string& sql) {
  PGresult* result = Synchronously([&] { return PQexec(connection_, sql.c_str()); });
  const ExecStatusType status = PQresultStatus(result);
  const std::string message = ErrorOf(result);
  PQclear(result);
  // The server's own words: a setup's refusal (the robot's lock taken) is the news.
  if (status != PGRES_COMMAND_OK && status != PGRES_TUPLES_OK) throw DatabaseError(name_, message);
  setup_.push_back(sql);
}

void PostgresConnection::Consume(PGresult* result, const std::string& what) const {
  const ExecStatusType status = PQresultStatus(result);
  const bool failed = status != PGRES_COMMAND_OK && status != PGRES_TUPLES_OK;
  const std::string message = failed ? ErrorOf(result) : "";
  PQclear(result);
  if (failed) ThrowFailure(what, message);
}

void PostgresConnection::Execute(const std::string& sql) {
  Consume(Synchronously([&] { return PQexec(connection_, sql.c_str()); }),
          "the server refused a statement");
}

std::unique_ptr<SqlStatement> PostgresConnection::Prepare(const std::string& sql) {
  int parameters = 0;
  NumberParameters(sql, parameters);
  const std::string name = "memloop_" + std::to_string(statements_++);
  const std::string text = ToPostgresDialect(sql);
  for (int attempt = 0;; ++attempt) {
    try {
      Consume(Synchronously(
                  [&] { return PQprepare(connection_, name.c_str(), text.c_str(), 0, nullptr); }),
              "the server refused a statement");
      break;
    } catch (const ServerConnectionLost&) {
      if (in_transaction_ || attempt > 0) throw;  // as Query
      Reconnect();
    }
  }
  texts_.emplace_back(name, text);
  return std::make_unique<PostgresStatement>(*this, name, parameters, sql);
}

}  // namespace memloop
