#include "detector/appearance_retrieval.h"

#include <gtest/gtest.h>

namespace memloop {
namespace {

// The threshold for retrieval by appearance: appearance_min_z, or the multiple of sqrt(2 ln N)
// when more. By hand: sqrt(2 ln 100) = 3.0349, sqrt(2 ln 1,000) = 3.7169, sqrt(2 ln 10^6) = 5.2565.
TEST(AppearanceMinZTest, RisesWithLtmAsTheBestOfItsChanceScores) {
  MemoryOptions options;
  options.appearance_min_z = 8;
  options.appearance_chance_multiple = 2.5;
  EXPECT_DOUBLE_EQ(AppearanceMinZ(options, 0), 8);  // no LTM: no chance score
  EXPECT_DOUBLE_EQ(AppearanceMinZ(options, 1), 8);
  EXPECT_DOUBLE_EQ(AppearanceMinZ(options, 100), 8);  // 2.5 x 3.0349 = 7.59, under the floor
  EXPECT_NEAR(AppearanceMinZ(options, 1000), 9.2923, 1e-4);
  EXPECT_NEAR(AppearanceMinZ(options, 1000000), 13.1413, 1e-4);
  options.appearance_chance_multiple = 0;  // appearance_min_z alone, whatever LTM's size
  EXPECT_DOUBLE_EQ(AppearanceMinZ(options, 1000000), 8);
  options.appearance_min_z = 0;
  options.appearance_chance_multiple = 1;
  EXPECT_NEAR(AppearanceMinZ(options, 1000), 3.7169, 1e-4);
}

}  // namespace
}  // namespace memloop
