#include "input/bag_sequence.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <optional>

#include "input/dataset_listing.h"
#include "input/depth_map.h"
#include "memloop/errors.h"

namespace memloop {
namespace {

namespace fs = std::filesystem;

bool IsImageType(const std::string& type) {
  for (const char* image : {"sensor_msgs/Image", "sensor_msgs/msg/Image",
                            "sensor_msgs/CompressedImage", "sensor_msgs/msg/CompressedImage"}) {
    if (type == image) return true;
  }
  return false;
}

std::string Listed(const std::vector<BagTopic>& topics, bool images_only) {
  std::string text;
  for (const BagTopic& topic : topics) {
    if (images_only && !IsImageType(topic.type)) continue;
    text += (text.empty() ? "" : ", ") + topic.name + " (" + topic.type + ", " +
            std::to_string(topic.messages) + " messages)";
  }
  return text.empty() ? "none" : text;
}

// The topic to read: the one named, or the bag's only image topic.
BagTopic ChooseTopic(const std::string& path, const std::vector<BagTopic>& topics,
                     const std::string& wanted) {
  std::vector<BagTopic> images;
  for (const BagTopic& topic : topics) {
    if (IsImageType(topic.type)) images.push_back(topic);
    if (!wanted.empty() && topic.name == wanted) {
      if (IsImageType(topic.type)) return topic;
      throw InputError(path, "topic " + wanted + " is of " + topic.type +
                                 ", not images; the bag's image topics: " + Listed(topics, true));
    }
  }
  if (!wanted.empty()) {
    throw InputError(
        path, "no topic " + wanted + " in the bag; its image topics: " + Listed(topics, true));
  }
  if (images.empty()) {
    throw InputError(path,
                     "holds no image topic (sensor_msgs Image or CompressedImage); its "
                     "topics: " +
                         Listed(topics, false));
  }
  if (images.size() > 1) {
    throw InputError(
        path, "holds several image topics: choose one with --topic: " + Listed(topics, true));
  }
  return images.front();
}

// The depth topic of --depth-topic: a second reader of the bag, selecting that topic.
struct DepthTopic {
  std::string name;
  std::unique_ptr<BagSource> source;
  std::vector<double> times;  // recording times, in order
  double units_per_metre = 1000;
};

// --depth-topic: a topic of sensor_msgs Image (depth maps are not JPEG or PNG compressed here).
BagTopic ChooseDepthTopic(const std::string& path, const std::vector<BagTopic>& topics,
                          const std::string& wanted) {
  for (const BagTopic& topic : topics) {
    if (topic.name != wanted) continue;
    if (topic.type == "sensor_msgs/Image" || topic.type == "sensor_msgs/msg/Image") return topic;
    throw InputError(path, "depth topic " + wanted + " is of " + topic.type +
                               ", not sensor_msgs Image (16UC1 or 32FC1); the bag's image "
                               "topics: " +
                               Listed(topics, true));
  }
  throw InputError(
      path, "no depth topic " + wanted + " in the bag; its image topics: " + Listed(topics, true));
}

class BagSequence : public ImageSequence {
 public:
  BagSequence(std::unique_ptr<BagSource> source, std::string topic, std::vector<size_t> taken,
              std::vector<double> times, std::optional<DepthTopic> depth)
      : source_(std::move(source)),
        topic_(std::move(topic)),
        taken_(std::move(taken)),
        times_(std::move(times)),
        depth_(std::move(depth)) {}

  bool Next(Frame* frame) override {
    if (next_ >= taken_.size()) return false;
    frame->index = static_cast<ImageIndex>(next_);
    frame->name = NameOf(frame->index);
    frame->error.clear();
    frame->image = cv::Mat();
    frame->dropped = 0;
    frame->depth.release();
    const size_t message = taken_[next_++];
    source_->Decode(message, frame);
    if (depth_ && frame->error.empty()) {
      // The depth map recorded nearest, within 20 ms (a 30 Hz camera's two streams are at most
      // 17 ms apart); an image without one is processed without (its poses up to scale).
      const int nearest = NearestTime(depth_->times, times_[message], 0.02);
      if (nearest >= 0) {
        frame->depth = depth_->source->DecodeDepth(nearest, depth_->units_per_metre, &frame->error);
        if (!frame->error.empty()) frame->image.release();
        CheckDepthMatchesImage(depth_->name + " " + std::to_string(depth_->times[nearest]), frame);
      }
    }
    return true;
  }
  void SkipTo(ImageIndex first) override {
    next_ = std::max(next_, std::min(taken_.size(), static_cast<size_t>(std::max(first, 0))));
  }
  int size() const override { return static_cast<int>(taken_.size()); }
  // The topic and the recording time: known without decoding the message.
  std::string NameOf(ImageIndex index) const override {
    if (index < 0 || static_cast<size_t>(index) >= taken_.size()) return "";
    char time[64];
    std::snprintf(time, sizeof(time), "%.6f", times_[taken_[index]]);
    return topic_ + " " + time;
  }

 private:
  std::unique_ptr<BagSource> source_;
  std::string topic_;
  std::vector<size_t> taken_;  // of the topic's messages, those the rate takes
  std::vector<double> times_;  // every message's recording time
  std::optional<DepthTopic> depth_;
  size_t next_ = 0;
};

}  // namespace

bool IsBag(const std::string& path) {
  std::error_code error;
  if (fs::is_directory(path, error))
    return fs::is_regular_file(fs::path(path) / "metadata.yaml", error);
  const std::string extension = fs::path(path).extension().string();
  return extension == ".bag" || extension == ".db3";
}

std::unique_ptr<ImageSequence> OpenBag(const std::string& path, const SequenceOptions& options) {
  const bool ros1 = fs::path(path).extension() == ".bag";
  std::unique_ptr<BagSource> source = ros1 ? OpenRos1Bag(path) : OpenRos2Bag(path);
  const BagTopic topic = ChooseTopic(path, source->Topics(), options.topic);
  const std::vector<double> times = source->Select(topic);
  std::vector<ListedImage> listed;
  for (double time : times) listed.push_back({"", "", time});
  // The rate samples by recording time, as a video by its frames' times.
  std::vector<size_t> taken;
  size_t at = 0;
  for (const ListedImage& image : SampleAtRate(listed, options.rate_hz)) {
    while (times[at] != image.timestamp) ++at;
    taken.push_back(at++);
  }
  if (taken.empty()) throw InputError(path, "topic " + topic.name + " holds no message");
  std::optional<DepthTopic> depth;
  if (!options.depth_topic.empty()) {
    depth.emplace();
    depth->name = options.depth_topic;
    depth->source = ros1 ? OpenRos1Bag(path) : OpenRos2Bag(path);
    depth->times =
        depth->source->Select(ChooseDepthTopic(path, depth->source->Topics(), options.depth_topic));
    if (depth->times.empty()) {
      throw InputError(path, "depth topic " + options.depth_topic + " holds no message");
    }
    if (options.depth_units_per_metre > 0) depth->units_per_metre = options.depth_units_per_metre;
  }
  return std::make_unique<BagSequence>(std::move(source), topic.name, std::move(taken), times,
                                       std::move(depth));
}

}  // namespace memloop
