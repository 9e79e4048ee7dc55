// ROS bags as a robot records them (written here from the generated route): the images of a
// topic, read as the same images in a folder are, with their time stamps; a clear error for a
// topic that is not there.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "cli_helpers.h"
#include "expect_input_error.h"
#include "memloop/errors.h"
#include "memloop/image_sequence.h"
#include "memloop/run_csv.h"
#include "memloop/synthetic_route.h"
#include "ros_bag_writers.h"
#include "short_route.h"
#include "temp_dir.h"

namespace memloop {
namespace {

namespace fs = std::filesystem;

constexpr const char* kTopic = "/camera/image_raw";

// The route's images, 10 Hz from t = 1500 s; the recorder got each 20 ms after its stamp.
std::vector<BagImage> RouteImages(const SyntheticRoute& route, int count) {
  std::vector<BagImage> images;
  for (int i = 0; i < count; ++i)
    images.push_back({route.Render(i), 1500 + 0.1 * i, 1500.02 + 0.1 * i});
  return images;
}

void ExpectSameImages(ImageSequence& sequence, const std::vector<BagImage>& images, bool gray) {
  ASSERT_EQ(sequence.size(), static_cast<int>(images.size()));
  Frame frame;
  for (const BagImage& image : images) {
    ASSERT_TRUE(sequence.Next(&frame));
    ASSERT_TRUE(frame.error.empty()) << frame.error;
    EXPECT_NEAR(frame.timestamp, image.stamp, 1e-6);
    cv::Mat expected = image.pixels;
    if (gray) cv::cvtColor(image.pixels, expected, cv::COLOR_BGR2GRAY);
    ASSERT_EQ(frame.image.type(), expected.type());
    EXPECT_EQ(cv::norm(frame.image, expected, cv::NORM_INF), 0) << frame.name;
  }
  EXPECT_FALSE(sequence.Next(&frame));
}

using testing::ExpectInputError;

class BagTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { route_ = new SyntheticRoute(testing::ShortRoute()); }
  static void TearDownTestSuite() { delete route_; }
  static SyntheticRoute* route_;
  ::memloop::testing::TempDir dir_;
};
SyntheticRoute* BagTest::route_ = nullptr;

TEST_F(BagTest, Ros2ImagesOfEveryEncodingComeBackAsWritten) {
  const std::vector<BagImage> images = RouteImages(*route_, 6);
  for (BagEncoding encoding :
       {BagEncoding::kBgr8, BagEncoding::kRgb8, BagEncoding::kMono8, BagEncoding::kPng}) {
    const std::string folder = dir_.File("bag" + std::to_string(static_cast<int>(encoding)));
    WriteRos2Bag(folder, kTopic, images, encoding);
    SequenceOptions options;
    auto sequence = ImageSequence::Open(folder, options);  // its only image topic
    ExpectSameImages(*sequence, images, encoding == BagEncoding::kMono8);
    EXPECT_EQ(sequence->NameOf(2), std::string(kTopic) + " 1500.220000");
  }
}

TEST_F(BagTest, Ros2TopicChoiceRateAndRefusals) {
  const std::vector<BagImage> images = RouteImages(*route_, 10);
  const std::string folder = dir_.File("two_topics");
  WriteRos2Bag(folder, kTopic, images, BagEncoding::kBgr8);
  AddRos2Topic(folder, "/camera/compressed", images, BagEncoding::kPng);
  SequenceOptions options;
  ExpectInputError([&] { ImageSequence::Open(folder, options); }, folder,
                   "holds several image topics: choose one with --topic: /camera/image_raw "
                   "(sensor_msgs/msg/Image, 10 messages), /camera/compressed");
  options.topic = "/camera/depth";
  ExpectInputError([&] { ImageSequence::Open(folder, options); }, folder,
                   "no topic /camera/depth in the bag; its image topics: /camera/image_raw");
  options.topic = "/chatter";
  ExpectInputError([&] { ImageSequence::Open(folder, options); }, folder,
                   "topic /chatter is of std_msgs/msg/String, not images");
  options.topic = "/camera/compressed";
  options.rate_hz = 5;  // 0.1 s apart: every other one, by the recording times
  auto sequence = ImageSequence::Open(folder, options);
  EXPECT_EQ(sequence->size(), 5);
  Frame frame;
  sequence->SkipTo(1);
  ASSERT_TRUE(sequence->Next(&frame));
  EXPECT_NEAR(frame.timestamp, images[2].stamp, 1e-6);
  EXPECT_EQ(frame.index, 1);
  // The .db3 file alone is a bag too; --topic on a folder of images is refused.
  const std::string db3 = folder + "/two_topics_0.db3";
  options.rate_hz = 0;
  EXPECT_EQ(ImageSequence::Open(db3, options)->size(), 10);
  fs::create_directories(dir_.File("images"));
  cv::imwrite(dir_.File("images/1.png"), images[0].pixels);
  ExpectInputError([&] { ImageSequence::Open(dir_.File("images"), options); }, dir_.File("images"),
                   "--topic /camera/compressed names a topic of a bag");
  std::ofstream(dir_.File("broken.db3")) << "not SQLite";
  ExpectInputError([&] { ImageSequence::Open(dir_.File("broken.db3"), options); },
                   dir_.File("broken.db3"), "not a readable ROS 2 bag");
}

TEST_F(BagTest, Ros1BagIsReadThroughRosbagStorage) {
  if (!testing::CanWriteRos1Bag()) GTEST_SKIP() << "built without rosbag_storage";
  const std::vector<BagImage> images = RouteImages(*route_, 6);
  for (BagEncoding encoding : {BagEncoding::kBgr8, BagEncoding::kRgb8, BagEncoding::kPng}) {
    const std::string path =
        dir_.File("walk" + std::to_string(static_cast<int>(encoding)) + ".bag");
    testing::WriteRos1Bag(path, kTopic, images, encoding);
    auto sequence = ImageSequence::Open(path);
    ExpectSameImages(*sequence, images, false);
  }
  const std::string path = dir_.File("walk0.bag");
  SequenceOptions options;
  options.topic = "/camera/left";
  ExpectInputError([&] { ImageSequence::Open(path, options); }, path,
                   "no topic /camera/left in the bag; its image topics: /camera/image_raw "
                   "(sensor_msgs/Image, 6 messages)");
  options.topic = "/imu";
  ExpectInputError([&] { ImageSequence::Open(path, options); }, path,
                   "topic /imu is of sensor_msgs/Imu, not images");
  std::ofstream(dir_.File("broken.bag")) << "#ROSBAG V2.0\nnot really";
  ExpectInputError([&] { ImageSequence::Open(dir_.File("broken.bag")); }, dir_.File("broken.bag"),
                   "not a readable ROS 1 bag");
}

// Depth maps of the images in `images`, each recorded 5 ms after its image, of (1000 + 100 i)
// units; none near image 3.
std::vector<BagImage> DepthMaps(const std::vector<BagImage>& images) {
  std::vector<BagImage> depths;
  for (size_t i = 0; i < images.size(); ++i) {
    if (i == 3) continue;
    BagImage depth = images[i];
    depth.pixels = cv::Mat(images[i].pixels.size(), CV_16UC1, cv::Scalar(1000 + 100 * i));
    depth.recorded += 0.005;
    depths.push_back(depth);
  }
  return depths;
}

// Each image with the depth map recorded nearest it (within 20 ms), in metres at the scale given.
void ExpectDepthMaps(ImageSequence& sequence, int count, double units_per_metre) {
  Frame frame;
  for (int i = 0; i < count; ++i) {
    ASSERT_TRUE(sequence.Next(&frame));
    ASSERT_TRUE(frame.error.empty()) << frame.error;
    ASSERT_FALSE(frame.image.empty());
    if (i == 3) {
      EXPECT_TRUE(frame.depth.empty());  // the nearest is 95 ms away: none
      continue;
    }
    ASSERT_EQ(frame.depth.type(), CV_32FC1) << i;
    ASSERT_EQ(frame.depth.size(), frame.image.size()) << i;
    EXPECT_FLOAT_EQ(frame.depth.at<float>(7, 9), (1000 + 100 * i) / units_per_metre) << i;
  }
}

// --depth-topic: a bag's depth images (16UC1 in millimetres unless --depth-scale says otherwise),
// each image taking the one recorded nearest it; a topic that is missing or not of raw images
// is refused naming the bag, one of another encoding skips its image.
TEST_F(BagTest, DepthTopicGivesEachImageTheDepthMapRecordedNearest) {
  const std::vector<BagImage> images = RouteImages(*route_, 6);
  const std::string folder = dir_.File("rgbd");
  WriteRos2Bag(folder, kTopic, images, BagEncoding::kBgr8);
  AddRos2Topic(folder, "/camera/depth", DepthMaps(images), BagEncoding::kDepth16);
  AddRos2Topic(folder, "/camera/compressed", images, BagEncoding::kPng);
  SequenceOptions options;
  options.topic = kTopic;
  options.depth_topic = "/camera/depth";
  ExpectDepthMaps(*ImageSequence::Open(folder, options), 6, 1000);
  options.depth_units_per_metre = 5000;
  ExpectDepthMaps(*ImageSequence::Open(folder, options), 6, 5000);

  options.depth_topic = "/camera/nothing";
  ExpectInputError([&] { ImageSequence::Open(folder, options); }, folder,
                   "no depth topic /camera/nothing in the bag; its image topics: "
                   "/camera/image_raw");
  options.depth_topic = "/camera/compressed";
  ExpectInputError([&] { ImageSequence::Open(folder, options); }, folder,
                   "depth topic /camera/compressed is of sensor_msgs/msg/CompressedImage, not "
                   "sensor_msgs Image (16UC1 or 32FC1)");
  options.depth_topic.clear();
  options.depth_folder = dir_.File("depth");
  ExpectInputError([&] { ImageSequence::Open(folder, options); }, folder,
                   "--depth reads a folder of depth maps; a bag's are a topic (--depth-topic)");
  options.depth_folder.clear();
  options.depth_topic = kTopic;  // colour images as depth
  auto sequence = ImageSequence::Open(folder, options);
  Frame frame;
  ASSERT_TRUE(sequence->Next(&frame));
  EXPECT_EQ(frame.error, "depth encoding 'bgr8' is not read (16UC1, mono16 or 32FC1 are)");
  EXPECT_TRUE(frame.image.empty());

  if (!testing::CanWriteRos1Bag()) GTEST_SKIP() << "built without rosbag_storage";
  const std::string bag = dir_.File("rgbd.bag");
  testing::WriteRos1Bag(bag, kTopic, images, BagEncoding::kBgr8);
  testing::AddRos1Topic(bag, "/camera/depth", DepthMaps(images), BagEncoding::kDepth16);
  options.depth_topic = "/camera/depth";
  options.depth_units_per_metre = 0;  // millimetres
  ExpectDepthMaps(*ImageSequence::Open(bag, options), 6, 1000);
}

// The CLI on a bag finds the loop closures it finds on the same images in a folder.
TEST_F(BagTest, CommandLineOnBagsAsOnTheirImages) {
  const std::vector<BagImage> images = RouteImages(*route_, route_->size());
  fs::create_directories(dir_.File("images"));
  for (size_t i = 0; i < images.size(); ++i) {
    cv::imwrite(dir_.File("images/" + std::to_string(i + 1) + ".png"), images[i].pixels);
  }
  WriteRos2Bag(dir_.File("ros2"), kTopic, images, BagEncoding::kBgr8);
  std::vector<std::string> inputs = {dir_.File("images"), dir_.File("ros2")};
  if (testing::CanWriteRos1Bag()) {
    testing::WriteRos1Bag(dir_.File("walk.bag"), kTopic, images, BagEncoding::kBgr8);
    inputs.push_back(dir_.File("walk.bag"));
  }
  std::vector<std::vector<std::pair<int, std::vector<ImageIndex>>>> loops;
  for (size_t i = 0; i < inputs.size(); ++i) {
    const std::string csv = dir_.File("run" + std::to_string(i) + ".csv");
    const Outcome outcome =
        Memloop("run " + inputs[i] + (i > 0 ? std::string(" --topic ") + kTopic : "") + " --out " +
                csv + " --set memory.max_wm_locations=20");
    ASSERT_EQ(outcome.exit_code, 0) << outcome.output;
    loops.emplace_back();
    for (const RunRow& row : ReadRunCsv(csv)) {
      if (!row.matched_images.empty()) loops.back().emplace_back(row.image, row.matched_images);
      if (i > 0) {
        EXPECT_NEAR(row.timestamp, 1500 + 0.1 * row.image, 1e-6);
      }
    }
  }
  ASSERT_GT(loops[0].size(), 20u);
  for (size_t i = 1; i < loops.size(); ++i) EXPECT_EQ(loops[i], loops[0]) << inputs[i];
  const Outcome unknown = Memloop("run " + dir_.File("ros2") + " --topic /camera/left");
  EXPECT_EQ(unknown.exit_code, 1);
  EXPECT_TRUE(Contains(unknown.output,
                       "no topic /camera/left in the bag; its image topics: "
                       "/camera/image_raw"))
      << unknown.output;
}

}  // namespace
}  // namespace memloop
