#include "memloop/fleet_routes.h"

#include <gtest/gtest.h>

#include <set>

#include "memloop/errors.h"

namespace memloop {
namespace {

// Default options: a lap of 80 frames, detours of 30, 160 px a step, views 320 px wide, the same
// place within 0.6 x 320 = 192 px: frames one step apart always are (160 px plus jitter), two
// steps apart (320 px) never.
TEST(FleetRoutes, RobotsShareStretchesOfTheLoopAndNothingOfTheirDetours) {
  const FleetRoutes fleet(3);
  ASSERT_EQ(fleet.robots(), 3);
  EXPECT_EQ(fleet.route(0).size(), 110);  // the loop, then a detour
  EXPECT_EQ(fleet.route(1).size(), 70);   // a detour, then half the loop
  EXPECT_EQ(fleet.route(2).size(), 70);
  std::set<std::tuple<int, int, int, int>> pairs;
  for (const FleetPair& pair : fleet.Pairs()) {
    pairs.insert({pair.robot, pair.frame, pair.other, pair.other_frame});
  }
  for (const auto& [robot, frame, other, other_frame] : pairs) {
    EXPECT_TRUE(pairs.count({other, other_frame, robot, frame})) << "both ways";
    EXPECT_NE(robot, other);
    // a's detour (frames 80-109) and b's and c's (0-29) are nobody else's.
    if (robot == 0) {
      EXPECT_LT(frame, 80);
    } else {
      EXPECT_GE(frame, 30);
    }
  }
  // b's frame 30 + k walks loop step 8 + k (a's frame 8 + k); c's walks step 28 + k.
  for (int k = 0; k < 40; ++k) {
    EXPECT_TRUE(pairs.count({1, 30 + k, 0, 8 + k})) << k;
    EXPECT_FALSE(pairs.count({1, 30 + k, 0, 10 + k})) << k;
    EXPECT_TRUE(pairs.count({2, 30 + k, 0, 28 + k})) << k;
    // b and c overlap on steps 28-47.
    EXPECT_EQ(pairs.count({1, 30 + k, 2, 10 + k}), k >= 20 ? 1u : 0u) << k;
  }
}

TEST(FleetRoutes, RobotsSeeOnePlaceDifferently) {
  const FleetRoutes fleet(2);
  // b's frame 30 and a's frame 8 show loop step 8, each with its own jitter and noise.
  const cv::Mat a = fleet.route(0).RenderGray(8), b = fleet.route(1).RenderGray(30);
  EXPECT_GT(cv::norm(a, b, cv::NORM_L1), 0);
}

TEST(FleetRoutes, RefusesAFleetOfOne) { EXPECT_THROW(FleetRoutes(1), Error); }

}  // namespace
}  // namespace memloop
