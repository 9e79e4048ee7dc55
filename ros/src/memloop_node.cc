// memloop_node: loop closures of an image topic, live. The ROS 1 layer over LiveDetector (the
// stream, its thread and drop policy) and node_configuration.h (parameters): subscribing,
// decoding, publishing, services, diagnostics and shutdown. A ROS 2 node would replace this file.
//
//   memloop_node image:=/camera/image_raw _database:=map.db _resume:=true
//
// Subscribes: image (sensor_msgs/Image; with ~image_transport compressed, image/compressed as
// sensor_msgs/CompressedImage); with ~depth, depth too (sensor_msgs/Image, 16UC1 or 32FC1,
// registered to image), each image paired with the depth map stamped nearest it. Publishes:
// ~loop_closures (memloop_msgs/LoopClosure), /diagnostics (1 Hz). Services: ~save
// (std_srvs/Trigger), ~pause (std_srvs/SetBool). docs/ros.md.
#include <diagnostic_msgs/DiagnosticArray.h>
#include <image_transport/image_transport.h>
#include <memloop_msgs/LoopClosure.h>
#include <message_filters/subscriber.h>
#include <message_filters/sync_policies/approximate_time.h>
#include <message_filters/synchronizer.h>
#include <ros/ros.h>
#include <sensor_msgs/CompressedImage.h>
#include <sensor_msgs/Image.h>
#include <std_srvs/SetBool.h>
#include <std_srvs/Trigger.h>

#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <mutex>
#include <set>

#include "input/ros_image.h"
#include "memloop/errors.h"
#include "memloop/live_detector.h"
#include "node_configuration.h"

namespace memloop::node {
namespace {

// Seconds without a publisher on the image topic before the node says so.
constexpr double kNoPublisherWarningS = 5.0;
// Encodings of depth maps: a topic remapped to the wrong camera stream, not images to match.
const std::set<std::string> kDepthEncodings = {"16UC1", "32FC1"};

// Every private parameter, as text, by its name below the node ("memory/time_limit_ms").
std::vector<std::pair<std::string, std::string>> PrivateParameters(const ros::NodeHandle& node) {
  std::vector<std::string> names;
  ros::param::getParamNames(names);
  const std::string prefix = node.getNamespace() + "/";
  std::vector<std::pair<std::string, std::string>> parameters;
  for (const std::string& name : names) {
    if (name.rfind(prefix, 0) != 0) continue;
    XmlRpc::XmlRpcValue value;
    if (!ros::param::get(name, value)) continue;
    std::string text;
    switch (value.getType()) {
      case XmlRpc::XmlRpcValue::TypeBoolean:
        text = static_cast<bool>(value) ? "true" : "false";
        break;
      case XmlRpc::XmlRpcValue::TypeInt:
        text = std::to_string(static_cast<int>(value));
        break;
      case XmlRpc::XmlRpcValue::TypeDouble: {
        char number[64];
        std::snprintf(number, sizeof(number), "%.17g", static_cast<double>(value));
        text = number;
        break;
      }
      case XmlRpc::XmlRpcValue::TypeString:
        text = static_cast<std::string>(value);
        break;
      default:
        throw ParameterError(name, name + ": not a number, a boolean or a string");
    }
    parameters.emplace_back(name.substr(prefix.size()), text);
  }
  return parameters;
}

ros::Time Stamp(double seconds) {
  return HasTimestamp(seconds) && seconds >= 0 ? ros::Time(seconds) : ros::Time();
}

class MemloopNode {
 public:
  explicit MemloopNode(const NodeConfiguration& configuration)
      : private_(ros::NodeHandle("~")),
        transport_(public_),
        loop_closures_(private_.advertise<memloop_msgs::LoopClosure>("loop_closures", 100)),
        diagnostics_(public_.advertise<diagnostic_msgs::DiagnosticArray>("/diagnostics", 10)),
        database_(configuration.database),
        live_(
            configuration.options, configuration.database, configuration.mode,
            configuration.queue ? StreamPolicy::kQueue : StreamPolicy::kLatest,
            [this](const LiveResult& result) { Publish(result); },
            [this](const std::string& message, bool fatal) { Report(message, fatal); }) {
    if (!configuration.notice.empty()) ROS_INFO("%s", configuration.notice.c_str());
    ROS_INFO("memloop: map %s (%s), images from %d on, %s", database_.c_str(),
             configuration.mode == MapMode::kResume       ? "resumed"
             : configuration.mode == MapMode::kNewSession ? "new session"
             : configuration.options.memory.localization  ? "localization, not modified"
                                                          : "new",
             live_.next_index(),
             configuration.queue ? "every image in order (~queue)" : "the newest image");
    // roscpp calls one subscription's callbacks one at a time, in order: Push() sees the stream's
    // order. A long queue: the node counts what it drops, roscpp would drop silently.
    const uint32_t queue = 1000;
    if (configuration.depth) {
      // Pairs by header stamps (a camera driver's colour and depth streams are not in step);
      // an image without a depth map within the pairing's reach is not processed.
      depth_units_per_metre_ = configuration.depth_units_per_metre;
      colour_.subscribe(public_, "image", queue);
      depth_.subscribe(public_, "depth", queue);
      pairs_ = std::make_unique<Pairing>(PairingPolicy(100), colour_, depth_);
      pairs_->registerCallback(&MemloopNode::OnImageWithDepth, this);
      topic_ = colour_.getTopic();
    } else if (configuration.image_transport == "compressed") {
      topic_ = public_.resolveName("image") + "/compressed";
      compressed_ = public_.subscribe(topic_, queue, &MemloopNode::OnCompressed, this);
    } else {
      image_ = transport_.subscribe("image", queue, &MemloopNode::OnImage, this,
                                    image_transport::TransportHints("raw"));
      topic_ = image_.getTopic();
    }
    save_ = private_.advertiseService("save", &MemloopNode::OnSave, this);
    pause_ = private_.advertiseService("pause", &MemloopNode::OnPause, this);
    diagnostics_timer_ = public_.createWallTimer(
        ros::WallDuration(1.0), [this](const ros::WallTimerEvent&) { PublishDiagnostics(); });
    no_publisher_timer_ = public_.createWallTimer(
        ros::WallDuration(kNoPublisherWarningS),
        [this](const ros::WallTimerEvent&) { WarnIfNoPublisher(); }, /*oneshot=*/true);
  }

  // Closes the map (complete: it resumes from the last image processed). Said on stdout and
  // stderr directly: ROS's logging has shut down with the node.
  void Stop() {
    live_.Stop();
    const LiveStatus status = live_.Status();
    if (!status.failure.empty()) {
      std::fprintf(stderr, "memloop: stopped on a failure: %s\n", status.failure.c_str());
      return;
    }
    std::printf(
        "memloop: map %s closed after %lld images (%lld dropped); it resumes with "
        "_resume:=true\n",
        database_.c_str(), status.processed, status.dropped);
  }

  bool failed() const { return !live_.Status().failure.empty(); }

 private:
  void OnImage(const sensor_msgs::ImageConstPtr& message) {
    if (kDepthEncodings.count(message->encoding) > 0) {
      Skip(message->encoding,
           "a depth map's encoding, not a camera image's: remap image to the "
           "camera's image topic");
      return;
    }
    std::string error;
    const cv::Mat image = DecodeRawImage(RawImageOf(*message), &error);
    if (image.empty()) {
      Skip(message->encoding, error);
      return;
    }
    Take(image, message->header);
  }

  void OnImageWithDepth(const sensor_msgs::ImageConstPtr& message,
                        const sensor_msgs::ImageConstPtr& depth_message) {
    std::string error;
    const cv::Mat image = DecodeRawImage(RawImageOf(*message), &error);
    if (image.empty()) {
      Skip(message->encoding, error);
      return;
    }
    const cv::Mat depth =
        DecodeRawDepth(RawImageOf(*depth_message), depth_units_per_metre_, &error);
    if (depth.empty()) {
      Skip("depth " + depth_message->encoding, error);
      return;
    }
    Take(image, message->header, depth);
  }

  void OnCompressed(const sensor_msgs::CompressedImageConstPtr& message) {
    std::string error;
    const cv::Mat image = DecodeCompressedImage(message->data.data(), message->data.size(), &error);
    if (image.empty()) {
      Skip("compressed (" + message->format + ")", error);
      return;
    }
    Take(image, message->header);
  }

  void Take(const cv::Mat& image, const std_msgs::Header& header, const cv::Mat& depth = {}) {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      frame_id_ = header.frame_id;
    }
    ImageInfo info;
    info.timestamp = header.stamp.toSec();
    char name[64];
    std::snprintf(name, sizeof(name), " %.6f", info.timestamp);
    info.name = topic_ + name;  // as `memloop run BAG` names a bag's image
    live_.Push(image, depth, info);
  }

  // An image that cannot be read: one error line per encoding, every one counted.
  void Skip(const std::string& encoding, const std::string& reason) {
    live_.Skip();
    std::lock_guard<std::mutex> lock(mutex_);
    if (!refused_encodings_.insert(encoding).second) return;
    ROS_ERROR(
        "memloop: skipping the images of encoding %s on %s: %s (counted in /diagnostics; "
        "said once)",
        encoding.c_str(), topic_.c_str(), reason.c_str());
  }

  void Publish(const LiveResult& live) {
    const Result& result = live.result;
    if (!result.HasLoopClosure()) return;
    memloop_msgs::LoopClosure message;
    message.header.stamp = Stamp(live.image.timestamp);
    {
      std::lock_guard<std::mutex> lock(mutex_);
      message.header.frame_id = frame_id_;
    }
    message.query_stamp = message.header.stamp;
    message.match_stamp = Stamp(live.match_timestamp);
    message.query_image = result.image_index;
    message.match_image = result.loop_closure_images.front();
    message.match_images.assign(result.loop_closure_images.begin(),
                                result.loop_closure_images.end());
    message.query_location = result.location_id == kNoLocation ? 0 : result.location_id;
    message.match_location = result.loop_closure_id;
    message.query_session = result.session;
    message.match_session = live.match_session;
    message.hypothesis_value = result.hypothesis_value;
    const LoopGeometry& geometry = result.loop_closure_geometry;
    message.inliers = geometry.correspondences > 0 ? static_cast<int>(geometry.inliers.size())
                                                   : result.hypothesis_inliers;
    message.has_pose = geometry.has_pose;
    message.metric = geometry.translation_metric;
    if (geometry.has_pose) {
      auto& pose = message.pose.pose;
      pose.position.x = geometry.translation[0];
      pose.position.y = geometry.translation[1];
      pose.position.z = geometry.translation[2];
      pose.orientation.x = geometry.quaternion[0];
      pose.orientation.y = geometry.quaternion[1];
      pose.orientation.z = geometry.quaternion[2];
      pose.orientation.w = geometry.quaternion[3];
      // Metres with depth: 3 cm (1 sigma, about the 95th percentile on tum_fr1_rpy); else a
      // direction of unit length, its scale unknown (1e6). Rotation: 0.05 rad.
      const double translation_variance = geometry.translation_metric ? 0.03 * 0.03 : 1e6;
      for (int i = 0; i < 3; ++i) message.pose.covariance[i * 6 + i] = translation_variance;
      for (int i = 3; i < 6; ++i) message.pose.covariance[i * 6 + i] = 0.05 * 0.05;
    }
    loop_closures_.publish(message);
  }

  void Report(const std::string& message, bool fatal) {
    if (!fatal) {
      ROS_ERROR("memloop: %s", message.c_str());
      return;
    }
    ROS_FATAL("memloop: stopping: %s", message.c_str());
    ros::requestShutdown();
  }

  bool OnSave(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& response) {
    try {
      live_.Save();
      response.success = true;
      response.message = "saved " + database_ + ": it resumes after image " +
                         std::to_string(live_.Status().last.image_index);
    } catch (const std::exception& error) {
      response.success = false;
      response.message = error.what();
    }
    return true;
  }

  bool OnPause(std_srvs::SetBool::Request& request, std_srvs::SetBool::Response& response) {
    live_.SetPaused(request.data);
    response.success = true;
    response.message = request.data ? "paused: images are dropped (counted) until unpaused"
                                    : "processing images again";
    return true;
  }

  void WarnIfNoPublisher() {
    const uint32_t publishers = pairs_        ? colour_.getSubscriber().getNumPublishers()
                                : compressed_ ? compressed_.getNumPublishers()
                                              : image_.getNumPublishers();
    if (publishers == 0) {
      ROS_WARN("memloop: no publisher on %s after %.0f s: remap image:=<the camera's topic>",
               topic_.c_str(), kNoPublisherWarningS);
    }
  }

  void PublishDiagnostics() {
    const LiveStatus status = live_.Status();
    diagnostic_msgs::DiagnosticStatus entry;
    entry.name = "memloop: loop closure detection";
    entry.hardware_id = database_;
    entry.level = !status.failure.empty() ? diagnostic_msgs::DiagnosticStatus::ERROR
                  : status.received == 0  ? diagnostic_msgs::DiagnosticStatus::WARN
                                          : diagnostic_msgs::DiagnosticStatus::OK;
    entry.message = !status.failure.empty() ? status.failure
                    : status.received == 0  ? "no image received on " + topic_
                    : status.paused         ? "paused"
                                            : "running";
    const auto add = [&](const std::string& key, const std::string& value) {
      diagnostic_msgs::KeyValue pair;
      pair.key = key;
      pair.value = value;
      entry.values.push_back(pair);
    };
    const auto number = [](double value) {
      char text[32];
      std::snprintf(text, sizeof(text), "%.1f", value);
      return std::string(text);
    };
    add("images received", std::to_string(status.received));
    add("images processed", std::to_string(status.processed));
    add("images dropped", std::to_string(status.dropped));
    add("images skipped", std::to_string(status.refused));
    add("images waiting", std::to_string(status.waiting));
    add("loop closures", std::to_string(status.loop_closures));
    add("iteration time median (ms)", number(status.median_iteration_ms));
    add("iteration time max (ms)", number(status.max_iteration_ms));
    add("latency median (ms)", number(status.median_latency_ms));
    add("latency max (ms)", number(status.max_latency_ms));
    add("WM size", std::to_string(status.last.wm_size));
    add("STM size", std::to_string(status.last.stm_size));
    add("LTM size", std::to_string(status.last.ltm_size));
    add("dictionary size", std::to_string(status.last.dictionary_size));
    add("paused", status.paused ? "true" : "false");
    diagnostic_msgs::DiagnosticArray array;
    array.header.stamp = ros::Time::now();
    array.status.push_back(entry);
    diagnostics_.publish(array);
  }

  ros::NodeHandle public_;
  ros::NodeHandle private_;
  image_transport::ImageTransport transport_;
  ros::Publisher loop_closures_;
  ros::Publisher diagnostics_;
  std::string database_;
  std::string topic_;
  std::mutex mutex_;  // frame_id_ and refused_encodings_
  std::string frame_id_;
  std::set<std::string> refused_encodings_;
  LiveDetector live_;  // after the publishers its callback uses
  image_transport::Subscriber image_;
  ros::Subscriber compressed_;
  // ~depth: the image and depth topics, paired by stamp.
  using PairingPolicy =
      message_filters::sync_policies::ApproximateTime<sensor_msgs::Image, sensor_msgs::Image>;
  using Pairing = message_filters::Synchronizer<PairingPolicy>;
  message_filters::Subscriber<sensor_msgs::Image> colour_, depth_;
  std::unique_ptr<Pairing> pairs_;
  double depth_units_per_metre_ = 1000;
  ros::ServiceServer save_, pause_;
  ros::WallTimer diagnostics_timer_, no_publisher_timer_;
};

// SIGINT (Ctrl-C) and SIGTERM (rosnode kill, roslaunch's second signal) end the spin; the map is
// then closed.
void RequestShutdown(int) { ros::requestShutdown(); }

std::string DefaultDatabase() {
  if (const char* home = std::getenv("ROS_HOME")) return std::string(home) + "/memloop.db";
  const char* home = std::getenv("HOME");
  return std::string(home != nullptr ? home : ".") + "/.ros/memloop.db";
}

}  // namespace
}  // namespace memloop::node

int main(int argc, char** argv) {
  setvbuf(stdout, nullptr, _IOLBF, 0);  // a log file or roslaunch's pipe gets each line as said
  ros::init(argc, argv, "memloop", ros::init_options::NoSigintHandler);
  std::signal(SIGINT, memloop::node::RequestShutdown);
  std::signal(SIGTERM, memloop::node::RequestShutdown);
  ros::NodeHandle node("~");
  std::unique_ptr<memloop::node::MemloopNode> memloop_node;
  try {
    const memloop::node::NodeConfiguration configuration = memloop::node::Configure(
        memloop::node::PrivateParameters(node), memloop::node::DefaultDatabase());
    memloop_node = std::make_unique<memloop::node::MemloopNode>(configuration);
  } catch (const std::exception& error) {
    ROS_FATAL("memloop: %s", error.what());
    return 1;
  }
  ros::MultiThreadedSpinner spinner(2);  // a ~save waits for the stream; images still come
  spinner.spin();
  memloop_node->Stop();
  return memloop_node->failed() ? 1 : 0;
}
