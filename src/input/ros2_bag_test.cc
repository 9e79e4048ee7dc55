#include <gtest/gtest.h>
#include <sqlite3.h>

#include "input/bag_sequence.h"
#include "memloop/errors.h"
#include "temp_dir.h"

namespace memloop {
namespace {

// A one-message ROS 2 bag whose CDR bytes are written out by hand, so that the reader is checked
// against the format, not against memloop's own writer.
TEST(Ros2BagTest, HandWrittenCdrImageDecodes) {
  testing::TempDir dir;
  const std::string path = dir.File("hand.db3");
  sqlite3* db = nullptr;
  ASSERT_EQ(sqlite3_open(path.c_str(), &db), SQLITE_OK);
  // sensor_msgs/msg/Image, little-endian CDR: header (stamp 100 s + 500,000,000 ns, frame_id
  // ""), height 1, width 2 (after 3 bytes of padding to 4), encoding "mono8", is_bigendian 0,
  // step 2 (after 1 byte of padding), data [127, 128].
  const char* sql =
      "CREATE TABLE topics(id INTEGER PRIMARY KEY, name TEXT, type TEXT,"
      " serialization_format TEXT, offered_qos_profiles TEXT);"
      "CREATE TABLE messages(id INTEGER PRIMARY KEY, topic_id INTEGER, timestamp INTEGER,"
      " data BLOB);"
      "INSERT INTO topics VALUES(1, '/cam', 'sensor_msgs/msg/Image', 'cdr', '');"
      "INSERT INTO messages VALUES(1, 1, 100600000000, x'00010000'"
      " || x'64000000' || x'0065cd1d' || x'0100000000' || x'000000'"
      " || x'01000000' || x'02000000' || x'060000006d6f6e6f3800' || x'00' || x'00'"
      " || x'02000000' || x'02000000' || x'7f80');";
  ASSERT_EQ(sqlite3_exec(db, sql, nullptr, nullptr, nullptr), SQLITE_OK) << sqlite3_errmsg(db);
  sqlite3_close(db);

  auto sequence = OpenBag(path, SequenceOptions());
  ASSERT_EQ(sequence->size(), 1);
  EXPECT_EQ(sequence->NameOf(0), "/cam 100.600000");  // the recording time
  Frame frame;
  ASSERT_TRUE(sequence->Next(&frame));
  ASSERT_TRUE(frame.error.empty()) << frame.error;
  EXPECT_DOUBLE_EQ(frame.timestamp, 100.5);  // the header's stamp
  ASSERT_EQ(frame.image.type(), CV_8UC1);
  ASSERT_EQ(frame.image.size(), cv::Size(2, 1));
  EXPECT_EQ(frame.image.at<uint8_t>(0, 0), 127);
  EXPECT_EQ(frame.image.at<uint8_t>(0, 1), 128);

  // The same message cut short: a frame with an error, not a crash.
  ASSERT_EQ(sqlite3_open(path.c_str(), &db), SQLITE_OK);
  sqlite3_exec(db, "UPDATE messages SET data = substr(data, 1, 30)", nullptr, nullptr, nullptr);
  sqlite3_close(db);
  auto cut = OpenBag(path, SequenceOptions());
  ASSERT_TRUE(cut->Next(&frame));
  EXPECT_TRUE(frame.image.empty());
  EXPECT_NE(frame.error.find("not a CDR message"), std::string::npos) << frame.error;
}

}  // namespace
}  // namespace memloop
