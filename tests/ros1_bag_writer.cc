#include "ros_bag_writers.h"

#ifdef MEMLOOP_HAVE_ROSBAG
#include <rosbag/bag.h>
#include <sensor_msgs/CompressedImage.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/Imu.h>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#endif

namespace memloop::testing {

using ::memloop::BagEncoding;
using ::memloop::BagImage;

#ifdef MEMLOOP_HAVE_ROSBAG
bool CanWriteRos1Bag() { return true; }

namespace {

void WriteImages(rosbag::Bag& bag, const std::string& topic, const std::vector<BagImage>& images,
                 BagEncoding encoding) {
  for (const BagImage& image : images) {
    const ros::Time recorded(image.recorded);
    if (encoding == BagEncoding::kPng) {
      sensor_msgs::CompressedImage message;
      message.header.stamp = ros::Time(image.stamp);
      message.format = "png";
      cv::imencode(".png", image.pixels, message.data);
      bag.write(topic, recorded, message);
      continue;
    }
    sensor_msgs::Image message;
    message.header.stamp = ros::Time(image.stamp);
    cv::Mat pixels = image.pixels;
    message.encoding = "bgr8";
    if (encoding == BagEncoding::kRgb8)
      cv::cvtColor(image.pixels, pixels, cv::COLOR_BGR2RGB), message.encoding = "rgb8";
    if (encoding == BagEncoding::kMono8)
      cv::cvtColor(image.pixels, pixels, cv::COLOR_BGR2GRAY), message.encoding = "mono8";
    if (encoding == BagEncoding::kDepth16) message.encoding = "16UC1";
    pixels = pixels.clone();
    message.height = pixels.rows;
    message.width = pixels.cols;
    message.step = static_cast<uint32_t>(pixels.step[0]);
    message.data.assign(pixels.data, pixels.data + pixels.total() * pixels.elemSize());
    bag.write(topic, recorded, message);
  }
}

}  // namespace

void WriteRos1Bag(const std::string& path, const std::string& topic,
                  const std::vector<BagImage>& images, BagEncoding encoding) {
  rosbag::Bag bag(path, rosbag::bagmode::Write);
  WriteImages(bag, topic, images, encoding);
  // A topic of another type, which the reader must leave out.
  sensor_msgs::Imu imu;
  imu.header.stamp = ros::Time(images.front().stamp);
  bag.write("/imu", ros::Time(images.front().recorded), imu);
}

void AddRos1Topic(const std::string& path, const std::string& topic,
                  const std::vector<BagImage>& images, BagEncoding encoding) {
  rosbag::Bag bag(path, rosbag::bagmode::Append);
  WriteImages(bag, topic, images, encoding);
}
#else
bool CanWriteRos1Bag() { return false; }
void AddRos1Topic(const std::string&, const std::string&, const std::vector<BagImage>&,
                  BagEncoding) {}
void WriteRos1Bag(const std::string&, const std::string&, const std::vector<BagImage>&,
                  BagEncoding) {}
#endif

}  // namespace memloop::testing
