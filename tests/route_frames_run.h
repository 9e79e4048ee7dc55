// A detector run (T_time off, a map in a temporary folder) over frames given by a function, as the
// tests that change a generated route's frames (rolled, at night) need: every image's Result and
// the detections to evaluate, with the map's consistency checked after each image.
#pragma once

#include <gtest/gtest.h>

#include <functional>
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

inline FramesRun RunFrames(Options options, int count, const std::function<cv::Mat(int)>& frame) {
  options.memory.time_limit_ms = 0;
  TempDir dir;
  Detector detector(options, dir.File("map.db"));
  FramesRun run;
  for (int index = 0; index < count; ++index) {
    const Result result = detector.Process(frame(index), index);
    for (const std::string& problem : detector.CheckConsistency()) {
      ADD_FAILURE() << "after image " << index << ": " << problem;
    }
    if (!result.HasLoopClosure()) continue;
    run.detections.push_back({result.image_index, result.loop_closure_images});
    run.loop_closures.push_back(result);
  }
  return run;
}

}  // namespace memloop::testing
