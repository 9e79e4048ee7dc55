// `memloop view`'s HTTP API on a map of the generated route: what it shows is what inspect and
// export read; edits need the token, are kept in the map, honoured by export and inspect, undone;
// refusals name the problem. The browser's side: tests/viewer_browser_test.py.
#include <gtest/gtest.h>
#include <httplib.h>

#include <filesystem>
#include <fstream>
#include <future>
#include <memory>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <sstream>
#include <thread>

#include "cli_helpers.h"
#include "memloop/errors.h"
#include "memloop/loop_closure_edits.h"
#include "memloop/map_export.h"
#include "memloop/map_info.h"
#include "storage/map_writer_lock.h"
#include "view/view_server.h"

namespace memloop {
namespace {

using nlohmann::json;

class ViewTest : public ::testing::Test {
 protected:
  // One map for the suite (the demo route's first 130 images: a lap and its revisit), copied for
  // each test since edits write it.
  static void SetUpTestSuite() {
    suite_dir_ = new testing::TempDir;
    const std::string route = suite_dir_->File("route");
    ASSERT_EQ(Memloop("generate " + route).exit_code, 0);
    for (int i = 131; std::filesystem::remove(route + "/images/" + std::to_string(i) + ".png");) {
      ++i;
    }
    const Outcome run = Memloop("run " + route + "/images --db " + suite_dir_->File("map.db") +
                                " --set memory.time_limit_ms=0 camera.fx=300 camera.fy=300 "
                                "camera.cx=160 camera.cy=120");
    ASSERT_EQ(run.exit_code, 0) << run.output;
  }
  static void TearDownTestSuite() {
    delete suite_dir_;
    suite_dir_ = nullptr;
  }

  void SetUp() override {
    ASSERT_TRUE(std::filesystem::exists(suite_dir_->File("map.db")));
    map_ = dir_.File("map.db");
    std::filesystem::copy_file(suite_dir_->File("map.db"), map_);
  }
  void TearDown() override { StopServer(); }

  void StartServer(bool read_only = false, bool images = true) {
    ViewServerOptions options;
    options.map = map_;
    options.images = images ? suite_dir_->File("route/images") : "";
    options.read_only = read_only;
    options.who = "tester";
    server_ = std::make_unique<ViewServer>(options);
    const int port = server_->Bind();
    thread_ = std::thread([this] { server_->Run(); });
    client_ = std::make_unique<httplib::Client>("127.0.0.1", port);
  }
  void StopServer() {
    if (!server_) return;
    server_->Stop();
    thread_.join();
    server_.reset();
  }

  json Get(const std::string& path, int status = 200) {
    const auto response = client_->Get(path.c_str());
    EXPECT_TRUE(response) << path;
    if (!response) return nullptr;
    EXPECT_EQ(response->status, status) << path << ": " << response->body;
    return json::parse(response->body, nullptr, false);
  }
  // The answer's status and JSON body.
  std::pair<int, json> Post(const json& body, const std::string& token) {
    httplib::Headers headers;
    if (!token.empty()) headers.emplace("X-Memloop-Token", token);
    const auto response = client_->Post("/api/edits", headers, body.dump(), "application/json");
    EXPECT_TRUE(response);
    if (!response) return {0, nullptr};
    return {response->status, json::parse(response->body, nullptr, false)};
  }

  static testing::TempDir* suite_dir_;
  testing::TempDir dir_;
  std::string map_;
  std::unique_ptr<ViewServer> server_;
  std::thread thread_;
  std::unique_ptr<httplib::Client> client_;
};

testing::TempDir* ViewTest::suite_dir_ = nullptr;

std::vector<std::pair<ImageIndex, ImageIndex>> ExportedPairs(const std::string& map) {
  std::vector<std::pair<ImageIndex, ImageIndex>> pairs;
  for (const ExportedLoopClosure& loop : ExportLoopClosures(map, {})) {
    pairs.emplace_back(loop.loop.query_image, loop.loop.match_image);
  }
  return pairs;
}

TEST_F(ViewTest, ApiShowsWhatInspectReads) {
  StartServer();
  const MapInfo info = InspectMap(map_);
  ASSERT_GT(info.loop_closures.size(), 5u);
  const json summary = Get("/api/summary");
  EXPECT_EQ(summary["images"], info.images);
  EXPECT_EQ(summary["images"], 130);
  EXPECT_EQ(summary["loop_closures"], info.loop_closures.size());
  EXPECT_EQ(summary["sessions"].size(), 1u);
  EXPECT_EQ(summary["read_only"], false);
  EXPECT_EQ(summary["parameters"]["camera.fx"], "300");
  // Opened without reading every page (MapCheck::kQuick): what is not counted is said.
  EXPECT_EQ(summary["integrity"], "not checked here (memloop inspect checks it)");
  EXPECT_EQ(summary["words"], -1);
  EXPECT_EQ(info.integrity, "ok");
  EXPECT_GT(info.words, 0);

  // A page of a session's images, each with the location that holds it.
  const json page = Get("/api/images?session=0&offset=120&limit=50");
  EXPECT_EQ(page["total"], 130);
  ASSERT_EQ(page["images"].size(), 10u);
  EXPECT_EQ(page["images"][0]["index"], 120);
  EXPECT_EQ(page["images"][0]["name"], "121.png");
  EXPECT_TRUE(page["images"][0]["location"].is_number());

  // A loop closure, and the location of its query image: it lists it, with its geometry.
  const json loops = Get("/api/loop_closures?offset=0&limit=1000");
  EXPECT_EQ(loops["total"], info.loop_closures.size());
  const json& first = loops["loop_closures"][0];
  EXPECT_EQ(first["query_image"], info.loop_closures[0].query_image);
  EXPECT_EQ(first["match_image"], info.loop_closures[0].match_image);
  EXPECT_EQ(first["state"], "detected");
  EXPECT_EQ(first["query_name"], std::to_string(info.loop_closures[0].query_image + 1) + ".png");
  ASSERT_TRUE(first["pose"].is_object()) << first;  // the intrinsics were given
  EXPECT_GT(first["pose"]["inliers"].get<int>(), 0);
  const json location = Get("/api/locations/" + first["query_location"].dump());
  EXPECT_NE(location["images"].dump().find("\"index\":" + first["query_image"].dump()),
            std::string::npos)
      << location;
  EXPECT_GT(location["words"].get<int>(), 0);
  EXPECT_FALSE(location["loop_closures"].empty());
  EXPECT_FALSE(location["neighbours"].empty());
  EXPECT_EQ(Get("/api/locations/99999", 404)["error"], "the map has no location 99999");

  // Search by name and by index; thumbnails made from --images.
  EXPECT_EQ(Get("/api/find?q=17.png")["index"], 16);
  EXPECT_EQ(Get("/api/find?q=16")["name"], "17.png");
  Get("/api/find?q=nothing-like-it.png", 404);
  const auto thumbnail = client_->Get("/api/thumbnails/16");
  ASSERT_TRUE(thumbnail);
  ASSERT_EQ(thumbnail->status, 200);
  EXPECT_EQ(thumbnail->get_header_value("Content-Type"), "image/jpeg");
  const cv::Mat decoded = cv::imdecode(
      std::vector<unsigned char>(thumbnail->body.begin(), thumbnail->body.end()), cv::IMREAD_COLOR);
  EXPECT_EQ(decoded.cols, ImageSource::kThumbnailWidth);
  // The page itself, built into the program.
  const auto page_html = client_->Get("/");
  ASSERT_TRUE(page_html);
  EXPECT_NE(page_html->body.find("<script src=\"/viewer.js\">"), std::string::npos);
  EXPECT_EQ(client_->Get("/viewer.js")->status, 200);
}

TEST_F(ViewTest, NoImagesFolderServesNoImageAndSaysWhy) {
  StartServer(false, false);
  const json answer = Get("/api/thumbnails/3", 404);
  EXPECT_EQ(answer["error"], "no images: start memloop view with --images FOLDER");
}

TEST_F(ViewTest, EditsNeedTheTokenAreKeptInTheMapAndUndone) {
  StartServer();
  const MapInfo before = InspectMap(map_);
  const MapLoopClosure wrong = before.loop_closures[2];
  const json reject = {
      {"action", "reject"}, {"query_image", wrong.query_image}, {"match_image", wrong.match_image}};

  // No token, a wrong one: refused, nothing written.
  EXPECT_EQ(Post(reject, "").first, 403);
  EXPECT_EQ(Post(reject, std::string(32, '0')).first, 403);
  EXPECT_TRUE(ReadLoopClosureEdits(map_).empty());

  // With the token: kept in the map, honoured by inspect, export and the API.
  const auto [status, rejected] = Post(reject, server_->token());
  ASSERT_EQ(status, 200) << rejected;
  EXPECT_EQ(rejected["id"], 1);
  const std::vector<LoopClosureEdit> edits = ReadLoopClosureEdits(map_);
  ASSERT_EQ(edits.size(), 1u);
  EXPECT_EQ(edits[0].who, "tester");
  EXPECT_EQ(edits[0].query_image, wrong.query_image);
  const MapInfo after = InspectMap(map_);
  EXPECT_EQ(after.loop_closures.size(), before.loop_closures.size() - 1);
  EXPECT_EQ(after.rejected_loop_closures, 1);
  const auto pair = std::make_pair(wrong.query_image, wrong.match_image);
  auto exported = ExportedPairs(map_);
  EXPECT_EQ(std::count(exported.begin(), exported.end(), pair), 0);
  EXPECT_EQ(exported.size(), after.loop_closures.size());
  EXPECT_EQ(Get("/api/loop_closures?offset=2&limit=1")["loop_closures"][0]["state"], "rejected");
  EXPECT_EQ(Get("/api/summary")["edits"], 1);
  // The same again: it is no longer a loop closure of the map.
  const auto [again, again_error] = Post(reject, server_->token());
  EXPECT_EQ(again, 400);
  EXPECT_EQ(again_error["error"], map_ + ": images " + std::to_string(wrong.query_image) + " and " +
                                      std::to_string(wrong.match_image) +
                                      " are not one of the map's loop closures");

  // Undone: the detected loop closure is back.
  EXPECT_EQ(Post({{"action", "undo"}, {"edit", 1}}, server_->token()).first, 200);
  EXPECT_EQ(InspectMap(map_).loop_closures.size(), before.loop_closures.size());
  exported = ExportedPairs(map_);
  EXPECT_EQ(std::count(exported.begin(), exported.end(), pair), 1);
  EXPECT_EQ(Post({{"action", "undo"}, {"edit", 1}}, server_->token()).first, 400);

  // A missed one added between two images of different locations: export gives its geometry.
  const json add = {{"action", "add"}, {"query_image", 100}, {"match_image", 3}};
  const auto [added_status, added] = Post(add, server_->token());
  ASSERT_EQ(added_status, 200) << added;
  const std::vector<ExportedLoopClosure> with_added = ExportLoopClosures(map_, {});
  ASSERT_EQ(with_added.size(), before.loop_closures.size() + 1);
  EXPECT_EQ(with_added.back().loop.query_image, 100);
  EXPECT_EQ(with_added.back().loop.match_image, 3);
  EXPECT_EQ(with_added.back().loop.added_by_edit, added["id"]);
  const json last = Get("/api/loop_closures?offset=0&limit=1000")["loop_closures"].back();
  EXPECT_EQ(last["state"], "added");
  EXPECT_EQ(Post(add, server_->token()).first, 400);  // already one

  // Bad edits: one clear answer each, nothing written.
  const size_t written = ReadLoopClosureEdits(map_).size();
  const auto refused = [&](const json& body, const std::string& message) {
    const auto [code, answer] = Post(body, server_->token());
    EXPECT_EQ(code, 400) << body;
    EXPECT_NE(answer.value("error", "").find(message), std::string::npos) << answer;
  };
  refused({{"action", "add"}, {"query_image", 100000}, {"match_image", 3}},
          "image 100000 is not in the map's Long-Term Memory");
  refused({{"action", "add"}, {"query_image", 5}}, "add needs \"match_image\", an integer");
  refused({{"action", "merge"}}, "unknown action 'merge'");
  refused({{"action", "undo"}, {"edit", 77}}, "the map has no edit 77");
  const auto malformed =
      client_->Post("/api/edits", {{"X-Memloop-Token", server_->token()}}, "{oops", "text/plain");
  ASSERT_TRUE(malformed);
  EXPECT_EQ(malformed->status, 400);
  EXPECT_EQ(ReadLoopClosureEdits(map_).size(), written);
}

TEST_F(ViewTest, ReadOnlyAndAMapARunWritesRefuseEdits) {
  const MapLoopClosure loop = InspectMap(map_).loop_closures[0];
  const json reject = {
      {"action", "reject"}, {"query_image", loop.query_image}, {"match_image", loop.match_image}};
  StartServer(/*read_only=*/true);
  EXPECT_EQ(Get("/api/summary")["read_only_reason"], "opened with --read-only");
  auto [status, answer] = Post(reject, server_->token());
  EXPECT_EQ(status, 409);
  EXPECT_EQ(answer["error"], "the map is read-only here: opened with --read-only");
  StopServer();

  StartServer();
  {
    MapWriterLock writer(map_);  // as a run holds it
    writer.Adopt();
    EXPECT_EQ(Get("/api/summary")["read_only"], true);
    std::tie(status, answer) = Post(reject, server_->token());
    EXPECT_EQ(status, 409);
    EXPECT_NE(answer["error"].get<std::string>().find("a run is writing the map (pid"),
              std::string::npos);
  }
  EXPECT_TRUE(ReadLoopClosureEdits(map_).empty());
  EXPECT_EQ(Post(reject, server_->token()).first, 200);  // the run is over
}

// Edits stay through a resumed run, and localization reads the map as edited.
TEST_F(ViewTest, ResumeKeepsTheEdits) {
  const MapLoopClosure loop = InspectMap(map_).loop_closures[0];
  RejectLoopClosure(map_, loop.query_image, loop.match_image, "tester");
  const Outcome resumed =
      Memloop("run " + suite_dir_->File("route/images") + " --db " + map_ + " --resume");
  ASSERT_EQ(resumed.exit_code, 0) << resumed.output;
  EXPECT_EQ(ReadLoopClosureEdits(map_).size(), 1u);
  EXPECT_EQ(InspectMap(map_).rejected_loop_closures, 1);
  const Outcome inspect = Memloop("inspect " + map_);
  EXPECT_NE(inspect.output.find("(as edited: 1 edits, 1 detected ones rejected)"),
            std::string::npos)
      << inspect.output;
}

// --poses: each image at its pose in a TUM trajectory, matched by time stamp; a malformed
// trajectory is refused naming its line.
TEST_F(ViewTest, PositionsFromATrajectoryOfTheImagesTimeStamps) {
  const std::string walk = dir_.File("walk");
  ASSERT_EQ(Memloop("generate " + walk + " --layout tum").exit_code, 0);
  // The first 40 images of the TUM folder (rgb.txt's 3 comment lines, then one line an image).
  const std::vector<std::string> lines = [&] {
    std::vector<std::string> all;
    std::ifstream in(walk + "/rgb.txt");
    for (std::string line; std::getline(in, line) && all.size() < 43;) all.push_back(line);
    return all;
  }();
  {
    std::ofstream out(walk + "/rgb.txt");
    for (const std::string& line : lines) out << line << "\n";
  }
  const std::string map = dir_.File("walk.db");
  ASSERT_EQ(Memloop("run " + walk + " --db " + map + " --set memory.time_limit_ms=0").exit_code, 0);
  ViewServerOptions options;
  options.map = map;
  options.poses = walk + "/groundtruth.txt";
  server_ = std::make_unique<ViewServer>(options);
  const int port = server_->Bind();
  thread_ = std::thread([this] { server_->Run(); });
  client_ = std::make_unique<httplib::Client>("127.0.0.1", port);
  const json positions = Get("/api/positions")["positions"];
  ASSERT_EQ(positions.size(), 40u);
  // Image 0 is at the trajectory's first pose (its time stamp, 1000.0).
  std::ifstream truth(walk + "/groundtruth.txt");
  std::string line;
  for (int i = 0; i < 4; ++i) std::getline(truth, line);
  std::istringstream first(line);
  double stamp = 0, x = 0, y = 0, z = 0;
  first >> stamp >> x >> y >> z;
  EXPECT_EQ(positions[0][0], 0);
  EXPECT_DOUBLE_EQ(positions[0][1].get<double>(), x);
  EXPECT_DOUBLE_EQ(positions[0][3].get<double>(), z);
  StopServer();

  std::ofstream(dir_.File("bad.txt")) << "1000.0 1 2 3 0 0 0\n";
  options.poses = dir_.File("bad.txt");
  try {
    ViewServer refused(options);
    ADD_FAILURE() << "a malformed trajectory was taken";
  } catch (const InputError& error) {
    EXPECT_EQ(
        std::string(error.what()),
        dir_.File("bad.txt") + ": line 1: expected 'time tx ty tz qx qy qz qw' (a TUM trajectory)");
  }
  // Without --poses the page says how to get the graph.
  StartServer();
  EXPECT_EQ(Get("/api/positions", 404)["error"],
            "no positions: start memloop view with --poses TRAJECTORY");
}

// A stop that comes before the server runs (Ctrl-C at start) still ends it.
TEST_F(ViewTest, StopBeforeRunEndsTheRun) {
  ViewServerOptions options;
  options.map = map_;
  ViewServer server(options);
  server.Bind();
  server.Stop();
  auto run = std::async(std::launch::async, [&server] { server.Run(); });
  const bool ended = run.wait_for(std::chrono::seconds(30)) == std::future_status::ready;
  EXPECT_TRUE(ended) << "Run() went on after Stop()";
  if (!ended) server.Stop();  // it runs now: this stops it
}

TEST_F(ViewTest, CommandRefusesBadInputInOneLine) {
  const auto one_line = [](const Outcome& outcome, const std::string& message) {
    EXPECT_EQ(outcome.exit_code, 1) << outcome.output;
    EXPECT_NE(outcome.output.find(message), std::string::npos) << outcome.output;
    EXPECT_EQ(std::count(outcome.output.begin(), outcome.output.end(), '\n'), 1) << outcome.output;
  };
  const std::string text = dir_.File("notes.txt");
  std::ofstream(text) << "not a map\n";
  one_line(Memloop("view " + text), "notes.txt");
  one_line(Memloop("view " + map_ + " --images " + dir_.File("missing")),
           dir_.File("missing") + ": not a folder of images (--images): no such folder");
  httplib::Server holder;  // holds a port
  const int taken = holder.bind_to_any_port("127.0.0.1");
  one_line(Memloop("view " + map_ + " --port " + std::to_string(taken)),
           "127.0.0.1:" + std::to_string(taken) + ": cannot listen there: the port is in use");
}

}  // namespace
}  // namespace memloop
