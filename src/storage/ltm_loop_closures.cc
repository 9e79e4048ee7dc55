// The map's accepted loop closures and the geometry found when each was accepted.
#include "storage/ltm_database.h"

namespace memloop {

void LtmDatabase::CreateLoopClosurePoseTable() {
  // `loop` is the loop closure's rowid; the translation and rotation are NULL without a pose.
  connection_->Execute(
      "CREATE TABLE IF NOT EXISTS loop_closure_poses(loop INTEGER PRIMARY KEY,"
      " inliers INTEGER NOT NULL, has_pose INTEGER NOT NULL, metric INTEGER NOT NULL,"
      " tx REAL, ty REAL, tz REAL, qx REAL, qy REAL, qz REAL, qw REAL, reason TEXT NOT NULL)");
}

void LtmDatabase::WriteLoopClosure(const LoopClosureRecord& record) {
  Cached(
      "INSERT INTO loop_closures(query_image, match_image, query_location, match_location,"
      " probability) VALUES(?,?,?,?,?)")
      .Bind(1, static_cast<long long>(record.query_image))
      .Bind(2, static_cast<long long>(record.match_image))
      .Bind(3, static_cast<long long>(record.query_location))
      .Bind(4, static_cast<long long>(record.match_location))
      .Bind(5, record.probability)
      .Run();
  const LoopClosurePose& pose = record.pose;
  if (!pose.estimated) return;
  auto& insert = Cached(
      "INSERT INTO loop_closure_poses(loop, inliers, has_pose, metric, tx, ty, tz, qx, qy, qz,"
      " qw, reason) VALUES(last_insert_rowid(),?,?,?,?,?,?,?,?,?,?,?)");
  insert.Bind(1, static_cast<long long>(pose.inliers))
      .Bind(2, static_cast<long long>(pose.has_pose))
      .Bind(3, static_cast<long long>(pose.metric));
  for (int i = 0; i < 7; ++i) {
    if (pose.has_pose) {
      insert.Bind(4 + i, i < 3 ? pose.translation[i] : pose.quaternion[i - 3]);
    } else {
      insert.BindNull(4 + i);  // a cached statement keeps the last row's values
    }
  }
  insert.Bind(11, pose.reason).Run();
}

std::vector<LoopClosureRecord> LtmDatabase::ReadLoopClosures() {
  if (!has_poses_) has_poses_ = HasTable("loop_closure_poses");
  auto& query = Cached(
      *has_poses_ ? "SELECT l.query_image, l.match_image, l.query_location, l.match_location,"
                    " l.probability, p.inliers, p.has_pose, p.metric, p.tx, p.ty, p.tz, p.qx, p.qy,"
                    " p.qz, p.qw, p.reason FROM loop_closures l LEFT JOIN loop_closure_poses p"
                    " ON p.loop = l.rowid ORDER BY l.rowid"
                  : "SELECT query_image, match_image, query_location, match_location, probability"
                    " FROM loop_closures ORDER BY rowid");
  std::vector<LoopClosureRecord> records;
  while (query.Step()) {
    LoopClosureRecord record;
    record.query_image = static_cast<ImageIndex>(query.Int(0));
    record.match_image = static_cast<ImageIndex>(query.Int(1));
    record.query_location = static_cast<LocationId>(query.Int(2));
    record.match_location = static_cast<LocationId>(query.Int(3));
    record.probability = query.Double(4);
    if (*has_poses_ && !query.IsNull(5)) {
      LoopClosurePose& pose = record.pose;
      pose.estimated = true;
      pose.inliers = static_cast<int>(query.Int(5));
      pose.has_pose = query.Int(6) != 0;
      pose.metric = query.Int(7) != 0;
      for (int i = 0; i < 7 && pose.has_pose; ++i) {
        (i < 3 ? pose.translation[i] : pose.quaternion[i - 3]) = query.Double(8 + i);
      }
      pose.reason = query.Text(15);
    }
    records.push_back(std::move(record));
  }
  query.Reset();
  const std::vector<ForeignPlace> foreign = ReadForeignPlaces();
  if (foreign.empty()) return records;
  std::unordered_map<LocationId, const ForeignPlace*> by_location;
  for (const ForeignPlace& place : foreign) by_location[place.location] = &place;
  for (LoopClosureRecord& record : records) {
    const auto place = by_location.find(record.match_location);
    if (place != by_location.end()) record.match_robot = place->second->robot;
  }
  return records;
}

}  // namespace memloop
