// The ROS node against a real roscore that the test starts on a free port: queue mode gives the
// loop closures `memloop run BAG` gives, live mode drops and counts, unsupported encodings are
// skipped with one error, bad parameters refuse to start, and a signal leaves a map that resumes.
#include <diagnostic_msgs/DiagnosticArray.h>
#include <gtest/gtest.h>
#include <memloop_msgs/LoopClosure.h>
#include <netinet/in.h>
#include <ros/ros.h>
#include <sensor_msgs/CompressedImage.h>
#include <sensor_msgs/Image.h>
#include <std_srvs/Trigger.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <map>
#include <mutex>
#include <opencv2/imgcodecs.hpp>
#include <set>
#include <sstream>
#include <thread>

#include "cli_helpers.h"
#include "memloop/synthetic_route.h"
#include "ros_bag_writers.h"
#include "short_route.h"
#include "temp_dir.h"

namespace memloop {
namespace {

using Clock = std::chrono::steady_clock;
constexpr const char* kTopic = "/camera/image_raw";
const std::chrono::seconds kDeadline(300);  // for a loaded machine; a pass takes seconds

int FreePort() {
  const int fd = socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  bind(fd, reinterpret_cast<sockaddr*>(&address), sizeof(address));
  socklen_t length = sizeof(address);
  getsockname(fd, reinterpret_cast<sockaddr*>(&address), &length);
  close(fd);
  return ntohs(address.sin_port);
}

// A process of its own group, its output to `log`.
pid_t Spawn(const std::vector<std::string>& arguments, const std::string& log) {
  const pid_t child = fork();
  if (child == 0) {
    setpgid(0, 0);
    if (freopen(log.c_str(), "w", stdout) == nullptr) _exit(126);
    dup2(fileno(stdout), fileno(stderr));
    std::vector<char*> argv;
    for (const std::string& argument : arguments)
      argv.push_back(const_cast<char*>(argument.c_str()));
    argv.push_back(nullptr);
    execvp(argv[0], argv.data());
    _exit(127);
  }
  return child;
}

// The exit code, or -1 when it has not exited within `wait`.
int WaitExit(pid_t child, std::chrono::seconds wait = kDeadline) {
  const auto end = Clock::now() + wait;
  int status = 0;
  while (waitpid(child, &status, WNOHANG) != child) {
    if (Clock::now() > end) return -1;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

template <typename Condition>
bool WaitFor(Condition condition, std::chrono::seconds wait = kDeadline) {
  const auto end = Clock::now() + wait;
  while (!condition()) {
    if (Clock::now() > end) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return true;
}

int CountLines(const std::string& text, const std::string& part) {
  std::istringstream in(text);
  int count = 0;
  for (std::string line; std::getline(in, line);) count += Contains(line, part);
  return count;
}

sensor_msgs::Image ImageMessage(const cv::Mat& bgr, double stamp) {
  sensor_msgs::Image message;
  message.header.stamp = ros::Time(stamp);
  message.header.frame_id = "camera";
  message.height = bgr.rows;
  message.width = bgr.cols;
  message.encoding = "bgr8";
  message.step = bgr.cols * 3;
  message.data.assign(bgr.data, bgr.data + bgr.total() * 3);
  return message;
}

class RosNodeTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    home_ = new testing::TempDir();
    const std::string master = "http://127.0.0.1:" + std::to_string(FreePort());
    setenv("ROS_MASTER_URI", master.c_str(), 1);
    setenv("ROS_HOME", home_->path().c_str(), 1);
    setenv("ROS_LOG_DIR", home_->File("log").c_str(), 1);
    roscore_ =
        Spawn({"roscore", "-p", master.substr(master.rfind(':') + 1)}, home_->File("roscore.log"));
    int argc = 1;
    char name[] = "memloop_test";
    char* argv[] = {name, nullptr};
    ros::init(argc, argv, "memloop_test",
              ros::init_options::NoSigintHandler | ros::init_options::AnonymousName);
    if (!WaitFor([] { return ros::master::check(); }, std::chrono::seconds(60))) {
      GTEST_FAIL() << "roscore did not start: " << ReadFile(home_->File("roscore.log"));
    }
    ros::start();
    spinner_ = new ros::AsyncSpinner(2);
    spinner_->start();
    route_ = new SyntheticRoute(testing::ShortRoute());
  }
  static void TearDownTestSuite() {
    delete spinner_;
    ros::shutdown();
    kill(-roscore_, SIGINT);
    if (WaitExit(roscore_, std::chrono::seconds(20)) < 0) {
      kill(-roscore_, SIGKILL);
      WaitExit(roscore_);
    }
    delete route_;
    delete home_;
  }

  void SetUp() override {
    if (!ros::master::check()) GTEST_FAIL() << "no roscore";
    ros::NodeHandle node;
    loop_closures_ =
        node.subscribe("/memloop/loop_closures", 1000, &RosNodeTest::OnLoopClosure, this);
    diagnostics_ = node.subscribe("/diagnostics", 10, &RosNodeTest::OnDiagnostics, this);
    images_ = node.advertise<sensor_msgs::Image>(kTopic, 1000);
  }

  // Starts the node with `arguments` (remaps and _parameters) on kTopic.
  pid_t StartNode(std::vector<std::string> arguments, const std::string& log) {
    ros::param::del("/memloop");  // the last node's private parameters stay on the server
    arguments.insert(arguments.begin(),
                     {MEMLOOP_NODE, std::string("image:=") + kTopic, "__name:=memloop"});
    return Spawn(arguments, log);
  }

  // Waits until the node is subscribed to the images and publishes loop closures.
  void WaitConnected() {
    ASSERT_TRUE(WaitFor(
        [&] { return images_.getNumSubscribers() > 0 && loop_closures_.getNumPublishers() > 0; }));
  }

  // The last diagnostics' value of `key` as a number, -1 before any.
  long long Diagnostic(const std::string& key) {
    std::lock_guard<std::mutex> lock(mutex_);
    const auto found = status_.find(key);
    return found == status_.end() ? -1 : std::atoll(found->second.c_str());
  }

  std::vector<std::pair<int, int>> LoopClosures() {
    std::lock_guard<std::mutex> lock(mutex_);
    return loops_;
  }

  void OnLoopClosure(const memloop_msgs::LoopClosure& loop) {
    std::lock_guard<std::mutex> lock(mutex_);
    loops_.emplace_back(loop.query_image, loop.match_image);
    last_loop_ = loop;
  }
  void OnDiagnostics(const diagnostic_msgs::DiagnosticArray& array) {
    std::lock_guard<std::mutex> lock(mutex_);
    for (const auto& entry : array.status) {
      if (entry.name != "memloop: loop closure detection") continue;
      for (const auto& pair : entry.values) status_[pair.key] = pair.value;
    }
  }

  static inline testing::TempDir* home_ = nullptr;
  static inline pid_t roscore_ = -1;
  static inline ros::AsyncSpinner* spinner_ = nullptr;
  static inline SyntheticRoute* route_ = nullptr;
  testing::TempDir dir_;
  ros::Subscriber loop_closures_, diagnostics_;
  ros::Publisher images_;
  std::mutex mutex_;
  std::vector<std::pair<int, int>> loops_;
  memloop_msgs::LoopClosure last_loop_;
  std::map<std::string, std::string> status_;
};

const char kSettings[] = "memory.time_limit_ms=0 memory.max_wm_locations=30";

// Queue mode, T_time off: the bag's images published into the node give exactly the loop
// closures `memloop run BAG --topic` gives, image for image; ~save, then SIGINT, leave a map that
// inspect and --resume accept.
TEST_F(RosNodeTest, QueueModeGivesTheLoopClosuresOfTheCommandLine) {
  if (!testing::CanWriteRos1Bag()) GTEST_SKIP() << "memloop was built without rosbag_storage";
  std::vector<BagImage> frames;
  for (int i = 0; i < route_->size(); ++i) {
    frames.push_back({route_->Render(i), 1000 + 0.1 * i, 1000 + 0.1 * i});
  }
  const std::string bag = dir_.File("route.bag");
  testing::WriteRos1Bag(bag, kTopic, frames, BagEncoding::kBgr8);
  const std::string csv = dir_.File("cli.csv");
  const Outcome cli =
      Memloop("run " + bag + " --topic " + kTopic + " --out " + csv + " --set " + kSettings);
  ASSERT_EQ(cli.exit_code, 0) << cli.output;

  const std::string map = dir_.File("node.db");
  const std::string log = dir_.File("node.log");
  const pid_t node = StartNode({"_queue:=true", "_database:=" + map, "_memory/time_limit_ms:=0",
                                "_memory/max_wm_locations:=30"},
                               log);
  WaitConnected();
  for (const BagImage& frame : frames) images_.publish(ImageMessage(frame.pixels, frame.stamp));
  const long long count = static_cast<long long>(frames.size());
  ASSERT_TRUE(WaitFor([&] { return Diagnostic("images processed") == count; })) << ReadFile(log);
  ASSERT_TRUE(WaitFor([&] {
    return static_cast<long long>(LoopClosures().size()) == Diagnostic("loop closures");
  }));
  // The command line's loop closures, image for image.
  std::vector<std::pair<int, int>> expected;
  std::istringstream rows(ReadFile(csv));
  std::string row;
  std::getline(rows, row);
  while (std::getline(rows, row)) {
    std::vector<std::string> cells;
    std::istringstream fields(row);
    for (std::string cell; std::getline(fields, cell, ',');) cells.push_back(cell);
    if (cells.size() > 3 && !cells[3].empty()) {
      expected.emplace_back(std::stoi(cells[0]), std::stoi(cells[3]));
    }
  }
  ASSERT_GT(expected.size(), 5u);
  EXPECT_EQ(LoopClosures(), expected);
  {
    std::lock_guard<std::mutex> lock(mutex_);
    EXPECT_DOUBLE_EQ(last_loop_.query_stamp.toSec(), 1000 + 0.1 * last_loop_.query_image);
    EXPECT_NEAR(last_loop_.match_stamp.toSec(), 1000 + 0.1 * last_loop_.match_image, 1e-6);
    EXPECT_GT(last_loop_.hypothesis_value, 0);
    EXPECT_EQ(last_loop_.header.frame_id, "camera");
  }
  std_srvs::Trigger save;
  ASSERT_TRUE(ros::service::call("/memloop/save", save));
  EXPECT_TRUE(save.response.success) << save.response.message;
  EXPECT_TRUE(Contains(save.response.message, "resumes after image " + std::to_string(count - 1)))
      << save.response.message;

  kill(node, SIGINT);
  EXPECT_EQ(WaitExit(node), 0) << ReadFile(log);
  EXPECT_TRUE(Contains(ReadFile(log), "closed after " + std::to_string(count) + " images"))
      << ReadFile(log);
  EXPECT_EQ(Memloop("inspect " + map).exit_code, 0);
  const Outcome resumed =
      Memloop("run " + bag + " --topic " + kTopic + " --db " + map + " --resume");
  EXPECT_EQ(resumed.exit_code, 0) << resumed.output;
  EXPECT_TRUE(
      Contains(resumed.output, "resuming " + map + " after image " + std::to_string(count - 1)))
      << resumed.output;
}

// Live mode: the images come far faster than the node goes: those a newer one replaced are
// dropped and counted, every image is accounted for, and the map resumes.
TEST_F(RosNodeTest, LiveModeDropsAndCountsAndTheMapResumes) {
  const std::string map = dir_.File("live.db");
  const std::string log = dir_.File("node.log");
  const pid_t node = StartNode({"_database:=" + map}, log);
  WaitConnected();
  const long long count = 100;
  for (long long i = 0; i < count; ++i) images_.publish(ImageMessage(route_->Render(i), 1 + i));
  ASSERT_TRUE(WaitFor([&] {
    return Diagnostic("images received") == count && Diagnostic("images waiting") == 0;
  })) << ReadFile(log);
  const long long processed = Diagnostic("images processed");
  const long long dropped = Diagnostic("images dropped");
  EXPECT_GE(processed, 1);
  EXPECT_EQ(processed + dropped, count);
  EXPECT_EQ(Diagnostic("images skipped"), 0);
  kill(node, SIGTERM);
  EXPECT_EQ(WaitExit(node), 0) << ReadFile(log);
  EXPECT_EQ(Memloop("inspect " + map).exit_code, 0);
  const pid_t again = StartNode({"_database:=" + map, "_resume:=true"}, log + "2");
  ASSERT_TRUE(WaitFor([&] { return Contains(ReadFile(log + "2"), "(resumed)"); }))
      << ReadFile(log + "2");
  EXPECT_TRUE(Contains(ReadFile(log + "2"), "images from " + std::to_string(count) + " on"));
  kill(again, SIGINT);
  EXPECT_EQ(WaitExit(again), 0) << ReadFile(log + "2");
}

// A depth map or a Bayer image on the image topic: skipped, one error line per encoding, counted.
TEST_F(RosNodeTest, UnsupportedEncodingsAreSkippedWithOneErrorEach) {
  const std::string log = dir_.File("node.log");
  const pid_t node = StartNode({"_queue:=true", "_database:=" + dir_.File("map.db")}, log);
  WaitConnected();
  sensor_msgs::Image depth;
  depth.height = 240;
  depth.width = 320;
  depth.encoding = "16UC1";
  depth.step = 640;
  depth.data.assign(240 * 640, 0);
  sensor_msgs::Image bayer = depth;
  bayer.encoding = "bayer_rggb8";
  bayer.step = 320;
  bayer.data.assign(240 * 320, 0);
  for (int i = 0; i < 3; ++i) images_.publish(depth);
  images_.publish(ImageMessage(route_->Render(0), 1));
  for (int i = 0; i < 2; ++i) images_.publish(bayer);
  images_.publish(ImageMessage(route_->Render(1), 2));
  ASSERT_TRUE(WaitFor([&] {
    return Diagnostic("images received") == 7 && Diagnostic("images processed") == 2;
  })) << ReadFile(log);
  EXPECT_EQ(Diagnostic("images skipped"), 5);
  kill(node, SIGINT);
  EXPECT_EQ(WaitExit(node), 0);
  const std::string text = ReadFile(log);
  EXPECT_EQ(CountLines(text, "encoding 16UC1"), 1) << text;
  EXPECT_EQ(CountLines(text, "encoding bayer_rggb8"), 1) << text;
}

// ~depth: each image with the depth map stamped nearest it (a flat world 2 m away, seen square
// on): the loop closures' poses are metric and their covariance says 3 cm. A depth map of another
// size skips its image, counted.
TEST_F(RosNodeTest, DepthTopicMakesTheLoopClosuresMetric) {
  const std::string log = dir_.File("node.log");
  ros::NodeHandle handle;
  ros::Publisher depth = handle.advertise<sensor_msgs::Image>("/camera/depth", 1000);
  const pid_t node = StartNode(
      {"depth:=/camera/depth", "_depth:=true", "_queue:=true", "_database:=" + dir_.File("map.db"),
       "_memory/time_limit_ms:=0", "_memory/max_wm_locations:=30", "_camera/fx:=300",
       "_camera/fy:=300", "_camera/cx:=160", "_camera/cy:=120"},
      log);
  ASSERT_TRUE(WaitFor([&] {
    return images_.getNumSubscribers() > 0 && depth.getNumSubscribers() > 0 &&
           loop_closures_.getNumPublishers() > 0;
  })) << ReadFile(log);
  const auto depth_message = [](int rows, int columns, double stamp) {
    sensor_msgs::Image message;
    message.header.stamp = ros::Time(stamp);
    message.height = rows;
    message.width = columns;
    message.encoding = "16UC1";
    message.step = columns * 2;
    const cv::Mat millimetres(rows, columns, CV_16UC1, cv::Scalar(2000));
    message.data.assign(millimetres.data, millimetres.data + millimetres.total() * 2);
    return message;
  };
  // The pairing holds the newest pair until a later image shows it is the nearest: one more.
  const int count = route_->size();
  for (int i = 0; i <= count; ++i) {
    const double stamp = 1000 + 0.1 * i;
    images_.publish(ImageMessage(route_->Render(i % count), stamp));
    // The depth camera's stamp a few milliseconds off; image 3's map of another size.
    depth.publish(i == 3 ? depth_message(10, 10, stamp + 0.004)
                         : depth_message(240, 320, stamp + 0.004));
  }
  ASSERT_TRUE(WaitFor([&] { return Diagnostic("images processed") == count - 1; },
                      std::chrono::seconds(60)))
      << ReadFile(log) << " received " << Diagnostic("images received") << ", processed "
      << Diagnostic("images processed") << " of " << count;
  EXPECT_EQ(Diagnostic("images skipped"), 1);
  ASSERT_TRUE(WaitFor([&] {
    return static_cast<long long>(LoopClosures().size()) == Diagnostic("loop closures");
  }));
  EXPECT_GT(LoopClosures().size(), 5u);
  {
    std::lock_guard<std::mutex> lock(mutex_);
    EXPECT_TRUE(last_loop_.has_pose);
    EXPECT_TRUE(last_loop_.metric);
    EXPECT_DOUBLE_EQ(last_loop_.pose.covariance[0], 0.03 * 0.03);
    // Places revisited a lap apart, seen from within the jitter: centimetres to a metre.
    const auto& p = last_loop_.pose.pose.position;
    EXPECT_LT(std::hypot(p.x, p.y, p.z), 1.5);
  }
  kill(node, SIGINT);
  EXPECT_EQ(WaitExit(node), 0) << ReadFile(log);
  EXPECT_EQ(CountLines(ReadFile(log), "the depth map is 10x10, the image 320x240"), 1)
      << ReadFile(log);
}

// ~image_transport compressed: the node reads image/compressed (Debian has no compressed
// image_transport plugin) and decodes JPEG and PNG itself.
TEST_F(RosNodeTest, CompressedTransportIsDecoded) {
  const std::string log = dir_.File("node.log");
  ros::NodeHandle handle;
  ros::Publisher compressed =
      handle.advertise<sensor_msgs::CompressedImage>(std::string(kTopic) + "/compressed", 100);
  const pid_t node = StartNode(
      {"_queue:=true", "_image_transport:=compressed", "_database:=" + dir_.File("map.db")}, log);
  ASSERT_TRUE(WaitFor([&] {
    return compressed.getNumSubscribers() > 0 && loop_closures_.getNumPublishers() > 0;
  })) << ReadFile(log);
  for (int i = 0; i < 4; ++i) {
    sensor_msgs::CompressedImage message;
    message.header.stamp = ros::Time(1 + i);
    message.format = i % 2 ? "jpeg" : "png";
    cv::imencode(i % 2 ? ".jpg" : ".png", route_->Render(i), message.data);
    compressed.publish(message);
  }
  sensor_msgs::CompressedImage broken;
  broken.format = "jpeg";
  broken.data.assign(100, 7);
  compressed.publish(broken);
  ASSERT_TRUE(WaitFor([&] {
    return Diagnostic("images received") == 5 && Diagnostic("images processed") == 4;
  })) << ReadFile(log);
  EXPECT_EQ(Diagnostic("images skipped"), 1);
  kill(node, SIGINT);
  EXPECT_EQ(WaitExit(node), 0) << ReadFile(log);
}

// After `cmake --install`, with ROS_PACKAGE_PATH=PREFIX/share: roslaunch starts the node from the
// launch file (a remapped topic, parameters), and SIGINT closes its map.
TEST_F(RosNodeTest, TheInstalledLaunchFileStartsTheNode) {
  const std::string prefix = dir_.File("prefix");
  ASSERT_EQ(std::system(("cmake --install " + std::string(MEMLOOP_BUILD_DIR) + " --prefix " +
                         prefix + " > " + dir_.File("install.log") + " 2>&1")
                            .c_str()),
            0)
      << ReadFile(dir_.File("install.log"));
  setenv("ROS_PACKAGE_PATH", (prefix + "/share").c_str(), 1);
  const std::string log = dir_.File("launch.log");
  const std::string map = dir_.File("launched.db");
  ros::param::del("/memloop");
  const pid_t launch = Spawn({"roslaunch", "memloop", "memloop.launch",
                              std::string("image:=") + kTopic, "database:=" + map, "queue:=true"},
                             log);
  WaitConnected();
  for (int i = 0; i < 3; ++i) images_.publish(ImageMessage(route_->Render(i), 1 + i));
  ASSERT_TRUE(WaitFor([&] { return Diagnostic("images processed") == 3; })) << ReadFile(log);
  kill(launch, SIGINT);
  EXPECT_EQ(WaitExit(launch), 0) << ReadFile(log);
  EXPECT_TRUE(Contains(ReadFile(log), "closed after 3 images")) << ReadFile(log);
  EXPECT_EQ(Memloop("inspect " + map).exit_code, 0);
}

// An invalid or unknown parameter: the node refuses to start, in one line naming it. A topic
// nobody publishes: a warning after a few seconds.
TEST_F(RosNodeTest, BadParametersRefuseToStartAndASilentTopicIsWarnedAbout) {
  const std::string log = dir_.File("node.log");
  pid_t node = StartNode({"_database:=" + dir_.File("a.db"), "_memory/time_limit_ms:=-5"}, log);
  EXPECT_EQ(WaitExit(node), 1);
  EXPECT_EQ(CountLines(ReadFile(log), "~memory/time_limit_ms: "), 1) << ReadFile(log);
  node = StartNode({"_database:=" + dir_.File("a.db"), "_memory/time_limt_ms:=3"}, log);
  EXPECT_EQ(WaitExit(node), 1);
  EXPECT_TRUE(Contains(ReadFile(log), "~memory/time_limt_ms: unknown parameter")) << ReadFile(log);
  node = StartNode({"_database:=" + dir_.File("a.db"), "_queue:=maybe"}, log);
  EXPECT_EQ(WaitExit(node), 1);
  EXPECT_TRUE(Contains(ReadFile(log), "~queue: 'maybe' is not true or false")) << ReadFile(log);
  node = StartNode(
      {"_database:=" + dir_.File("a.db"), "_depth:=true", "_image_transport:=compressed"}, log);
  EXPECT_EQ(WaitExit(node), 1);
  EXPECT_TRUE(Contains(ReadFile(log), "~depth pairs raw images with raw depth maps"))
      << ReadFile(log);
  node = StartNode({"_database:=" + dir_.File("a.db"), "_depth:=true", "_depth_scale:=0"}, log);
  EXPECT_EQ(WaitExit(node), 1);
  EXPECT_TRUE(Contains(ReadFile(log), "~depth_scale: '0' is not")) << ReadFile(log);
  EXPECT_FALSE(std::filesystem::exists(dir_.File("a.db")));

  images_.shutdown();  // nobody publishes the images now
  node = StartNode({"_database:=" + dir_.File("b.db")}, log);
  EXPECT_TRUE(WaitFor([&] {
    return Contains(ReadFile(log), "no publisher on " + std::string(kTopic));
  })) << ReadFile(log);
  kill(node, SIGTERM);
  EXPECT_EQ(WaitExit(node), 0) << ReadFile(log);
}

}  // namespace
}  // namespace memloop
