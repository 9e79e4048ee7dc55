// ROS 1 bags through Debian's rosbag_storage, messages deserialized as sensor_msgs types. Built
// when the library is found (MEMLOOP_HAVE_ROSBAG); without it, a .bag is refused by name.
#include "input/bag_sequence.h"
#include "memloop/errors.h"

#ifdef MEMLOOP_HAVE_ROSBAG
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <sensor_msgs/CompressedImage.h>
#include <sensor_msgs/Image.h>

#include "input/ros_image.h"
#endif

namespace memloop {

#ifdef MEMLOOP_HAVE_ROSBAG
namespace {

class Ros1Bag : public BagSource {
 public:
  explicit Ros1Bag(const std::string& path) : path_(path) {
    try {
      bag_.open(path, rosbag::bagmode::Read);
      rosbag::View all(bag_);
      for (const rosbag::ConnectionInfo* connection : all.getConnections()) {
        rosbag::View one(bag_, rosbag::TopicQuery(connection->topic));
        bool known = false;
        for (const BagTopic& topic : topics_) known = known || topic.name == connection->topic;
        if (!known) topics_.push_back({connection->topic, connection->datatype, one.size()});
      }
    } catch (const rosbag::BagException& failure) {
      throw InputError(path, std::string("not a readable ROS 1 bag (") + failure.what() + ")");
    }
  }

  std::vector<BagTopic> Topics() const override { return topics_; }

  std::vector<double> Select(const BagTopic& topic) override {
    compressed_ = topic.type == "sensor_msgs/CompressedImage";
    view_ = std::make_unique<rosbag::View>(bag_, rosbag::TopicQuery(topic.name));
    std::vector<double> times;
    for (const rosbag::MessageInstance& message : *view_) {
      messages_.push_back(message);
      times.push_back(message.getTime().toSec());
    }
    return times;
  }

  void Decode(size_t i, Frame* frame) override {
    const rosbag::MessageInstance& message = messages_[i];
    const double recorded = message.getTime().toSec();
    try {
      if (compressed_) {
        const auto image = message.instantiate<sensor_msgs::CompressedImage>();
        frame->timestamp = image->header.stamp.isZero() ? recorded : image->header.stamp.toSec();
        frame->image = DecodeCompressedImage(image->data.data(), image->data.size(), &frame->error);
        return;
      }
      const auto image = message.instantiate<sensor_msgs::Image>();
      frame->timestamp = image->header.stamp.isZero() ? recorded : image->header.stamp.toSec();
      frame->image = DecodeRawImage(RawImageOf(*image), &frame->error);
    } catch (const std::exception& failure) {  // rosbag and ros::serialization exceptions
      frame->error = std::string("message does not decode (") + failure.what() + ")";
    }
  }

  cv::Mat DecodeDepth(size_t i, double units_per_metre, std::string* error) override {
    try {
      const auto image = messages_[i].instantiate<sensor_msgs::Image>();
      if (!image) {
        *error = "the depth topic's messages are not sensor_msgs/Image";
        return cv::Mat();
      }
      return DecodeRawDepth(RawImageOf(*image), units_per_metre, error);
    } catch (const std::exception& failure) {
      *error = std::string("depth message does not decode (") + failure.what() + ")";
      return cv::Mat();
    }
  }

 private:
  std::string path_;
  rosbag::Bag bag_;
  std::vector<BagTopic> topics_;
  bool compressed_ = false;
  std::unique_ptr<rosbag::View> view_;  // the selected topic's (messages_ point into it)
  std::vector<rosbag::MessageInstance> messages_;
};

}  // namespace

bool Ros1BagSupported() { return true; }
std::unique_ptr<BagSource> OpenRos1Bag(const std::string& path) {
  return std::make_unique<Ros1Bag>(path);
}
#else
bool Ros1BagSupported() { return false; }
std::unique_ptr<BagSource> OpenRos1Bag(const std::string& path) {
  throw InputError(path,
                   "a ROS 1 bag: this memloop was built without rosbag_storage (install "
                   "librosbag-storage-dev and libsensor-msgs-dev, and build again)");
}
#endif

}  // namespace memloop
