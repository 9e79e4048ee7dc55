// The fleet tests' server and fixture: one PostgreSQL server (postgres_server.h) for the tests
// of the process, and a fresh fleet database per test.
#pragma once

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "memloop/fleet.h"
#include "postgres_server.h"

namespace memloop::testing {

// One server for the tests of this process (initdb takes a second or two), stopped at its exit.
inline PostgresServer& Server() {
  static PostgresServer server;
  return server;
}

class FleetTest : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!Server().why_not().empty()) GTEST_SKIP() << Server().why_not();
  }
  // A fresh database prepared for a fleet of `robots`.
  std::string NewFleet(const std::string& name, const std::vector<std::string>& robots) {
    Server().Admin("postgres", "DROP DATABASE IF EXISTS " + name);
    Server().Admin("postgres", "CREATE DATABASE " + name);
    InitFleet(Server().Uri(PostgresServer::kAdmin, name), robots);
    return name;
  }
};

}  // namespace memloop::testing
