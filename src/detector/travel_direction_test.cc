#include "detector/travel_direction.h"

#include <gtest/gtest.h>

namespace memloop {
namespace {

TEST(TravelDirectionTest, FollowsTheStepsBetweenRecognizedPlaces) {
  TravelDirection direction;
  EXPECT_TRUE(direction.newer_first());  // nothing seen yet
  direction.Observe(42);
  EXPECT_TRUE(direction.newer_first());  // one place: no step yet
  direction.Observe(40);
  EXPECT_FALSE(direction.newer_first());  // 42 -> 40: going back
  direction.Observe(40);
  direction.Observe(kNoLocation);
  EXPECT_FALSE(direction.newer_first());  // the same place, or none, changes nothing
  direction.Observe(44);
  EXPECT_TRUE(direction.newer_first());  // 40 -> 44
}

// A jump to another part of the map (a revisit starting, a mistaken image) is no step: newer
// first, the way a robot mostly revisits a route, until a step says otherwise.
TEST(TravelDirectionTest, AJumpIsNoStep) {
  TravelDirection direction;
  direction.Observe(815);
  direction.Observe(42);  // 815 -> 42: a revisit of an old place starts
  EXPECT_TRUE(direction.newer_first());
  direction.Observe(42 - TravelDirection::kMaxStep);  // a step back, the longest one
  EXPECT_FALSE(direction.newer_first());
  direction.Observe(100);  // jumped
  EXPECT_TRUE(direction.newer_first());
}

}  // namespace
}  // namespace memloop
