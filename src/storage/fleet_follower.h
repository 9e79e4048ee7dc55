// A fleet's map (fleet_schema.h): the places other robots have put in their Long-Term Memory,
// read from the server by a background thread while they map them, so that a robot can search
// them (fleet_places.h). The detector's thread only takes what was read: the network stays off
// it, as the LTM's writes do.
#pragma once

#include <condition_variable>
#include <deque>
#include <mutex>
#include <opencv2/core.hpp>
#include <set>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "memloop/types.h"

namespace memloop {

class PostgresConnection;
class SqlStatement;

// A place as another robot's map holds it: its ids are that robot's.
struct FleetLocation {
  std::string robot;
  LocationId id = kNoLocation;
  int weight = 0;
  std::vector<ImageIndex> images;
  std::vector<LocationId> neighbours;  // its robot's locations linked to it as neighbours
  // One entry per feature whose word's descriptor the server holds, in the signature's order.
  std::vector<WordId> words;
  std::vector<cv::KeyPoint> keypoints;
  cv::Mat descriptors;  // one row per feature
};

struct FleetFollowerOptions {
  double poll_seconds = 0.5;  // how often the server is asked for new places
  size_t max_waiting = 512;   // places read and not yet taken; the rest waits on the server
};

class FleetFollower {
 public:
  // `uri`: the robot's own map (its role reads every robot's rows). `descriptor_cv_type` and
  // `descriptor_dim`: the robot's features; a place described otherwise is skipped. `imported`:
  // (robot, location) already imported, not read again.
  FleetFollower(const std::string& uri, int descriptor_cv_type, int descriptor_dim,
                std::set<std::pair<std::string, LocationId>> imported,
                FleetFollowerOptions options = {});
  ~FleetFollower();  // stops the thread
  FleetFollower(const FleetFollower&) = delete;
  FleetFollower& operator=(const FleetFollower&) = delete;

  // Up to `count` places read, in the order read (by robot, then location id).
  std::vector<FleetLocation> Take(size_t count);
  // Waits up to `seconds` for a poll of the server that starts after this call to end (at once
  // when there is no room to read). Returns false when none ended in time (the server is away);
  // `complete` receives whether that poll read every place it found (no room left: false).
  bool WaitForFreshPoll(double seconds, bool* complete = nullptr);
  // Places skipped because their features are not the robot's kind (robot names, once each).
  std::vector<std::string> TakeNotices();

 private:
  void Run();
  // One pass over the server: the places not seen yet, read while there is room.
  void Poll(PostgresConnection& connection, SqlStatement& list, SqlStatement& location,
            SqlStatement& signature);
  bool ReadPlace(SqlStatement& location, SqlStatement& signature, const std::string& robot,
                 LocationId id, FleetLocation& place);

  std::string uri_;
  int cv_type_;
  int dim_;
  FleetFollowerOptions options_;
  std::set<std::pair<std::string, LocationId>> seen_;  // the thread's only

  std::mutex mutex_;
  std::condition_variable wake_;
  std::condition_variable polled_;
  std::deque<FleetLocation> waiting_;
  std::vector<std::string> notices_;
  std::set<std::string> told_;  // robots a notice was given for (the thread's)
  long long polls_started_ = 0;
  long long polls_ended_ = 0;  // successfully
  bool last_poll_complete_ = true;
  bool stopping_ = false;
  bool poll_now_ = false;  // WaitForFreshPoll: no need to wait for the poll interval
  std::thread thread_;
};

}  // namespace memloop
