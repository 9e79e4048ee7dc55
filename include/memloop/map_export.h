// A map's loop closures for a SLAM back-end (`memloop export`): each with both images' names,
// indices, time stamps and sessions, the hypothesis value, the epipolar inliers between the two
// views' shared words and, given the camera's intrinsics, the relative pose from the essential
// matrix (rotation and the direction of the translation: one camera cannot give its scale).
#pragma once

#include <string>
#include <vector>

#include "memloop/loop_geometry.h"
#include "memloop/map_info.h"

namespace memloop {

struct ExportedLoopClosure {
  MapLoopClosure loop;
  MapImage query, match;  // index kNoImage... when the map does not record the image
  // Empty (no correspondences) when a view's location is not in the map's LTM (a map not
  // closed: STM and WM are only in its checkpoint).
  LoopGeometry geometry;
};

// Reads the map read-only. Each loop closure's geometry is estimated from the map's locations
// with `intrinsics` (the inliers); its pose is the one kept when it was accepted where the map
// kept one with the same intrinsics (the map's camera.*; `intrinsics` unknown means those).
// Throws DatabaseError as InspectMap does.
std::vector<ExportedLoopClosure> ExportLoopClosures(const std::string& map_path,
                                                    const CameraIntrinsics& intrinsics = {});

enum class ExportFormat { kJson, kG2o, kTum };
// "json", "g2o", "tum"; ParameterError naming `--format` otherwise.
ExportFormat ParseExportFormat(const std::string& name);
// Writes `loops` to `path` as g2o edges or TUM-convention poses (docs/export.md): both need the
// relative poses, so `intrinsics` must be known (ParameterError). Throws InputError when the file
// cannot be written. (`memloop export --format json` writes everything, poses or not.)
void WriteLoopClosures(const std::vector<ExportedLoopClosure>& loops, ExportFormat format,
                       const CameraIntrinsics& intrinsics, const std::string& path);

}  // namespace memloop
