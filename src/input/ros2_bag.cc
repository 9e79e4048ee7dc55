// ROS 2 bags in their SQLite storage (rosbag2_storage_default_plugins' sqlite3): a folder with
// metadata.yaml and one or more *.db3 files, each with tables topics(id, name, type,
// serialization_format, ...) and messages(id, topic_id, timestamp [ns], data). Messages are CDR
// (OMG DDS-XTypes), decoded here for the two image types.
#include <algorithm>
#include <cstring>
#include <filesystem>

#include "input/bag_sequence.h"
#include "input/ros_image.h"
#include "memloop/errors.h"
#include "storage/sqlite_statement.h"

namespace memloop {
namespace {

namespace fs = std::filesystem;

// Plain CDR, little endian (the encapsulation ROS 2 writes on x86 and ARM): each primitive is
// aligned to its size from the end of the 4-byte encapsulation header.
class CdrReader {
 public:
  CdrReader(const std::vector<unsigned char>& bytes) : bytes_(bytes) {
    ok_ = bytes.size() >= 4 && bytes[0] == 0 && bytes[1] == 1;  // CDR_LE
  }
  bool ok() const { return ok_; }
  uint32_t U32() {
    Align(4);
    uint32_t value = 0;
    if (Take(4)) std::memcpy(&value, &bytes_[position_ - 4], 4);
    return value;
  }
  uint8_t U8() { return Take(1) ? bytes_[position_ - 1] : 0; }
  std::string String() {
    const uint32_t length = U32();  // with its terminating NUL
    if (!Take(length)) return "";
    return std::string(reinterpret_cast<const char*>(&bytes_[position_ - length]),
                       length > 0 ? length - 1 : 0);
  }
  // A sequence<uint8>: its bytes stay in the message.
  std::pair<const uint8_t*, size_t> Bytes() {
    const uint32_t length = U32();
    if (!Take(length)) return {nullptr, 0};
    return {&bytes_[position_ - length], length};
  }

 private:
  void Align(size_t n) {
    const size_t offset = position_ - 4;
    position_ = 4 + (offset + n - 1) / n * n;
  }
  bool Take(size_t n) {
    if (!ok_ || position_ + n > bytes_.size()) return ok_ = false;
    position_ += n;
    return true;
  }
  const std::vector<unsigned char>& bytes_;
  size_t position_ = 4;
  bool ok_;
};

double HeaderStamp(CdrReader& cdr) {
  const int32_t seconds = static_cast<int32_t>(cdr.U32());
  const uint32_t nanoseconds = cdr.U32();
  cdr.String();  // frame_id
  return seconds + nanoseconds * 1e-9;
}

class Ros2Bag : public BagSource {
 public:
  explicit Ros2Bag(const std::string& path) : path_(path) {
    std::vector<std::string> files;
    std::error_code error;
    if (fs::is_directory(path, error)) {
      for (const auto& entry : fs::directory_iterator(path, error)) {
        if (entry.path().extension() == ".db3") files.push_back(entry.path().string());
      }
      std::sort(files.begin(), files.end(), NaturalLess);
      if (files.empty()) {
        const bool mcap = std::any_of(
            fs::directory_iterator(path, error), fs::directory_iterator(),
            [](const fs::directory_entry& entry) { return entry.path().extension() == ".mcap"; });
        throw InputError(path, mcap ? "a ROS 2 bag in MCAP storage: memloop reads the sqlite3 "
                                      "storage (ros2 bag convert can write it)"
                                    : "a ROS 2 bag folder without a .db3 file");
      }
    } else {
      files.push_back(path);
    }
    for (const std::string& file : files) {
      try {
        files_.push_back(std::make_unique<SqliteConnection>(file, SQLITE_OPEN_READONLY));
        SqliteStatement topics(*files_.back(),
                               "SELECT t.name, t.type, t.serialization_format, count(m.id) FROM "
                               "topics t LEFT JOIN messages m ON m.topic_id = t.id GROUP BY t.id");
        while (topics.Step()) {
          const std::string name = topics.Text(0);
          auto found = std::find_if(topics_.begin(), topics_.end(),
                                    [&](const BagTopic& topic) { return topic.name == name; });
          if (found == topics_.end()) {
            topics_.push_back({name, topics.Text(1), 0});
            formats_.push_back(topics.Text(2));
            found = topics_.end() - 1;
          }
          found->messages += topics.Int(3);
        }
      } catch (const DatabaseError&) {
        const bool opened = !files_.empty() && files_.back()->path() == file;
        throw InputError(
            file, std::string("not a readable ROS 2 bag (sqlite3 storage; SQLite: ") +
                      (opened ? sqlite3_errmsg(files_.back()->handle()) : "cannot be opened") +
                      ")");
      }
    }
  }

  std::vector<BagTopic> Topics() const override { return topics_; }

  std::vector<double> Select(const BagTopic& topic) override {
    compressed_ = topic.type.find("CompressedImage") != std::string::npos;
    const size_t index = std::find_if(topics_.begin(), topics_.end(),
                                      [&](const BagTopic& t) { return t.name == topic.name; }) -
                         topics_.begin();
    if (formats_[index] != "cdr") {
      throw InputError(
          path_, "topic " + topic.name + " is serialized as '" + formats_[index] + "', not CDR");
    }
    struct Row {
      long long time;
      size_t file;
      long long id;
    };
    std::vector<Row> rows;
    for (size_t file = 0; file < files_.size(); ++file) {
      SqliteStatement query(*files_[file],
                            "SELECT m.timestamp, m.id FROM messages m JOIN topics t ON "
                            "m.topic_id = t.id WHERE t.name = ? ORDER BY m.timestamp, m.id");
      query.Bind(1, topic.name);
      while (query.Step()) rows.push_back({query.Int(0), file, query.Int(1)});
    }
    std::stable_sort(rows.begin(), rows.end(),
                     [](const Row& a, const Row& b) { return a.time < b.time; });
    std::vector<double> times;
    for (const Row& row : rows) {
      times.push_back(row.time * 1e-9);
      messages_.emplace_back(row.file, row.id);
    }
    return times;
  }

  void Decode(size_t i, Frame* frame) override {
    double recorded = 0;
    const std::vector<unsigned char> bytes = Message(i, &recorded, &frame->error);
    if (bytes.empty()) {
      if (frame->error.empty()) frame->error = kNotCdr;
      return;
    }
    CdrReader cdr(bytes);
    const double stamp = HeaderStamp(cdr);
    frame->timestamp = stamp > 0 ? stamp : recorded;
    if (compressed_) {
      cdr.String();  // format: the codec says it
      const auto [data, size] = cdr.Bytes();
      if (cdr.ok()) frame->image = DecodeCompressedImage(data, size, &frame->error);
    } else {
      const RawImage raw = ReadRawImage(cdr);
      if (cdr.ok()) frame->image = DecodeRawImage(raw, &frame->error);
    }
    if (!cdr.ok()) frame->error = kNotCdr;
  }

  cv::Mat DecodeDepth(size_t i, double units_per_metre, std::string* error) override {
    double recorded = 0;
    const std::vector<unsigned char> bytes = Message(i, &recorded, error);
    if (bytes.empty()) {
      if (error->empty()) *error = std::string("depth: ") + kNotCdr;
      return cv::Mat();
    }
    CdrReader cdr(bytes);
    HeaderStamp(cdr);
    const RawImage raw = ReadRawImage(cdr);
    if (!cdr.ok()) {
      *error = std::string("depth: ") + kNotCdr;
      return cv::Mat();
    }
    return DecodeRawDepth(raw, units_per_metre, error);
  }

 private:
  static constexpr const char* kNotCdr =
      "not a CDR message of its type (truncated or of another encoding)";

  // Message `i` of the selection's bytes and recording time; empty with `error` when missing.
  std::vector<unsigned char> Message(size_t i, double* recorded, std::string* error) {
    const auto [file, id] = messages_[i];
    SqliteStatement query(*files_[file], "SELECT timestamp, data FROM messages WHERE id = ?");
    query.Bind(1, id);
    if (!query.Step()) {
      *error = "message missing from the bag";
      return {};
    }
    *recorded = query.Int(0) * 1e-9;
    return query.Blob(1);
  }
  // A sensor_msgs/msg/Image's fields after its header; its data stays in the message.
  static RawImage ReadRawImage(CdrReader& cdr) {
    RawImage raw;
    raw.height = cdr.U32();
    raw.width = cdr.U32();
    raw.encoding = cdr.String();
    raw.big_endian = cdr.U8() != 0;
    raw.step = cdr.U32();
    std::tie(raw.data, raw.size) = cdr.Bytes();
    return raw;
  }

  std::string path_;
  std::vector<std::unique_ptr<SqliteConnection>> files_;
  std::vector<BagTopic> topics_;
  std::vector<std::string> formats_;  // of each topic
  bool compressed_ = false;
  std::vector<std::pair<size_t, long long>> messages_;  // file, message id
};

}  // namespace

std::unique_ptr<BagSource> OpenRos2Bag(const std::string& path) {
  return std::make_unique<Ros2Bag>(path);
}

}  // namespace memloop
