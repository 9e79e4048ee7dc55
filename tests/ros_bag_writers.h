// ROS 1 bags written by the tests from generated images through rosbag_storage, as a robot's
// recorder would (ROS 2 bags: synthetic/ros2_bag_writer.h).
#pragma once

#include <string>
#include <vector>

#include "synthetic/ros2_bag_writer.h"

namespace memloop::testing {

// False when memloop was built without rosbag_storage.
bool CanWriteRos1Bag();
void WriteRos1Bag(const std::string& path, const std::string& topic,
                  const std::vector<BagImage>& images, BagEncoding encoding);
// Another image topic in the bag WriteRos1Bag wrote.
void AddRos1Topic(const std::string& path, const std::string& topic,
                  const std::vector<BagImage>& images, BagEncoding encoding);

}  // namespace memloop::testing
