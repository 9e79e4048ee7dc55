// A consumer of memloop's loop closures: prints each one, as a SLAM back-end would take it.
//   loop_closure_listener loop_closures:=/memloop/loop_closures
#include <memloop_msgs/LoopClosure.h>
#include <ros/ros.h>

void OnLoopClosure(const memloop_msgs::LoopClosure& loop) {
  ROS_INFO("image %d (t=%.3f) closes a loop with image %d (t=%.3f), p=%.3f, %d inliers%s",
           loop.query_image, loop.query_stamp.toSec(), loop.match_image, loop.match_stamp.toSec(),
           loop.hypothesis_value, loop.inliers, loop.has_pose ? ", with a relative pose" : "");
}

int main(int argc, char** argv) {
  ros::init(argc, argv, "loop_closure_listener");
  ros::NodeHandle node;
  ros::Subscriber subscriber = node.subscribe("loop_closures", 100, OnLoopClosure);
  ros::spin();
  return 0;
}
