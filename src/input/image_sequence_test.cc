#include "memloop/image_sequence.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>

#include "memloop/errors.h"
#include "temp_dir.h"

namespace memloop {
namespace {

TEST(ImageSequenceTest, NaturalOrder) {
  EXPECT_TRUE(NaturalLess("2.jpg", "10.jpg"));
  EXPECT_FALSE(NaturalLess("10.jpg", "2.jpg"));
  EXPECT_TRUE(NaturalLess("img9_b.png", "img10_a.png"));
  EXPECT_TRUE(NaturalLess("a.jpg", "b.jpg"));
  EXPECT_TRUE(NaturalLess("frame2.png", "frame002b.png"));
}

TEST(ImageSequenceTest, FolderInNaturalOrderWithUnreadableFilesReported) {
  testing::TempDir dir;
  const cv::Mat image(20, 30, CV_8UC3, cv::Scalar(10, 20, 30));
  for (const char* name : {"10.png", "2.png", "1.png"}) cv::imwrite(dir.File(name), image);
  std::ofstream(dir.File("3.png")) << "not really a png";
  std::ofstream(dir.File(".hidden")) << "ignored";
  EXPECT_EQ(ListFolder(dir.path().string()),
            (std::vector<std::string>{"1.png", "2.png", "3.png", "10.png"}));

  auto sequence = ImageSequence::Open(dir.path().string());
  EXPECT_EQ(sequence->size(), 4);
  Frame frame;
  std::vector<std::string> readable;
  std::vector<std::string> unreadable;
  while (sequence->Next(&frame)) {
    (frame.error.empty() ? readable : unreadable).push_back(frame.name);
    if (frame.name == "10.png") {
      EXPECT_EQ(frame.index, 3);
    }
  }
  EXPECT_EQ(readable, (std::vector<std::string>{"1.png", "2.png", "10.png"}));
  EXPECT_EQ(unreadable, (std::vector<std::string>{"3.png"}));
}

// --depth DIR: each image's depth map in metres (16-bit: millimetres, or --depth-scale's units);
// an image without one goes without; one that does not read, or is not its image's size, makes
// its frame an error naming the depth map.
TEST(ImageSequenceTest, DepthMapsOfAFolderAndTheirFaults) {
  testing::TempDir dir;
  std::filesystem::create_directories(dir.File("images"));
  std::filesystem::create_directories(dir.File("depth"));
  for (int i = 1; i <= 4; ++i) {
    cv::imwrite(dir.File("images/" + std::to_string(i) + ".png"), cv::Mat(6, 8, CV_8UC3));
  }
  cv::imwrite(dir.File("depth/1.png"), cv::Mat(6, 8, CV_16UC1, cv::Scalar(1500)));
  std::ofstream(dir.File("depth/2.png")) << "not a PNG";
  cv::imwrite(dir.File("depth/3.png"), cv::Mat(3, 4, CV_16UC1, cv::Scalar(1500)));
  SequenceOptions options;
  options.depth_folder = dir.File("depth");
  for (double units : {0.0, 5000.0}) {
    options.depth_units_per_metre = units;
    auto sequence = ImageSequence::Open(dir.File("images"), options);
    Frame frame;
    ASSERT_TRUE(sequence->Next(&frame));
    ASSERT_TRUE(frame.error.empty()) << frame.error;
    ASSERT_EQ(frame.depth.type(), CV_32FC1);
    EXPECT_FLOAT_EQ(frame.depth.at<float>(2, 3), units == 0 ? 1.5f : 0.3f);
    ASSERT_TRUE(sequence->Next(&frame));
    EXPECT_EQ(frame.error, "depth map " + dir.File("depth/2.png") + ": not a readable image");
    EXPECT_TRUE(frame.image.empty());
    ASSERT_TRUE(sequence->Next(&frame));
    EXPECT_EQ(frame.error, "depth map " + dir.File("depth/3.png") +
                               " is 4x3, its image 8x6 (a depth map registered to the image has "
                               "its size)");
    EXPECT_TRUE(frame.image.empty() && frame.depth.empty());
    ASSERT_TRUE(sequence->Next(&frame));
    EXPECT_TRUE(frame.error.empty());
    EXPECT_FALSE(frame.image.empty());
    EXPECT_TRUE(frame.depth.empty());  // none of its name: without
  }
}

void ExpectInputError(const std::string& path, const std::string& reason) {
  try {
    ImageSequence::Open(path);
    FAIL() << "opened " << path;
  } catch (const InputError& error) {
    EXPECT_EQ(error.path(), path);
    EXPECT_NE(std::string(error.what()).find(reason), std::string::npos) << error.what();
  }
}

TEST(ImageSequenceTest, MissingEmptyAndNotAVideo) {
  testing::TempDir dir;
  ExpectInputError(dir.File("nowhere"), "no such file or folder");
  ExpectInputError(dir.path().string(), "holds no image");
  std::ofstream(dir.File("clip.avi")) << "not a video";
  ExpectInputError(dir.File("clip.avi"), "cannot be opened as a video");
}

}  // namespace
}  // namespace memloop
