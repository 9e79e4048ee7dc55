// Which way the robot goes along a part of the map it revisits (memloop, issue 37). Location ids
// grow as the map is made, so the places recognized image after image have growing ids when the
// robot goes the way it went then, and falling ids when it goes back. Staged retrieval
// (retrieval.h) asks first for the neighbour that lies that way.
#pragma once

#include "memloop/types.h"

namespace memloop {

class TravelDirection {
 public:
  // The place recognized this image (kNoLocation: none): a step to a newer place says "newer",
  // to an older one "older"; the same place, or none, keeps what was said.
  void Observe(LocationId place) {
    if (place == kNoLocation) return;
    if (last_ != kNoLocation && place != last_) newer_first_ = place > last_;
    last_ = place;
  }
  // Before any step: newer first, the way a robot revisiting a route mostly goes.
  bool newer_first() const { return newer_first_; }

 private:
  LocationId last_ = kNoLocation;
  bool newer_first_ = true;
};

}  // namespace memloop
