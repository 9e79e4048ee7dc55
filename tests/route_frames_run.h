// A detector run (T_time off, a map in a temporary folder) over frames given by a function, as the
// tests that change a generated route's frames (rolled, at night) need: every image's Result and
// the detections to evaluate, with the map's consistency checked after each image.
#pragma once

#include <gtest/gtest.h>

#include <functional>
#include <memory>
#include <opencv2/core.hpp>
#include <vector>

#include "memloop/detector.h"
#include "memloop/evaluation.h"
#include "temp_dir.h"

namespace memloop::testing {

struct FramesRun {
  std::vector<Result> loop_closures;  // the results of the images that closed a loop
  std::vector<Detection> detections;  // the same, for memloop::Evaluate
};

// From image `new_session_from` on (if any), the frames are a new session of the map
// (MapMode::kNewSession), as `memloop run --new-session` adds them.
inline FramesRun RunFrames(Options options, int count, const std::function<cv::Mat(int)>& frame,
                           int new_session_from = -1) {
  options.memory.time_limit_ms = 0;
  TempDir dir;
  auto detector = std::make_unique<Detector>(options, dir.File("map.db"));
  FramesRun run;
  for (int index = 0; index < count; ++index) {
    if (index == new_session_from) {
      detector.reset();
      detector = std::make_unique<Detector>(options, dir.File("map.db"), MapMode::kNewSession);
    }
    const Result result = detector->Process(frame(index), index);
    for (const std::string& problem : detector->CheckConsistency()) {
      ADD_FAILURE() << "after image " << index << ": " << problem;
    }
    if (!result.HasLoopClosure()) continue;
    run.detections.push_back({result.image_index, result.loop_closure_images});
    run.loop_closures.push_back(result);
  }
  return run;
}

}  // namespace memloop::testing
