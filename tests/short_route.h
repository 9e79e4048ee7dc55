// The short generated route shared by the integration tests: one lap of 40 frames, a detour of
// 10 and 10 frames of a third lap (about 110 images, a few seconds per run).
#pragma once

#include "memloop/synthetic_route.h"

namespace memloop::testing {

inline SyntheticRouteOptions ShortRoute() {
  SyntheticRouteOptions options;
  options.lap_frames = 40;
  options.detour_frames = 10;
  options.third_lap_frames = 10;
  return options;
}

}  // namespace memloop::testing
