#include "memloop/result.h"

#include <cstdio>

namespace memloop {

void Result::AddTimeDecision(const std::string& what) {
  if (("|" + time_decided + "|").find("|" + what + "|") != std::string::npos) return;
  time_decided += (time_decided.empty() ? "" : "|") + what;
}

std::string Result::Brief() const {
  if (!processed) return "Detector::Process was not called.";
  char text[256];
  if (location_id == kNoLocation) {  // localization: the image made no location
    if (HasLoopClosure()) {
      std::snprintf(text, sizeof(text), "image %d: localized at location %d (image %d), p=%.3f",
                    image_index, loop_closure_id,
                    loop_closure_images.empty() ? kNoImage : loop_closure_images.front(),
                    hypothesis_value);
    } else {
      std::snprintf(text, sizeof(text), "image %d: not localized (highest hypothesis %d, p=%.3f)",
                    image_index, hypothesis_id, hypothesis_value);
    }
  } else if (HasLoopClosure()) {
    // Another robot's place (a fleet's map): its robot names the image.
    const std::string robot = loop_closure_robot.empty() ? "" : "robot " + loop_closure_robot + " ";
    std::snprintf(text, sizeof(text),
                  "image %d -> location %d: loop closure with location %d (%simage %d), p=%.3f",
                  image_index, location_id, loop_closure_id, robot.c_str(),
                  loop_closure_images.empty() ? kNoImage : loop_closure_images.front(),
                  hypothesis_value);
  } else {
    std::snprintf(text, sizeof(text),
                  "image %d -> location %d: no loop closure (highest hypothesis %d, p=%.3f)",
                  image_index, location_id, hypothesis_id, hypothesis_value);
  }
  return text;
}

}  // namespace memloop
