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

}  // namespace
}  // namespace memloop
