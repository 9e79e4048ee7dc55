// sensor_msgs Image and CompressedImage payloads as OpenCV images, for the bag readers.
#pragma once

#include <cstdint>
#include <opencv2/core.hpp>
#include <string>

namespace memloop {

struct RawImage {
  uint32_t height = 0, width = 0, step = 0;
  std::string encoding;  // "mono8", "bgr8", "rgb8", "bgra8", "rgba8", "mono16", "8UC1", "8UC3"...
  bool big_endian = false;
  const uint8_t* data = nullptr;
  size_t size = 0;
};

// The pixels of a sensor_msgs/Image: ROS 1's C++ message, or any type with its fields.
template <typename ImageMessage>
RawImage RawImageOf(const ImageMessage& image) {
  RawImage raw;
  raw.height = image.height;
  raw.width = image.width;
  raw.step = image.step;
  raw.encoding = image.encoding;
  raw.big_endian = image.is_bigendian != 0;
  raw.data = image.data.data();
  raw.size = image.data.size();
  return raw;
}

// An 8-bit gray or BGR image (a copy), or empty with `error` saying why (an encoding memloop does
// not read, data shorter than height x step).
cv::Mat DecodeRawImage(const RawImage& image, std::string* error);
// A depth image (16UC1 or mono16 in units of 1 / units_per_metre, 32FC1 in metres) in metres,
// CV_32F, 0 where there is no reading; or empty with `error`.
cv::Mat DecodeRawDepth(const RawImage& image, double units_per_metre, std::string* error);
// A CompressedImage's bytes (JPEG, PNG), or empty with `error`.
cv::Mat DecodeCompressedImage(const uint8_t* data, size_t size, std::string* error);

}  // namespace memloop
