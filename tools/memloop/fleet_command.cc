// memloop fleet init URI [--robot NAME ...]: a PostgreSQL database made ready for a fleet's map.
#include <iostream>

#include "commands.h"
#include "memloop/fleet.h"
#include "storage/sql_connection.h"

namespace memloop::cli {

void AddFleetCommand(CLI::App& app) {
  CLI::App* fleet = app.add_subcommand("fleet",
                                       "A map that many robots share, on a PostgreSQL "
                                       "server (docs/fleet.md)");
  fleet->require_subcommand(1);
  struct Arguments {
    std::string uri;
    std::vector<std::string> robots;
  };
  auto arguments = std::make_shared<Arguments>();
  CLI::App* init = fleet->add_subcommand(
      "init",
      "Create the fleet's tables, their row-level security and the robots' roles in the "
      "database URI names (idempotent: a fleet's rows are kept)");
  init->add_option("uri", arguments->uri,
                   "postgresql://USER@HOST/DBNAME, connecting as a role that may create schemas "
                   "and roles")
      ->required()
      ->check([](const std::string& uri) {
        return IsServerMap(uri) ? std::string() : "not a postgresql:// URI: " + uri;
      });
  init->add_option("--robot", arguments->robots,
                   "A robot's name: its database role is created if missing (repeatable)");
  init->callback([arguments] {
    InitFleet(arguments->uri, arguments->robots);
    std::cout << "fleet ready in " << WithoutPassword(arguments->uri) << " ("
              << arguments->robots.size() << " robot role(s) added or kept)\n";
  });
}

}  // namespace memloop::cli
