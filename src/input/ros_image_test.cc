#include "input/ros_image.h"

#include <gtest/gtest.h>

#include <cstring>
#include <limits>
#include <vector>

namespace memloop {
namespace {

RawImage Raw(const std::vector<uint8_t>& bytes, uint32_t width, uint32_t height, uint32_t step,
             const std::string& encoding, bool big_endian = false) {
  RawImage raw;
  raw.width = width, raw.height = height, raw.step = step;
  raw.encoding = encoding;
  raw.big_endian = big_endian;
  raw.data = bytes.data();
  raw.size = bytes.size();
  return raw;
}

TEST(RosImageTest, DepthImagesBecomeMetres) {
  // 2x1 16UC1, little endian: 1500 and 0 (no reading); a row step of 6 bytes (2 of padding).
  const std::vector<uint8_t> little = {0xDC, 0x05, 0x00, 0x00, 0xFF, 0xFF};
  std::string error;
  cv::Mat metres = DecodeRawDepth(Raw(little, 2, 1, 6, "16UC1"), 1000, &error);
  ASSERT_TRUE(error.empty()) << error;
  ASSERT_EQ(metres.type(), CV_32FC1);
  EXPECT_FLOAT_EQ(metres.at<float>(0, 0), 1.5f);
  EXPECT_FLOAT_EQ(metres.at<float>(0, 1), 0);
  // Big endian, 5000 units per metre (TUM's): 0x05DC = 1500 -> 0.3 m.
  const std::vector<uint8_t> big = {0x05, 0xDC, 0x00, 0x01};
  metres = DecodeRawDepth(Raw(big, 2, 1, 4, "mono16", true), 5000, &error);
  EXPECT_FLOAT_EQ(metres.at<float>(0, 0), 0.3f);
  EXPECT_FLOAT_EQ(metres.at<float>(0, 1), 1.0f / 5000);

  // 32FC1 in metres; NaN (no reading) becomes 0.
  const float values[2] = {2.25f, std::numeric_limits<float>::quiet_NaN()};
  std::vector<uint8_t> floats(sizeof(values));
  std::memcpy(floats.data(), values, sizeof(values));
  metres = DecodeRawDepth(Raw(floats, 2, 1, 8, "32FC1"), 1000, &error);
  EXPECT_FLOAT_EQ(metres.at<float>(0, 0), 2.25f);
  EXPECT_FLOAT_EQ(metres.at<float>(0, 1), 0);
}

TEST(RosImageTest, DepthOfAnotherEncodingOrCutShortIsRefused) {
  const std::vector<uint8_t> bytes(12, 0);
  std::string error;
  EXPECT_TRUE(DecodeRawDepth(Raw(bytes, 2, 2, 6, "bgr8"), 1000, &error).empty());
  EXPECT_NE(error.find("depth encoding 'bgr8' is not read (16UC1, mono16 or 32FC1 are)"),
            std::string::npos)
      << error;
  error.clear();
  EXPECT_TRUE(DecodeRawDepth(Raw(bytes, 4, 2, 8, "32FC1"), 1000, &error).empty());
  EXPECT_NE(error.find("shorter than its size says"), std::string::npos) << error;
}

}  // namespace
}  // namespace memloop
