// What a map file holds, read without changing it (`memloop inspect`).
#pragma once

#include <array>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "memloop/types.h"

namespace memloop {

// An accepted loop closure's geometry as it was found (camera.fx..cy set then), kept with it:
// the two images' own keypoints, before Rehearsal merges either into another location.
struct LoopClosurePose {
  bool estimated = false;  // the intrinsics were known: inliers and a pose or a reason
  int inliers = -1;        // epipolar inliers of the two views (-1: not estimated)
  bool has_pose = false;
  bool metric = false;  // the translation is in metres; else a unit direction (0: unknown)
  std::array<double, 3> translation{};           // the query camera in the match camera's frame
  std::array<double, 4> quaternion{0, 0, 0, 1};  // x, y, z, w: x_match = R x_query + t
  std::string reason;                            // why there is no pose ("" with one)
};

struct MapLoopClosure {
  ImageIndex query_image = kNoImage;
  ImageIndex match_image = kNoImage;
  LocationId query_location = kNoLocation;
  LocationId match_location = kNoLocation;
  double probability = 0;       // the hypothesis value that accepted it (0 for one added by hand)
  LoopClosurePose pose;         // estimated = false in maps made before it was kept
  long long added_by_edit = 0;  // the edit that added it (loop_closure_edits.h), 0 when detected
  // A fleet's map: the robot that mapped the matched place when it is another robot's (then
  // match_image is that robot's image); empty for the map's own places.
  std::string match_robot;
};

// A fleet's map: a place another robot mapped, a copy of which joined this robot's map as
// location `location` (docs/fleet.md).
struct ForeignPlace {
  LocationId location = kNoLocation;
  std::string robot;
  LocationId origin_location = kNoLocation;  // the other robot's id of it
  std::vector<ImageIndex> images;            // the other robot's images of it
  ImageIndex imported_image = kNoImage;      // this map's image at whose iteration it joined
};

// An image of the map: what Detector::Process was told of it (ImageInfo).
struct MapImage {
  ImageIndex index = kNoImage;
  int session = 0;
  std::string name;                 // "" when the caller gave none
  double timestamp = kNoTimestamp;  // seconds
};

// A session: the images one run (or its resumed runs) added. A new session (MapMode::kNewSession)
// is linked to the earlier ones only by loop closures.
struct MapSession {
  int id = 0;  // 0 for the map's first session
  ImageIndex first_image = kNoImage;
  ImageIndex last_image = kNoImage;
  long long images = 0;
  std::string first_name, last_name;  // of its first and last images
  double first_timestamp = kNoTimestamp, last_timestamp = kNoTimestamp;
};

struct MapInfo {
  std::string path;
  int format_version = 0;
  // "ok": SQLite's quick_check and a read of the whole resume checkpoint found nothing wrong;
  // else "resume checkpoint damaged (the problem)": the LTM is readable, --resume refuses it.
  std::string integrity;
  long long images = 0;     // images the map's locations hold
  long long locations = 0;  // in the Long-Term Memory (all of them after Detector::Close)
  long long checkpoint_locations = 0;  // STM/WM of the last checkpoint (resume state)
  long long words = 0;                 // words stored in LTM, with descriptors (-1: not counted)
  long long whole_images = 0;  // LTM locations with a whole-image descriptor (features.whole_image)
  long long neighbour_links = 0;
  long long loop_closure_links = 0;
  ImageIndex last_image = kNoImage;  // the last image a checkpoint holds (--resume goes on after)
  // As edited (loop_closure_edits.h): the detected ones less those rejected, with those added.
  std::vector<MapLoopClosure> loop_closures;
  long long edits = 0;                   // edits in force (not undone)
  long long rejected_loop_closures = 0;  // detected, then rejected by an edit
  // A fleet's map: places of other robots that joined this robot's map, by robot.
  std::map<std::string, long long> foreign_places;
  // Empty for a map made before memloop recorded images (format 4 without the images table).
  std::vector<MapSession> sessions;
  std::vector<std::pair<std::string, std::string>> parameters;  // name, value as stored
  // The process writing the map as it was read (MapWriterProcess), 0 when none: what it had
  // committed then is what this holds, read in one transaction.
  long writer_pid = 0;
};

// Opens `path` read-only (its bytes never change). Throws DatabaseError naming the file when it
// is not a memloop map, is of a newer format, or SQLite finds it damaged; a damaged checkpoint
// is said in `integrity` (what LTM holds is still read). A map another process is writing is
// read as that process has committed it (`writer_pid`).
// kQuick skips what reads a large map whole: SQLite's quick_check (6 s for a 1 GB map of 51,739
// images), the count of LTM words (1.2 s there; `words` is -1) and the read of the whole resume
// checkpoint; `integrity` says so. The file must still be a memloop map of a known format. For a
// viewer of a large map.
enum class MapCheck { kFull, kQuick };
MapInfo InspectMap(const std::string& path, MapCheck check = MapCheck::kFull);

// Every image the map records, in index order (up to its last checkpoint). Throws DatabaseError
// as InspectMap does.
std::vector<MapImage> ReadMapImages(const std::string& path);

// The process id of the process writing the map at `path` now (a run, a node, a Detector not
// yet closed), -1 when one is but its id is not known yet, 0 when none is. A map being written is
// sound: readers see what its writer has committed so far.
long MapWriterProcess(const std::string& path);

}  // namespace memloop
