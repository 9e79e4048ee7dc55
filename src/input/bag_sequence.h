// Images from robot recordings: ROS 1 bags (rosbag_storage) and ROS 2 bags in their SQLite
// storage (*.db3 beside metadata.yaml), topics of sensor_msgs Image or CompressedImage.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "memloop/image_sequence.h"

namespace memloop {

struct BagTopic {
  std::string name;
  std::string type;  // "sensor_msgs/Image" (ROS 1) or "sensor_msgs/msg/Image" (ROS 2)...
  long long messages = 0;
};

// One bag's messages, as the two formats give them.
class BagSource {
 public:
  virtual ~BagSource() = default;
  virtual std::vector<BagTopic> Topics() const = 0;
  // Takes `topic`'s messages in time order and returns their recording times, in seconds.
  virtual std::vector<double> Select(const BagTopic& topic) = 0;
  // Message `i` of the selection as an image (frame->image, or frame->error) and the time stamp
  // of its header (its recording time when the header has none).
  virtual void Decode(size_t i, Frame* frame) = 0;
  // Message `i` of the selection (a sensor_msgs Image) as a depth map in metres (CV_32F), or
  // empty with `error` saying why.
  virtual cv::Mat DecodeDepth(size_t i, double units_per_metre, std::string* error) = 0;
};

// Throws InputError naming `path` when it is not a readable bag of that kind.
std::unique_ptr<BagSource> OpenRos1Bag(const std::string& path);
std::unique_ptr<BagSource> OpenRos2Bag(const std::string& path);
bool Ros1BagSupported();  // built with rosbag_storage

// A ".bag" file, a ".db3" file, or a folder holding metadata.yaml.
bool IsBag(const std::string& path);

// The images of `options.topic` (or of the bag's only image topic) at `options.rate_hz` by their
// recording times; with `options.depth_topic`, each with the depth map recorded nearest it. Throws
// InputError naming `path`, listing the bag's image topics, when the topic is missing, is not of
// images, or is not given and the bag has several.
std::unique_ptr<ImageSequence> OpenBag(const std::string& path, const SequenceOptions& options);

}  // namespace memloop
