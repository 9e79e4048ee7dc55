#include "memloop/image_sequence.h"

#include <gtest/gtest.h>

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
