// The pose-graph files `memloop export` writes (docs/export.md): g2o edges and TUM-convention
// relative poses. (Its JSON, with everything, is written by the tool.)
#include <cstdio>
#include <sstream>

#include "memloop/errors.h"
#include "memloop/map_export.h"
#include "util/output_files.h"

namespace memloop {
namespace {

// The loop closures with a pose, each as `line` formats it; the others as comment lines.
template <typename Line>
void WritePoses(const std::vector<ExportedLoopClosure>& loops, const char* header,
                std::ostream& out, Line line) {
  out << header
      << "# the query camera in the match camera's frame; translation of unit length, scale "
         "unknown\n";
  for (const ExportedLoopClosure& loop : loops) {
    const LoopGeometry& g = loop.geometry;
    if (!g.has_pose) {
      out << "# image " << loop.query.index << " -> image " << loop.match.index
          << ": no relative pose (" << g.pose_problem << ")\n";
      continue;
    }
    char text[512];
    line(loop, g, text, sizeof(text));
    out << text;
  }
}

// A pose-graph edge from the match to the query image: rotation information 400 (0.05 rad, about
// the 90th percentile of the error measured on tum_fr1_rpy, docs/export.md), translation a
// direction only (information 1e-6: its scale comes from odometry; unknown: 0 0 0).
void WriteG2o(const std::vector<ExportedLoopClosure>& loops, std::ostream& out) {
  WritePoses(loops,
             "# memloop loop closures: EDGE_SE3:QUAT match_image query_image tx ty tz qx qy qz "
             "qw information (upper triangle, 21 values)\n",
             out,
             [](const ExportedLoopClosure& loop, const LoopGeometry& g, char* text, size_t size) {
               std::snprintf(text, size,
                             "EDGE_SE3:QUAT %d %d %.9f %.9f %.9f %.9f %.9f %.9f %.9f "
                             "1e-06 0 0 0 0 0 1e-06 0 0 0 0 1e-06 0 0 0 400 0 0 400 0 400\n",
                             loop.match.index, loop.query.index, g.translation[0], g.translation[1],
                             g.translation[2], g.quaternion[0], g.quaternion[1], g.quaternion[2],
                             g.quaternion[3]);
             });
}

// One line per loop closure, TUM's pose layout after the two images' time stamps (their indices
// when the map has no time stamp).
void WriteTum(const std::vector<ExportedLoopClosure>& loops, std::ostream& out) {
  WritePoses(loops,
             "# memloop loop closures: query_timestamp match_timestamp tx ty tz qx qy qz qw\n", out,
             [](const ExportedLoopClosure& loop, const LoopGeometry& g, char* text, size_t size) {
               const auto stamp = [](const MapImage& image) {
                 return HasTimestamp(image.timestamp) ? image.timestamp : image.index;
               };
               std::snprintf(text, size, "%.6f %.6f %.9f %.9f %.9f %.9f %.9f %.9f %.9f\n",
                             stamp(loop.query), stamp(loop.match), g.translation[0],
                             g.translation[1], g.translation[2], g.quaternion[0], g.quaternion[1],
                             g.quaternion[2], g.quaternion[3]);
             });
}

}  // namespace

void WriteLoopClosures(const std::vector<ExportedLoopClosure>& loops, ExportFormat format,
                       const CameraIntrinsics& intrinsics, const std::string& path) {
  if (format == ExportFormat::kJson) {
    throw Error("WriteLoopClosures writes g2o and tum; JSON is the tool's (memloop export)");
  }
  if (!intrinsics.known()) {
    throw ParameterError("--intrinsics", std::string("--format ") +
                                             (format == ExportFormat::kG2o ? "g2o" : "tum") +
                                             " writes relative poses: give the camera's "
                                             "--intrinsics fx,fy,cx,cy");
  }
  std::ostringstream out;
  switch (format) {
    case ExportFormat::kJson:
      break;
    case ExportFormat::kG2o:
      WriteG2o(loops, out);
      break;
    case ExportFormat::kTum:
      WriteTum(loops, out);
      break;
  }
  WriteWholeFile(path, "the export file", out.str());
}

}  // namespace memloop
