#include "detector/consistency.h"

#include <gtest/gtest.h>

#include "small_map.h"

namespace memloop {
namespace {

// L1 .. L5 with L2, L3 and L4 in LTM: memory (L1, L5) links to L2 and L4.
class LtmCheckTest : public ::testing::Test {
 protected:
  void SetUp() override { ids_ = map_.ChainWithMiddleInLtm({{1}, {2}, {3}, {4}, {5}}); }

  testing::SmallMap map_;
  std::vector<LocationId> ids_;
};

TEST_F(LtmCheckTest, EveryLtmLocationOrThoseNearMemoryAndTheNewest) {
  ASSERT_EQ(map_.ltm.ids(), (std::set<LocationId>{ids_[1], ids_[2], ids_[3]}));
  EXPECT_EQ(LtmLocationsToCheck(map_.memory, map_.ltm, LtmCheck::kEvery),
            (std::vector<LocationId>{ids_[1], ids_[2], ids_[3]}));
  // Linked to memory: L2 (from L1) and L4 (from L5); L3 only as one of the newest.
  EXPECT_EQ(LtmLocationsToCheck(map_.memory, map_.ltm, LtmCheck::kNearMemory, 0),
            (std::vector<LocationId>{ids_[1], ids_[3]}));
  EXPECT_EQ(LtmLocationsToCheck(map_.memory, map_.ltm, LtmCheck::kNearMemory, 1),
            (std::vector<LocationId>{ids_[1], ids_[3]}));
  EXPECT_EQ(LtmLocationsToCheck(map_.memory, map_.ltm, LtmCheck::kNearMemory, 2),
            (std::vector<LocationId>{ids_[1], ids_[2], ids_[3]}));
  EXPECT_TRUE(map_.CheckConsistencyEmpty());
}

}  // namespace
}  // namespace memloop
