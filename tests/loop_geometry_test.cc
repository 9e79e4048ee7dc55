// The geometry of each loop closure for a SLAM back-end: in Result as it is found (camera.fx..cy
// set), and from the map by `ExportLoopClosures`, the same for the same two views.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>

#include "memloop/detector.h"
#include "memloop/errors.h"
#include "memloop/map_export.h"
#include "memloop/synthetic_route.h"
#include "short_route.h"
#include "temp_dir.h"

namespace memloop {
namespace {

Options WithCamera() {
  Options options;
  options.memory.time_limit_ms = 0;
  options.camera = {300, 300, 160, 120};
  return options;
}

TEST(LoopGeometryResultTest, AcceptedLoopClosuresCarryTheGeometryTheExportGives) {
  testing::TempDir dir;
  const SyntheticRoute route(testing::ShortRoute());
  const std::string map = dir.File("map.db");
  std::vector<Result> accepted;
  {
    Detector detector(WithCamera(), map);
    for (int i = 0; i < route.size(); ++i) {
      Result result = detector.Process(route.Render(i), i);
      if (result.HasLoopClosure()) accepted.push_back(std::move(result));
    }
  }
  ASSERT_GT(accepted.size(), 20u);
  int with_inliers = 0;
  int posed = 0;
  for (const Result& result : accepted) {
    const LoopGeometry& g = result.loop_closure_geometry;
    // The images whose keypoints the two locations hold: the image or one Rehearsal merged into
    // its location, and one of the matched location's images.
    EXPECT_LE(g.query_view, result.image_index);
    EXPECT_NE(std::find(result.loop_closure_images.begin(), result.loop_closure_images.end(),
                        g.match_view),
              result.loop_closure_images.end());
    EXPECT_GE(g.correspondences, static_cast<int>(g.inliers.size()));
    with_inliers += !g.inliers.empty();
    if (!g.has_pose) continue;
    ++posed;
    // A rotation (R R^T = I) and a direction.
    for (int row = 0; row < 3; ++row) {
      for (int column = 0; column < 3; ++column) {
        double dot = 0;
        for (int k = 0; k < 3; ++k) dot += g.rotation[row * 3 + k] * g.rotation[column * 3 + k];
        EXPECT_NEAR(dot, row == column ? 1 : 0, 1e-6);
      }
    }
    EXPECT_NEAR(std::hypot(g.translation[0], g.translation[1], g.translation[2]),
                g.translation_known ? 1 : 0, 1e-6);
    EXPECT_LE(g.pose_inliers, static_cast<int>(g.inliers.size()));
  }
  EXPECT_GT(with_inliers, 0);
  EXPECT_GT(posed, 0);

  // The export of the closed map: the same geometry wherever it compares the same two views.
  std::map<std::pair<ImageIndex, ImageIndex>, const LoopGeometry*> found;
  for (const Result& result : accepted) {
    const LoopGeometry& g = result.loop_closure_geometry;
    found[{g.query_view, g.match_view}] = &g;
  }
  int compared = 0;
  for (const ExportedLoopClosure& loop : ExportLoopClosures(map, {300, 300, 160, 120})) {
    const auto same = found.find({loop.geometry.query_view, loop.geometry.match_view});
    if (same == found.end()) continue;  // a view absorbed since
    ++compared;
    EXPECT_EQ(loop.geometry.inliers.size(), same->second->inliers.size());
    EXPECT_EQ(loop.geometry.has_pose, same->second->has_pose);
    if (loop.geometry.has_pose) {
      EXPECT_EQ(loop.geometry.rotation, same->second->rotation);
    }
  }
  EXPECT_GT(compared, 0);  // rehearsal merges most query views into later locations
}

TEST(LoopGeometryResultTest, NoIntrinsicsNoGeometryAndBothFocalLengthsNeeded) {
  testing::TempDir dir;
  const SyntheticRoute route(testing::ShortRoute());
  Options options = WithCamera();
  options.camera = {};
  {
    Detector detector(options, dir.File("plain.db"));
    for (int i = 0; i < 60; ++i) {
      const Result result = detector.Process(route.Render(i), i);
      EXPECT_EQ(result.loop_closure_geometry.correspondences, 0);
      EXPECT_TRUE(result.loop_closure_geometry.inliers.empty());
    }
  }
  options.camera.fx = 300;
  EXPECT_THROW(Detector(options, dir.File("half.db")), ParameterError);
}

}  // namespace
}  // namespace memloop
