#include "storage/fleet_follower.h"

#include <algorithm>
#include <chrono>
#include <cstring>
#include <memory>
#include <sstream>
#include <utility>

#include "memloop/errors.h"
#include "storage/fleet_schema.h"
#include "storage/postgres_connection.h"
#include "util/thread_name.h"
#include "util/thread_priority.h"

namespace memloop {
namespace {

std::vector<long long> SplitNumbers(const std::string& text) {
  std::vector<long long> numbers;
  std::istringstream stream(text);
  std::string item;
  while (std::getline(stream, item, ';')) {
    if (!item.empty()) numbers.push_back(std::stoll(item));
  }
  return numbers;
}

// The statements of one connection, prepared once.
struct FleetQueries {
  explicit FleetQueries(PostgresConnection& connection) {
    const std::string fleet = kFleetSchema;
    // Places of other robots, not themselves imported from another (their origin is read).
    unseen = connection.Prepare(
        "SELECT l.robot, l.id FROM " + fleet + ".locations l WHERE l.robot <> current_user" +
        " AND NOT EXISTS (SELECT 1 FROM " + fleet + ".foreign_places f" +
        " WHERE f.robot = l.robot AND f.location_id = l.id) ORDER BY l.robot, l.id");
    location = connection.Prepare(
        "SELECT l.weight, (SELECT string_agg(i.image::text, ';' ORDER BY i.rank) FROM " + fleet +
        ".location_images i WHERE i.robot = l.robot AND i.location_id = l.id), (SELECT" +
        " string_agg(k.to_id::text, ';' ORDER BY k.to_id) FROM " + fleet + ".links k" +
        " WHERE k.robot = l.robot AND k.from_id = l.id AND k.type = 0), (SELECT v.image FROM " +
        fleet + ".location_views v WHERE v.robot = l.robot AND v.location_id = l.id) FROM " +
        fleet + ".locations l WHERE l.robot = ? AND l.id = ?");
    // A word's descriptor: in `words` once it left its robot's dictionary, in the checkpoint's
    // `index_descriptors` while it is in it.
    signature = connection.Prepare(
        "SELECT s.word_id, s.x, s.y, s.size, s.angle, s.response, s.octave,"
        " COALESCE(w.descriptor, d.descriptor) FROM " +
        fleet + ".signature_words s LEFT JOIN " + fleet +
        ".words w ON w.robot = s.robot AND w.id = s.word_id LEFT JOIN " + fleet +
        ".index_descriptors d ON d.robot = s.robot AND d.word_id = s.word_id"
        " WHERE s.robot = ? AND s.location_id = ? ORDER BY s.rank");
  }
  std::unique_ptr<SqlStatement> unseen, location, signature;
};

}  // namespace

FleetFollower::FleetFollower(const std::string& uri, int descriptor_cv_type, int descriptor_dim,
                             std::set<std::pair<std::string, LocationId>> imported,
                             FleetFollowerOptions options)
    : uri_(uri),
      cv_type_(descriptor_cv_type),
      dim_(descriptor_dim),
      options_(options),
      seen_(std::move(imported)) {
  thread_ = std::thread([this] { Run(); });
}

FleetFollower::~FleetFollower() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stopping_ = true;
  }
  wake_.notify_all();
  thread_.join();
}

std::vector<FleetLocation> FleetFollower::Take(size_t count) {
  std::vector<FleetLocation> places;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    while (places.size() < count && !waiting_.empty()) {
      places.push_back(std::move(waiting_.front()));
      waiting_.pop_front();
    }
  }
  if (!places.empty()) wake_.notify_all();  // room to read more
  return places;
}

bool FleetFollower::WaitForFreshPoll(double seconds, bool* complete) {
  std::unique_lock<std::mutex> lock(mutex_);
  const long long target = polls_started_ + 1;
  poll_now_ = true;
  wake_.notify_all();
  const bool ended = polled_.wait_for(lock, std::chrono::duration<double>(seconds),
                                      [&] { return polls_ended_ >= target; });
  if (complete != nullptr) *complete = ended && last_poll_complete_;
  return ended;
}

std::vector<std::string> FleetFollower::TakeNotices() {
  std::lock_guard<std::mutex> lock(mutex_);
  return std::exchange(notices_, {});
}

void FleetFollower::Run() {
  StepBelowRealTimePriority();  // behind the per-image threads (thread_priority.h)
  NameThisThread("fleet");
  std::unique_ptr<PostgresConnection> connection;
  std::unique_ptr<FleetQueries> queries;
  for (;;) {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      ++polls_started_;
      poll_now_ = false;
    }
    bool polled = false;
    try {
      if (!connection) {
        connection = std::make_unique<PostgresConnection>(uri_);
        queries = std::make_unique<FleetQueries>(*connection);
      }
      Poll(*connection, *queries->unseen, *queries->location, *queries->signature);
      polled = true;
    } catch (const std::exception&) {
      // The server is away (the LTM's writer says so and waits for it): asked again next time,
      // on a new connection.
      queries.reset();
      connection.reset();
    }
    std::unique_lock<std::mutex> lock(mutex_);
    polls_ended_ += polled;
    polled_.notify_all();
    wake_.wait_for(lock, std::chrono::duration<double>(options_.poll_seconds),
                   [this] { return stopping_ || poll_now_; });
    if (stopping_) return;
  }
}

void FleetFollower::Poll(PostgresConnection& connection, SqlStatement& list, SqlStatement& location,
                         SqlStatement& signature) {
  // One snapshot: a place and its words as one committed checkpoint of its robot left them.
  connection.Execute("BEGIN ISOLATION LEVEL REPEATABLE READ READ ONLY");
  // A lost connection throws at once (no waiting for the server here: the next poll connects
  // again), so that the thread stops promptly whatever the server's state.
  connection.SetInTransaction(true);
  std::vector<std::pair<std::string, LocationId>> unseen;
  while (list.Step()) {
    std::pair<std::string, LocationId> key(list.Text(0), static_cast<LocationId>(list.Int(1)));
    if (seen_.count(key) == 0) unseen.push_back(std::move(key));
  }
  list.Reset();
  bool complete = true;
  for (const auto& [robot, id] : unseen) {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (stopping_ || waiting_.size() >= options_.max_waiting) {
        complete = false;
        break;
      }
    }
    FleetLocation place;
    const bool usable = ReadPlace(location, signature, robot, id, place);
    seen_.insert({robot, id});
    if (!usable) continue;
    std::lock_guard<std::mutex> lock(mutex_);
    waiting_.push_back(std::move(place));
  }
  connection.Execute("COMMIT");
  connection.SetInTransaction(false);
  std::lock_guard<std::mutex> lock(mutex_);
  last_poll_complete_ = complete;
}

bool FleetFollower::ReadPlace(SqlStatement& location, SqlStatement& signature,
                              const std::string& robot, LocationId id, FleetLocation& place) {
  place.robot = robot;
  place.id = id;
  SqlStatement& row = location;
  row.Bind(1, robot).Bind(2, static_cast<long long>(id));
  if (!row.Step()) {
    row.Reset();
    return false;  // gone since the list (merged into another place)
  }
  place.weight = static_cast<int>(row.Int(0));
  for (long long image : SplitNumbers(row.IsNull(1) ? "" : row.Text(1))) {
    place.images.push_back(static_cast<ImageIndex>(image));
  }
  for (long long to : SplitNumbers(row.IsNull(2) ? "" : row.Text(2))) {
    place.neighbours.push_back(static_cast<LocationId>(to));
  }
  // The image whose keypoints it holds first (Result::loop_closure_images' order).
  const auto view = row.IsNull(3) ? place.images.end()
                                  : std::find(place.images.begin(), place.images.end(),
                                              static_cast<ImageIndex>(row.Int(3)));
  if (view != place.images.end()) std::rotate(place.images.begin(), view, view + 1);
  row.Reset();

  const size_t row_bytes = static_cast<size_t>(dim_) * CV_ELEM_SIZE(cv_type_);
  std::vector<std::vector<unsigned char>> rows;
  bool foreign_kind = false;
  SqlStatement& words = signature;
  words.Bind(1, robot).Bind(2, static_cast<long long>(id));
  while (words.Step()) {
    if (words.IsNull(7)) continue;  // its descriptor is not on the server (yet)
    std::vector<unsigned char> descriptor = words.Blob(7);
    if (descriptor.size() != row_bytes) {
      foreign_kind = true;
      continue;
    }
    place.words.push_back(static_cast<WordId>(words.Int(0)));
    place.keypoints.emplace_back(
        cv::Point2f(static_cast<float>(words.Double(1)), static_cast<float>(words.Double(2))),
        static_cast<float>(words.Double(3)), static_cast<float>(words.Double(4)),
        static_cast<float>(words.Double(5)), static_cast<int>(words.Int(6)));
    rows.push_back(std::move(descriptor));
  }
  words.Reset();
  if (foreign_kind && told_.insert(robot).second) {
    std::lock_guard<std::mutex> lock(mutex_);
    notices_.push_back("robot " + robot +
                       "'s places are described by other features than this robot's: skipped");
  }
  if (rows.empty()) return false;
  place.descriptors.create(static_cast<int>(rows.size()), dim_, cv_type_);
  for (size_t i = 0; i < rows.size(); ++i) {
    std::memcpy(place.descriptors.ptr(static_cast<int>(i)), rows[i].data(), row_bytes);
  }
  return true;
}

}  // namespace memloop
