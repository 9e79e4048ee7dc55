// ROS 2 bags (sqlite3 storage, CDR messages written byte by byte) of generated images: what
// `memloop generate --layout ros2-bag` writes, and the tests' bags.
#pragma once

#include <opencv2/core.hpp>
#include <string>
#include <vector>

namespace memloop {

struct BagImage {
  cv::Mat pixels;       // 8-bit BGR; kDepth16: 16-bit depth, one channel
  double stamp = 0;     // header stamp, seconds
  double recorded = 0;  // the recorder's time, seconds
};

enum class BagEncoding { kBgr8, kRgb8, kMono8, kPng, kDepth16 };

// A ROS 2 bag folder (`folder`/metadata.yaml, `folder`/<name>_0.db3) with a std_msgs/msg/String
// topic /chatter and `images` on `topic` (sensor_msgs/msg/Image, or CompressedImage for kPng).
// Throws InputError naming the file when it cannot be written.
void WriteRos2Bag(const std::string& folder, const std::string& topic,
                  const std::vector<BagImage>& images, BagEncoding encoding);
// Another image topic in the bag WriteRos2Bag wrote.
void AddRos2Topic(const std::string& folder, const std::string& topic,
                  const std::vector<BagImage>& images, BagEncoding encoding);

}  // namespace memloop
