// A robot's map on a fleet's PostgreSQL server (fleet_schema.h): the checks of LtmDatabase's
// modes, and the robot's writer lock.
#include <string>

#include "memloop/errors.h"
#include "storage/fleet_schema.h"
#include "storage/ltm_database.h"

namespace memloop {

int LtmDatabase::OpenServerMap(Mode mode) {
  if (QueryNumber(std::string("SELECT count(*) FROM pg_namespace WHERE nspname='") +
                  kOwnRowsSchema + "'") == 0) {
    throw DatabaseError(path(),
                        "the database holds no memloop fleet: run `memloop fleet init` on it "
                        "first");
  }
  const std::string robot = [this] {
    auto& query = Cached("SELECT current_user");
    const std::string name = query.Step() ? query.Text(0) : "";
    query.Reset();
    return name;
  }();
  if (QueryNumber(std::string("SELECT count(*) FROM pg_roles WHERE pg_has_role(current_user, "
                              "oid, 'MEMBER') AND rolname='") +
                  kRobotsRole + "'") == 0) {
    throw DatabaseError(path(), "the role " + robot +
                                    " is not a robot of this fleet: add it with `memloop fleet "
                                    "init URI --robot " +
                                    robot + "`");
  }
  connection_->Setup(std::string("SET search_path = ") + kOwnRowsSchema);
  if (mode == Mode::kCreate || mode == Mode::kOpen) {
    // Session-level: the server releases it when this connection ends, a kill -9 included, and
    // it is taken again after a reconnection.
    connection_->Setup(
        "DO $$ BEGIN IF NOT pg_try_advisory_lock(hashtext('memloop robot ' || current_user)) "
        "THEN RAISE EXCEPTION 'robot %''s map is being written by another process (one run per "
        "robot at a time)', current_user; END IF; END $$");
  }
  if (mode == Mode::kRead || mode == Mode::kPeek) {
    connection_->Setup("SET default_transaction_read_only = on");
  }
  const std::string version = ReadInfo(kFormatKey);
  if (mode == Mode::kCreate) {
    if (!version.empty()) {
      throw DatabaseError(path(), "robot " + robot +
                                      " already has a map on this server; a run starts a new "
                                      "map (--resume goes on with it, --new-session adds a "
                                      "session to it)");
    }
    WriteInfo(kFormatKey, std::to_string(kFormatVersion));
    return kFormatVersion;
  }
  if (version.empty()) {
    throw DatabaseError(path(), "robot " + robot +
                                    " has no map on this server (a run without --resume starts "
                                    "one)");
  }
  if (std::stoi(version) > kFormatVersion) {
    throw DatabaseError(path(), "robot " + robot + "'s map has format " + version +
                                    ", newer than this memloop's (" +
                                    std::to_string(kFormatVersion) + "): upgrade memloop");
  }
  return std::stoi(version);
}

}  // namespace memloop
