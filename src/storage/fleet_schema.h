// A fleet's map on a PostgreSQL server: the tables of the SQLite map file, each with a `robot`
// column (the database role that wrote the row) first in its key. Each robot connects as its
// own role, a member of memloop_robots; row-level security lets it read every robot's rows and
// write only its own. Through the views of the schema memloop_own (rows of the connected
// robot), the detector's SQL is the SQLite file's.
#pragma once

#include <string>
#include <vector>

#include "memloop/fleet.h"

namespace memloop {

inline constexpr const char* kFleetSchema = "memloop";        // every robot's rows
inline constexpr const char* kOwnRowsSchema = "memloop_own";  // the connected robot's
inline constexpr const char* kRobotsRole = "memloop_robots";

// The statements InitFleet (memloop/fleet.h) runs first, in order; then it adds the robots'
// roles (with no password: the server's pg_hba.conf says how each authenticates, and ALTER ROLE
// ... PASSWORD sets one).
std::vector<std::string> FleetSchemaStatements();

}  // namespace memloop
