#include "synthetic/ros2_bag_writer.h"

#include <sqlite3.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "memloop/errors.h"

namespace memloop {
namespace {

namespace fs = std::filesystem;

// CDR, little endian: primitives aligned to their size from the end of the 4-byte header.
class CdrWriter {
 public:
  CdrWriter() : bytes_{0, 1, 0, 0} {}
  void U32(uint32_t value) {
    Align(4);
    const auto* raw = reinterpret_cast<const unsigned char*>(&value);
    bytes_.insert(bytes_.end(), raw, raw + 4);
  }
  void U8(uint8_t value) { bytes_.push_back(value); }
  void String(const std::string& text) {
    U32(static_cast<uint32_t>(text.size() + 1));
    bytes_.insert(bytes_.end(), text.begin(), text.end());
    bytes_.push_back(0);
  }
  void Bytes(const unsigned char* data, size_t size) {
    U32(static_cast<uint32_t>(size));
    bytes_.insert(bytes_.end(), data, data + size);
  }
  const std::vector<unsigned char>& bytes() const { return bytes_; }

 private:
  void Align(size_t n) {
    while ((bytes_.size() - 4) % n != 0) bytes_.push_back(0);
  }
  std::vector<unsigned char> bytes_;
};

std::vector<unsigned char> ImageMessage(const BagImage& image, BagEncoding encoding) {
  CdrWriter cdr;
  const long long nanoseconds = static_cast<long long>(std::llround(image.stamp * 1e9));
  cdr.U32(static_cast<uint32_t>(nanoseconds / 1000000000));
  cdr.U32(static_cast<uint32_t>(nanoseconds % 1000000000));
  cdr.String("camera");
  if (encoding == BagEncoding::kPng) {
    std::vector<unsigned char> png;
    cv::imencode(".png", image.pixels, png);
    cdr.String("png");
    cdr.Bytes(png.data(), png.size());
    return cdr.bytes();
  }
  cv::Mat pixels;
  std::string name = "bgr8";
  if (encoding == BagEncoding::kBgr8) pixels = image.pixels;
  if (encoding == BagEncoding::kRgb8)
    cv::cvtColor(image.pixels, pixels, cv::COLOR_BGR2RGB), name = "rgb8";
  if (encoding == BagEncoding::kMono8)
    cv::cvtColor(image.pixels, pixels, cv::COLOR_BGR2GRAY), name = "mono8";
  if (encoding == BagEncoding::kDepth16) pixels = image.pixels, name = "16UC1";
  pixels = pixels.clone();  // continuous
  cdr.U32(pixels.rows);
  cdr.U32(pixels.cols);
  cdr.String(name);
  cdr.U8(0);
  cdr.U32(static_cast<uint32_t>(pixels.step[0]));
  cdr.Bytes(pixels.data, pixels.total() * pixels.elemSize());
  return cdr.bytes();
}

void Run(sqlite3* db, const std::string& sql) {
  char* error = nullptr;
  if (sqlite3_exec(db, sql.c_str(), nullptr, nullptr, &error) != SQLITE_OK) {
    const std::string message = error ? error : "?";
    sqlite3_free(error);
    throw InputError(sqlite3_db_filename(db, "main"), "cannot write the bag (" + message + ")");
  }
}

std::string DbPath(const std::string& folder) {
  return (fs::path(folder) / (fs::path(folder).filename().string() + "_0.db3")).string();
}

void InsertTopic(sqlite3* db, const std::string& topic, const std::vector<BagImage>& images,
                 BagEncoding encoding) {
  const std::string type =
      encoding == BagEncoding::kPng ? "sensor_msgs/msg/CompressedImage" : "sensor_msgs/msg/Image";
  Run(db, "INSERT INTO topics(name, type, serialization_format, offered_qos_profiles) VALUES('" +
              topic + "', '" + type + "', 'cdr', '')");
  const long long topic_id = sqlite3_last_insert_rowid(db);
  sqlite3_stmt* insert = nullptr;
  sqlite3_prepare_v2(db, "INSERT INTO messages(topic_id, timestamp, data) VALUES(?,?,?)", -1,
                     &insert, nullptr);
  for (const BagImage& image : images) {
    const std::vector<unsigned char> data = ImageMessage(image, encoding);
    sqlite3_bind_int64(insert, 1, topic_id);
    sqlite3_bind_int64(insert, 2, std::llround(image.recorded * 1e9));
    sqlite3_bind_blob(insert, 3, data.data(), static_cast<int>(data.size()), SQLITE_TRANSIENT);
    sqlite3_step(insert);
    sqlite3_reset(insert);
  }
  sqlite3_finalize(insert);
}

}  // namespace

void WriteRos2Bag(const std::string& folder, const std::string& topic,
                  const std::vector<BagImage>& images, BagEncoding encoding) {
  fs::create_directories(folder);
  std::ofstream(fs::path(folder) / "metadata.yaml")
      << "rosbag2_bagfile_information:\n  version: 5\n  storage_identifier: sqlite3\n"
         "  relative_file_paths:\n    - "
      << fs::path(DbPath(folder)).filename().string() << "\n";
  std::error_code ignored;
  fs::remove(DbPath(folder), ignored);  // a new bag
  sqlite3* db = nullptr;
  if (sqlite3_open(DbPath(folder).c_str(), &db) != SQLITE_OK) {
    sqlite3_close(db);
    throw InputError(DbPath(folder), "cannot write the bag");
  }
  Run(db,
      "CREATE TABLE schema(schema_version INTEGER PRIMARY KEY, ros_distro TEXT NOT NULL);"
      "CREATE TABLE topics(id INTEGER PRIMARY KEY, name TEXT NOT NULL, type TEXT NOT NULL,"
      " serialization_format TEXT NOT NULL, offered_qos_profiles TEXT NOT NULL);"
      "CREATE TABLE messages(id INTEGER PRIMARY KEY, topic_id INTEGER NOT NULL,"
      " timestamp INTEGER NOT NULL, data BLOB NOT NULL);"
      "CREATE INDEX timestamp_idx ON messages (timestamp ASC);"
      "INSERT INTO schema VALUES(3, 'humble');"
      "INSERT INTO topics(name, type, serialization_format, offered_qos_profiles)"
      " VALUES('/chatter', 'std_msgs/msg/String', 'cdr', '');"
      "INSERT INTO messages(topic_id, timestamp, data) VALUES(1, 1, "
      "x'000100000600000068656c6c6f00');");
  Run(db, "BEGIN");
  InsertTopic(db, topic, images, encoding);
  Run(db, "COMMIT");
  sqlite3_close(db);
}

void AddRos2Topic(const std::string& folder, const std::string& topic,
                  const std::vector<BagImage>& images, BagEncoding encoding) {
  sqlite3* db = nullptr;
  sqlite3_open(DbPath(folder).c_str(), &db);
  InsertTopic(db, topic, images, encoding);
  sqlite3_close(db);
}

}  // namespace memloop
