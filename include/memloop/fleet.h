// Many robots, one map: the Long-Term Memory of a fleet on a PostgreSQL server. A map is named
// by a libpq URI (postgresql://ROBOT@HOST/DBNAME) wherever a map file is: `Detector`,
// `memloop run --db`, inspect, export, view. Each robot connects as its own database role and
// its map is its rows of the fleet's tables; it reads every robot's rows and may write only its
// own (row-level security). docs/fleet.md says how to set a server up.
#pragma once

#include <string>
#include <vector>

namespace memloop {

// Prepares the database `uri` names for a fleet (idempotent): the tables, their row-level
// security policies, the role memloop_robots, and a login role for each of `robots` that lacks
// one. `uri` connects as a role that may create schemas and roles (the database's owner with
// CREATEROLE, or a superuser). Throws DatabaseError naming the URI (without its password).
void InitFleet(const std::string& uri, const std::vector<std::string>& robots);

// `uri` connecting as `robot` (its database role): the URI's user when it names one (then
// `robot`, if given, must be the same: InputError otherwise), else `robot` added as the URI's
// `user` parameter. `robot` empty: `uri` as it is.
std::string RobotMapUri(const std::string& uri, const std::string& robot);

}  // namespace memloop
