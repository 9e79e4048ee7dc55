// Which way the robot goes along a part of the map it revisits (memloop, issue 37). Location ids
// grow as the map is made, so the places recognized image after image have growing ids when the
// robot goes the way it went then, and falling ids when it goes back. Staged retrieval
// (retrieval.h) asks first for the neighbour that lies that way.
#pragma once

#include "memloop/types.h"

namespace memloop {

class TravelDirection {
 public:
  // A step between places recognized image after image spans at most this many ids; a longer
  // one is a jump to another part of the map (a revisit starts, or one image was mistaken).
  static constexpr LocationId kMaxStep = 10;

  // The place recognized this image (kNoLocation: none): a step to a newer place says "newer",
  // to an older one "older"; the same place, or none, keeps what was said. A jump says nothing
  // of the way: newer first again, as before any step (asking for the older neighbours first at
  // the start of each revisit after a jump back in time cost one image of its retrieval).
  void Observe(LocationId place) {
    if (place == kNoLocation) return;
    if (last_ != kNoLocation && place != last_) {
      const bool jump = place > last_ + kMaxStep || last_ > place + kMaxStep;
      newer_first_ = jump || place > last_;
    }
    last_ = place;
  }
  // Before any step: newer first, the way a robot revisiting a route mostly goes.
  bool newer_first() const { return newer_first_; }

 private:
  LocationId last_ = kNoLocation;
  bool newer_first_ = true;
};

}  // namespace memloop
