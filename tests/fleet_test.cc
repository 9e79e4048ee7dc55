// A fleet's map on a real PostgreSQL server that the tests start (postgres_server.h): the same
// detector and map as on an SQLite file, a robot's rows guarded by the server, and one clear
// line for each way a server can refuse.
#include "memloop/fleet.h"

#include <gtest/gtest.h>
#include <sqlite3.h>

#include <atomic>
#include <functional>
#include <map>
#include <memory>
#include <set>
#include <thread>

#include "cli_helpers.h"
#include "fleet_fixture.h"
#include "memloop/detector.h"
#include "memloop/errors.h"
#include "memloop/map_info.h"
#include "memloop/synthetic_route.h"
#include "short_route.h"
#include "small_memory.h"
#include "storage/long_term_memory.h"

namespace memloop {
namespace {

using testing::FleetTest;
using testing::PostgresServer;
using testing::Server;

Options BudgetOptions() {
  Options options = Preset("default");
  options.memory.time_limit_ms = 0;
  options.memory.max_wm_locations = 30;  // transfers to LTM and retrievals from it
  return options;
}

struct RouteRun {
  std::vector<std::pair<ImageIndex, std::vector<ImageIndex>>> loop_closures;
  std::vector<int> retrieved;  // per image
  std::vector<std::string> notices;
};

// The demo route (260 images): with 30 locations in WM, it transfers and retrieves.
// `before_image(index)` runs before each image is processed; `images`: the first ones only.
RouteRun RunRoute(const std::string& map, MapMode mode = MapMode::kNew,
                  const std::function<void(int)>& before_image = nullptr, int images = 0) {
  const SyntheticRoute route;
  Detector detector(BudgetOptions(), map, mode);
  RouteRun run;
  for (int index = 0; index < (images > 0 ? images : route.size()); ++index) {
    if (before_image) before_image(index);
    const Result result = detector.Process(route.Render(index), index);
    run.notices.insert(run.notices.end(), result.map_notices.begin(), result.map_notices.end());
    run.retrieved.push_back(static_cast<int>(result.retrieved_ids.size()));
    if (result.HasLoopClosure()) {
      run.loop_closures.emplace_back(index, result.loop_closure_images);
    }
  }
  detector.Close();
  return run;
}

// The demo route on a map file, once for the tests that compare with it.
struct FileRun {
  testing::TempDir dir;
  RouteRun run = RunRoute(dir.File("map.db"));
  MapInfo info = InspectMap(dir.File("map.db"));
};
const FileRun& OnAFile() {
  static const FileRun file;
  return file;
}

TEST_F(FleetTest, OneRobotOnTheServerFindsWhatItFindsOnAFile) {
  const std::string fleet = NewFleet("same_as_file", {"r1"});
  const RouteRun& file = OnAFile().run;
  const RouteRun server = RunRoute(Server().Uri("r1", fleet));
  ASSERT_GT(file.loop_closures.size(), 5u);
  int retrievals = 0;
  for (int count : file.retrieved) retrievals += count;
  ASSERT_GT(retrievals, 0) << "the budget should bring locations back from LTM";
  EXPECT_EQ(server.loop_closures, file.loop_closures);
  EXPECT_EQ(server.retrieved, file.retrieved);

  const MapInfo& on_file = OnAFile().info;
  const MapInfo on_server = InspectMap(Server().Uri("r1", fleet));
  EXPECT_EQ(on_server.integrity, "ok");
  EXPECT_EQ(on_server.locations, on_file.locations);
  EXPECT_EQ(on_server.words, on_file.words);
  EXPECT_EQ(on_server.neighbour_links, on_file.neighbour_links);
  EXPECT_EQ(on_server.loop_closure_links, on_file.loop_closure_links);
  EXPECT_EQ(on_server.loop_closures.size(), on_file.loop_closures.size());
  EXPECT_EQ(on_server.parameters, on_file.parameters);
}

// Table -> its columns, of an SQLite map file.
std::map<std::string, std::set<std::string>> FileColumns(const std::string& path) {
  sqlite3* db = nullptr;
  sqlite3_open_v2(path.c_str(), &db, SQLITE_OPEN_READONLY, nullptr);
  std::map<std::string, std::set<std::string>> columns;
  sqlite3_stmt* query = nullptr;
  sqlite3_prepare_v2(db,
                     "SELECT m.name, p.name FROM sqlite_master m, pragma_table_info(m.name) p "
                     "WHERE m.type='table'",
                     -1, &query, nullptr);
  while (sqlite3_step(query) == SQLITE_ROW) {
    columns[reinterpret_cast<const char*>(sqlite3_column_text(query, 0))].insert(
        reinterpret_cast<const char*>(sqlite3_column_text(query, 1)));
  }
  sqlite3_finalize(query);
  sqlite3_close(db);
  return columns;
}

TEST_F(FleetTest, TheFleetHoldsEveryTableAndColumnOfAMapFile) {
  const std::string fleet = NewFleet("tables", {"r1"});
  testing::TempDir dir;
  {
    Detector detector(BudgetOptions(), dir.File("map.db"));
    detector.Process(SyntheticRoute().Render(0), 0);
    detector.Close();
  }
  auto file = FileColumns(dir.File("map.db"));
  file["loop_closures"].insert("rowid");  // SQLite's implicit key, a column on the server
  ASSERT_GT(file.size(), 15u);
  for (const auto& [table, columns] : file) {
    std::string list;
    for (const std::string& column : columns) list += (list.empty() ? "" : ",") + column;
    const std::string server = Server().Run(
        "r1", fleet,
        "SELECT string_agg(column_name, ',' ORDER BY column_name COLLATE \"C\") FROM "
        "information_schema.columns WHERE table_schema='memloop_own' AND table_name='" +
            table + "' AND column_name <> 'robot'");
    EXPECT_EQ(server, list) << "table " << table;
  }
}

TEST_F(FleetTest, ARobotReadsEveryRobotsRowsAndChangesOnlyItsOwn) {
  const std::string fleet = NewFleet("guarded", {"r1", "r2"});
  RunRoute(Server().Uri("r1", fleet), MapMode::kNew, nullptr, 60);
  const std::string r1_rows = Server().Run("r2", fleet,
                                           "SELECT count(*) FROM memloop.locations WHERE "
                                           "robot='r1'");
  ASSERT_GT(std::stoi(r1_rows), 10);  // r2 reads r1's rows
  // The server refuses a row written in r1's name, and r1's rows are out of reach of r2's
  // updates and deletes (row-level security filters them: 0 rows changed).
  EXPECT_TRUE(Contains(Server().Run("r2", fleet,
                                    "INSERT INTO memloop.locations(robot, id, weight) "
                                    "VALUES('r1', 100000, 1)"),
                       "violates row-level security policy"));
  EXPECT_EQ(
      Server().Run("r2", fleet, "UPDATE memloop.locations SET weight=weight+1 WHERE robot='r1'"),
      "0");
  EXPECT_EQ(Server().Run("r2", fleet, "DELETE FROM memloop.words WHERE robot='r1'"), "0");
  EXPECT_EQ(Server().Run("r2", fleet, "SELECT count(*) FROM memloop.locations WHERE robot='r1'"),
            r1_rows);
  // Through the views a robot sees its own map only: r2 has none.
  EXPECT_EQ(Server().Run("r2", fleet, "SELECT count(*) FROM memloop_own.locations"), "0");
  // r2 writes its own rows.
  EXPECT_EQ(
      Server().Run("r2", fleet, "INSERT INTO memloop.info(key, value) VALUES('note', 'mine')"),
      "1");
}

TEST_F(FleetTest, FleetInitIsIdempotentAndKeepsTheRows) {
  const std::string fleet = NewFleet("twice", {"r1"});
  RunRoute(Server().Uri("r1", fleet), MapMode::kNew, nullptr, 60);
  const std::string rows =
      Server().Run("r1", fleet, "SELECT count(*) FROM memloop.signature_words");
  InitFleet(Server().Uri(PostgresServer::kAdmin, fleet), {"r1", "r2"});
  EXPECT_EQ(Server().Run("r1", fleet, "SELECT count(*) FROM memloop.signature_words"), rows);
  EXPECT_EQ(Server().Run("r2", fleet, "SELECT count(*) FROM memloop_own.locations"),
            "0");  // a robot now
}

TEST_F(FleetTest, EachWayToBeRefusedIsOneClearLine) {
  const std::string fleet = NewFleet("refusals", {"r1", "pw_robot"});
  Server().Admin(fleet, "ALTER ROLE pw_robot PASSWORD 'right'");
  Server().Admin(fleet, "CREATE ROLE stranger LOGIN");
  Server().Admin("postgres", "DROP DATABASE IF EXISTS bare");
  Server().Admin("postgres", "CREATE DATABASE bare");
  const auto refusal = [](const std::string& map, MapMode mode = MapMode::kNew) {
    try {
      Detector detector(BudgetOptions(), map, mode);
    } catch (const DatabaseError& error) {
      return std::string(error.what());
    }
    return std::string("accepted");
  };
  const std::string socket = Server().SocketFolder();
  const struct {
    std::string map;
    std::string says;
  } cases[] = {
      {"postgresql:///fleet?host=" + socket + "/absent", "cannot connect to the server"},
      {Server().Uri("r1", "no_such_database"), "database \"no_such_database\" does not exist"},
      {Server().Uri("pw_robot:wrong", fleet),
       "password authentication failed for user \"pw_robot\""},
      {Server().Uri("r1", "bare"), "holds no memloop fleet: run `memloop fleet init`"},
      {Server().Uri("stranger", fleet), "the role stranger is not a robot of this fleet"},
  };
  for (const auto& [map, says] : cases) {
    const std::string message = refusal(map);
    EXPECT_TRUE(Contains(message, says)) << map << ": " << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
    EXPECT_FALSE(Contains(message, "wrong")) << "the password is shown: " << message;
  }
  EXPECT_EQ(refusal(Server().Uri("pw_robot:right", fleet)), "accepted");
  EXPECT_TRUE(Contains(refusal(Server().Uri("r1", fleet), MapMode::kResume),
                       "robot r1 has no map on this server"));
  {
    Detector writing(BudgetOptions(), Server().Uri("r1", fleet));
    EXPECT_TRUE(Contains(refusal(Server().Uri("r1", fleet), MapMode::kResume),
                         "robot r1's map is being written by another process"));
  }
  EXPECT_TRUE(Contains(refusal(Server().Uri("r1", fleet)), "robot r1 already has a map"));
}

// The server restarts while the robot runs: its writes wait in memory, its reads wait for the
// server, and the map ends as an uninterrupted run's, saying what happened.
TEST_F(FleetTest, AServerRestartMidRunLosesNothing) {
  const std::string fleet = NewFleet("restarted", {"r1"});
  const RouteRun& file = OnAFile().run;
  std::thread restart;
  const RouteRun server = RunRoute(Server().Uri("r1", fleet), MapMode::kNew, [&](int index) {
    if (index == 80) {
      restart = std::thread([] {
        Server().Stop();
        std::this_thread::sleep_for(std::chrono::seconds(1));
        Server().Start();
      });
    }
    if (index == 140) restart.join();  // the outage falls within the run
  });
  EXPECT_EQ(server.loop_closures, file.loop_closures);
  EXPECT_EQ(server.retrieved, file.retrieved);
  ASSERT_FALSE(server.notices.empty()) << "the restart went unnoticed";
  EXPECT_TRUE(Contains(server.notices.back(), "reconnected to the server after"))
      << server.notices.back();
  const MapInfo& on_file = OnAFile().info;
  const MapInfo on_server = InspectMap(Server().Uri("r1", fleet));
  EXPECT_EQ(on_server.integrity, "ok");
  EXPECT_EQ(on_server.locations, on_file.locations);
  EXPECT_EQ(on_server.words, on_file.words);
  EXPECT_EQ(on_server.neighbour_links + on_server.loop_closure_links,
            on_file.neighbour_links + on_file.loop_closure_links);
  EXPECT_EQ(on_server.loop_closures.size(), on_file.loop_closures.size());
  EXPECT_EQ(on_server.last_image, on_file.last_image);
}

// Away too long: once the queued writes reach their bound, the robot stops; the server back, its
// map holds every location up to its last checkpoint and none after.
TEST_F(FleetTest, AServerAwayPastTheQueueBoundStopsTheRunAtItsLastCheckpoint) {
  const std::string fleet = NewFleet("away", {"r1"});
  LtmOptions options;
  options.max_pending_bytes = 64 << 10;
  CheckpointData checkpoint;
  checkpoint.full = true;
  checkpoint.state = {{"marker", {1, 2, 3}}};
  LocationId checkpointed = 1;
  {
    LongTermMemory ltm(Server().Uri("r1", fleet), LtmDatabase::Mode::kCreate, options);
    ltm.Store(testing::MakeLtmLocation(1, {1, 2, 3}));
    ltm.Checkpoint(checkpoint);
    ltm.Flush();
    Server().Stop();
    std::string stopped;
    try {
      for (LocationId id = 2; id < 100000; ++id) {
        ltm.Store(testing::MakeLtmLocation(id, std::vector<WordId>(50, id)));
        if (id % 10 == 0) {
          ltm.Checkpoint(checkpoint);
          checkpointed = id;
        }
      }
    } catch (const DatabaseError& error) {
      stopped = error.what();
    }
    EXPECT_TRUE(Contains(stopped, "the run stops at its last committed checkpoint")) << stopped;
    ASSERT_GT(checkpointed, 10) << "the bound was reached before a checkpoint was queued";
    Server().Start();  // the writer commits the queued checkpoints as the map closes
  }
  std::vector<LocationId> expected;
  for (LocationId id = 1; id <= checkpointed; ++id) expected.push_back(id);
  LtmDatabase map(Server().Uri("r1", fleet), LtmDatabase::Mode::kRead);
  EXPECT_EQ(map.ReadLocationIds(), expected);
  EXPECT_EQ(map.ReadState("marker"), std::vector<unsigned char>({1, 2, 3}));
}

// Over TCP the server takes TLS only: a robot's map goes through it with libpq's default
// (sslmode=prefer: TLS when the server offers it) and when the URI insists on it.
TEST_F(FleetTest, ARobotsMapTravelsOverTls) {
  const std::string fleet = NewFleet("tls", {"r1"});
  EXPECT_EQ(Server().RunAt(Server().TcpUri("r1", fleet),
                           "SELECT ssl FROM pg_stat_ssl WHERE pid = pg_backend_pid()"),
            "t");
  testing::TempDir dir;
  SyntheticRoute(testing::ShortRoute()).Write(dir.path().string());
  const Outcome run = Memloop("run " + dir.File("images") + " --db '" +
                              Server().TcpUri("r1", fleet, "sslmode=require") +
                              "' --set memory.time_limit_ms=0 --out " + dir.File("run.csv"));
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_GT(RowsWithLoopClosure(ReadFile(dir.File("run.csv"))), 0);
  const MapInfo map = InspectMap(Server().TcpUri("r1", fleet));
  EXPECT_EQ(map.integrity, "ok");
  EXPECT_GT(map.locations, 0);
}

TEST_F(FleetTest, TheToolRunsAndResumesARobotAfterKill9) {
  const std::string fleet = NewFleet("killed", {"r1"});
  testing::TempDir dir;
  SyntheticRoute(testing::ShortRoute()).Write(dir.path().string());
  const std::string images = dir.File("images");
  const std::string budget = " --set memory.time_limit_ms=0 memory.max_wm_locations=30";
  ASSERT_EQ(Memloop("run " + images + budget + " --out " + dir.File("whole.csv")).exit_code, 0);
  const std::string csv = dir.File("run.csv");
  const std::string uri = Server().Uri("", fleet);
  const pid_t child = Start({"run", images, "--db", uri, "--robot", "r1", "--out", csv, "--set",
                             "memory.time_limit_ms=0", "memory.max_wm_locations=30"},
                            dir.File("log0"));
  const int status = SignalAfterRows(child, csv, 40, SIGKILL);
  ASSERT_TRUE(WIFSIGNALED(status)) << ReadFile(dir.File("log0"));
  const Outcome resumed =
      Memloop("run " + images + " --db '" + uri + "' --robot r1 --resume --out " + csv);
  ASSERT_EQ(resumed.exit_code, 0) << resumed.output;
  EXPECT_TRUE(Contains(resumed.output, "after image ")) << resumed.output;
  EXPECT_EQ(WithoutTimes(ReadFile(csv)), WithoutTimes(ReadFile(dir.File("whole.csv"))));
  const Outcome inspect = Memloop("inspect '" + Server().Uri("r1", fleet) + "'");
  EXPECT_EQ(inspect.exit_code, 0) << inspect.output;
  EXPECT_TRUE(Contains(inspect.output, "integrity: ok")) << inspect.output;
  // --robot and the URI's user must agree, and --robot needs a server's map.
  const Outcome other =
      Memloop("run " + images + " --db '" + Server().Uri("r2", fleet) + "' --robot r1");
  EXPECT_NE(other.exit_code, 0);
  EXPECT_TRUE(Contains(other.output, "connects as r2, not as the robot r1")) << other.output;
  const Outcome file = Memloop("run " + images + " --db " + dir.File("x.db") + " --robot r1");
  EXPECT_NE(file.exit_code, 0);
  EXPECT_TRUE(Contains(file.output, "the map must be a server's")) << file.output;
}

}  // namespace
}  // namespace memloop
