#include "memloop/map_export.h"

#include <map>

#include "detector/loop_geometry.h"
#include "memloop/detector.h"
#include "memloop/errors.h"
#include "memloop/loop_closure_edits.h"
#include "storage/ltm_database.h"

namespace memloop {

namespace {

void UseKeptPose(const LoopClosurePose& pose, LoopGeometry& geometry) {
  geometry.pose_from_detection = true;
  geometry.has_pose = pose.has_pose;
  geometry.pose_problem = pose.reason;
  if (!pose.has_pose) return;
  geometry.quaternion = pose.quaternion;
  geometry.translation = pose.translation;
  geometry.translation_known = pose.translation != std::array<double, 3>{};
  geometry.translation_metric = pose.metric;
  geometry.pose_inliers = pose.inliers;
  const cv::Matx33d rotation = RotationOf(pose.quaternion);
  for (int i = 0; i < 9; ++i) geometry.rotation[i] = rotation(i / 3, i % 3);
}

}  // namespace

std::vector<ExportedLoopClosure> ExportLoopClosures(const std::string& map_path,
                                                    const CameraIntrinsics& intrinsics) {
  const Options options = ReadMapOptions(map_path);
  LtmDatabase database(map_path, LtmDatabase::Mode::kRead);
  database.Begin();  // one snapshot of a map another process may be writing
  std::map<ImageIndex, MapImage> images;
  for (MapImage& image : database.ReadImages()) images[image.index] = std::move(image);
  // The location that holds each image now (a location absorbs others: rehearsal, past matches).
  std::map<ImageIndex, LocationId> holder;
  for (LocationId id : database.ReadLocationIds()) {
    if (const std::optional<Location> location = database.ReadLocation(id)) {
      for (ImageIndex image : location->images) holder[image] = id;
    }
  }
  const auto image_of = [&](ImageIndex index) {
    const auto found = images.find(index);
    if (found != images.end()) return found->second;
    MapImage unknown;
    unknown.index = index;
    return unknown;
  };
  // A fleet's map: the images of other robots whose places loop closures name.
  std::map<std::string, std::map<ImageIndex, MapImage>> others;
  const auto other_image = [&](const std::string& robot, ImageIndex index) {
    if (!others.count(robot)) {
      for (MapImage& image : database.ReadImagesOf(robot)) others[robot][image.index] = image;
    }
    const auto found = others[robot].find(index);
    if (found != others[robot].end()) return found->second;
    MapImage unknown;
    unknown.index = index;
    return unknown;
  };
  std::vector<ExportedLoopClosure> loops;
  // As edited: the rejected ones left out, those added by hand in (their pose estimated below).
  for (const MapLoopClosure& loop :
       EditedLoopClosures(database.ReadLoopClosures(), database.ReadEdits())) {
    const bool foreign = !loop.match_robot.empty();
    ExportedLoopClosure exported{
        loop,
        image_of(loop.query_image),
        foreign ? other_image(loop.match_robot, loop.match_image) : image_of(loop.match_image),
        {}};
    const auto query = holder.find(loop.query_image);
    // Another robot's place is its own location (never merged), its images the other robot's.
    const auto match = foreign ? holder.end() : holder.find(loop.match_image);
    const LocationId match_id =
        foreign ? loop.match_location : (match == holder.end() ? kNoLocation : match->second);
    const std::optional<Location> foreign_location =
        foreign ? database.ReadLocation(match_id) : std::nullopt;
    if (query != holder.end() && (match != holder.end() || foreign_location) &&
        query->second != match_id) {
      const Location query_location = *database.ReadLocation(query->second);
      const Location match_location =
          foreign ? *foreign_location : *database.ReadLocation(match_id);
      exported.geometry = EstimateLoopGeometry(query_location.signature, match_location.signature,
                                               intrinsics, options.verification);
      exported.geometry.query_view = ViewOf(query_location);
      exported.geometry.match_view = ViewOf(match_location);
      if (!loop.pose.estimated) {  // the pose joins the views (their keypoints' images)
        exported.query = image_of(exported.geometry.query_view);
        if (!foreign) exported.match = image_of(exported.geometry.match_view);
      }
    } else {
      exported.geometry.pose_problem = "a view is not in the map's LTM (the map is not closed)";
    }
    // The pose found when the loop closure was accepted compares the two images themselves;
    // Rehearsal may have merged either into another location since (fewer correspondences).
    const CameraIntrinsics kept_camera{options.camera.fx, options.camera.fy, options.camera.cx,
                                       options.camera.cy};
    if (loop.pose.estimated && (!intrinsics.known() || intrinsics == kept_camera)) {
      UseKeptPose(loop.pose, exported.geometry);
    }
    loops.push_back(std::move(exported));
  }
  return loops;
}

ExportFormat ParseExportFormat(const std::string& name) {
  if (name == "json") return ExportFormat::kJson;
  if (name == "g2o") return ExportFormat::kG2o;
  if (name == "pairs") return ExportFormat::kPairs;
  if (name == "tum") {
    throw ParameterError("--format",
                         "--format tum: a TUM trajectory has 8 columns (time and pose) and a "
                         "loop closure is a pair of images: --format pairs writes them (both "
                         "time stamps, then the relative pose)");
  }
  throw ParameterError("--format", "--format: '" + name + "' is not one of json, g2o, pairs");
}

}  // namespace memloop
