// A PostgreSQL server of the test's own: initdb and pg_ctl on a private folder, listening on a
// Unix socket in it and, with TLS only (a self-signed certificate made here), on a free TCP port
// of 127.0.0.1, removed with everything in it at the end. As root (CI),
// the server runs as the user postgres (initdb refuses root). Debian's postgresql-15 package
// provides the programs (make test installs it). A watchman process stops the server and removes
// the folder should the test process die without doing it (a crash, a kill -9, a timeout).
#pragma once

#include <libpq-fe.h>
#include <netinet/in.h>
#include <pwd.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>

#include "cli_helpers.h"
#include "temp_dir.h"

namespace memloop::testing {

class PostgresServer {
 public:
  static constexpr const char* kAdmin = "memloop_admin";

  PostgresServer() {
    for (const char* version : {"15", "16", "17"}) {
      const std::string bin = std::string("/usr/lib/postgresql/") + version + "/bin";
      if (bin_.empty() && std::filesystem::exists(bin + "/initdb")) bin_ = bin;
    }
    if (bin_.empty()) {
      why_not_ =
          "PostgreSQL's server is not installed (apt-get install postgresql-15; make test "
          "installs it)";
      return;
    }
    as_ = geteuid() == 0 ? "runuser -u postgres -- " : "";
    if (geteuid() == 0 && getpwnam("postgres") == nullptr) {
      why_not_ = "running as root without a postgres user to run the server as";
      return;
    }
    if (!as_.empty()) Shell("chown postgres " + folder_.path().string());
    const Outcome init =
        Shell(as_ + bin_ + "/initdb --no-sync --auth=trust -U " + kAdmin + " -D " + Data());
    if (init.exit_code != 0) throw std::runtime_error("initdb failed: " + init.output);
    // The robot pw_robot authenticates with a password (the refusal of a wrong one is tested);
    // over TCP, only TLS is accepted.
    const std::string hba = Data() + "/pg_hba.conf";
    const std::string rules =
        "local all pw_robot scram-sha-256\nhostnossl all all 0.0.0.0/0 reject\n"
        "hostssl all all 127.0.0.1/32 trust\n" +
        ReadBytes(hba);
    std::ofstream(hba) << rules;
    const Outcome certificate =
        Shell("cd " + Data() +
              " && openssl req -new -x509 -days 2 -nodes -subj /CN=localhost -newkey ec "
              "-pkeyopt ec_paramgen_curve:prime256v1 -keyout server.key -out server.crt && "
              "chmod 600 server.key" +
              (as_.empty() ? "" : " && chown postgres server.key server.crt"));
    if (certificate.exit_code != 0) {
      throw std::runtime_error("openssl could not make a certificate: " + certificate.output);
    }
    port_ = FreePort();
    Start();
    // The watchman: detached, it outlives a killed test process by at most a second.
    Shell("setsid sh -c 'while kill -0 " + std::to_string(getpid()) +
          " 2>/dev/null; do sleep 1; done; " + as_ + bin_ + "/pg_ctl -D " + Data() +
          " -m immediate stop; rm -rf " + folder_.path().string() + "' >/dev/null 2>&1 &");
    Admin("postgres", "CREATE DATABASE fleet");
  }
  ~PostgresServer() {
    if (!bin_.empty()) Shell(as_ + bin_ + "/pg_ctl -D " + Data() + " -m immediate stop");
  }
  PostgresServer(const PostgresServer&) = delete;
  PostgresServer& operator=(const PostgresServer&) = delete;

  // Empty when the server runs; else why there is none (the test is skipped, saying so).
  const std::string& why_not() const { return why_not_; }

  // fsync off: the tests stop the server cleanly or not at all, and CI's disk is shared.
  void Start() {
    const Outcome start =
        Shell(as_ + bin_ + "/pg_ctl -D " + Data() + " -l " + Data() + "/log -w -o \"-k " +
              folder_.path().string() + " -c listen_addresses=127.0.0.1 -p " +
              std::to_string(port_) + " -c ssl=on -c fsync=off\" start");
    if (start.exit_code != 0) throw std::runtime_error("pg_ctl start failed: " + start.output);
  }
  void Stop() {
    const Outcome stop = Shell(as_ + bin_ + "/pg_ctl -D " + Data() + " -m fast -w stop");
    if (stop.exit_code != 0) throw std::runtime_error("pg_ctl stop failed: " + stop.output);
  }

  // A libpq URI of `database` connecting as `user` through the private socket.
  std::string Uri(const std::string& user, const std::string& database = "fleet") const {
    return "postgresql://" + (user.empty() ? "" : user + "@") + "/" + database +
           "?host=" + folder_.path().string() + "&port=" + std::to_string(port_);
  }
  // The same through TCP, where the server takes TLS only: libpq's default (sslmode=prefer)
  // uses it, as `parameters` (e.g. "sslmode=require") may insist.
  std::string TcpUri(const std::string& user, const std::string& database,
                     const std::string& parameters = "") const {
    return "postgresql://" + user + "@127.0.0.1:" + std::to_string(port_) + "/" + database +
           (parameters.empty() ? "" : "?" + parameters);
  }
  // The folder of the socket: a URI's host (the socket is named for the server's port).
  std::string SocketFolder() const { return folder_.path().string(); }

  // Runs `sql` as `user` on `database`; returns the first value of its result, the count of
  // rows changed for a command, or "ERROR: <message>" when the server refuses it.
  std::string Run(const std::string& user, const std::string& database,
                  const std::string& sql) const {
    return RunAt(Uri(user, database), sql);
  }
  std::string RunAt(const std::string& uri, const std::string& sql) const {
    PGconn* connection = PQconnectdb(uri.c_str());
    PQsetNoticeProcessor(
        connection, [](void*, const char*) {}, nullptr);
    std::string answer;
    if (PQstatus(connection) != CONNECTION_OK) {
      answer = std::string("ERROR: ") + PQerrorMessage(connection);
    } else {
      PGresult* result = PQexec(connection, sql.c_str());
      const ExecStatusType status = PQresultStatus(result);
      if (status == PGRES_TUPLES_OK && PQntuples(result) > 0) {
        answer = PQgetvalue(result, 0, 0);
      } else if (status != PGRES_TUPLES_OK && status != PGRES_COMMAND_OK) {
        answer = std::string("ERROR: ") + PQresultErrorMessage(result);
      } else if (status == PGRES_COMMAND_OK) {
        answer = PQcmdTuples(result);  // rows changed, "" for other commands
      }
      PQclear(result);
    }
    PQfinish(connection);
    return answer;
  }
  void Admin(const std::string& database, const std::string& sql) const {
    const std::string answer = Run(kAdmin, database, sql);
    if (answer.rfind("ERROR", 0) == 0) throw std::runtime_error(sql + ": " + answer);
  }

 private:
  std::string Data() const { return folder_.path().string() + "/data"; }
  // A TCP port of 127.0.0.1 no one listens on (the kernel's choice, released for the server).
  static int FreePort() {
    const int probe = socket(AF_INET, SOCK_STREAM, 0);
    sockaddr_in address{};
    address.sin_family = AF_INET;
    address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    socklen_t size = sizeof(address);
    if (bind(probe, reinterpret_cast<sockaddr*>(&address), size) != 0 ||
        getsockname(probe, reinterpret_cast<sockaddr*>(&address), &size) != 0) {
      close(probe);
      throw std::runtime_error("no free TCP port for the server");
    }
    close(probe);
    return ntohs(address.sin_port);
  }

  TempDir folder_;
  std::string bin_;
  std::string as_;
  std::string why_not_;
  int port_ = 0;
};

}  // namespace memloop::testing
