#include "detector/memory.h"

#include <gtest/gtest.h>

#include "small_memory.h"

namespace memloop {
namespace {

TEST(MemoryTest, NewLocationsAreLinkedBothWaysAndLeaveStmOldestFirst) {
  Memory memory(DescriptorKind::kFloat, 2, testing::SmallDictionaryOptions());
  const auto ids = testing::AddChain(memory, {{1}, {2}, {3}, {4}});
  EXPECT_EQ(memory.at(ids[1]).neighbours, (std::set<LocationId>{ids[0], ids[2]}));
  EXPECT_EQ(memory.at(ids[0]).weight, 0);
  memory.MoveStmOverflowToWm(2);
  EXPECT_EQ(memory.working_memory(), (IdSet{ids[0], ids[1]}));
  EXPECT_EQ(memory.stm(), (std::deque<LocationId>{ids[2], ids[3]}));
}

TEST(MemoryTest, AbsorbRewiresLinksAndReturnsOrphanWords) {
  Memory memory(DescriptorKind::kFloat, 2, testing::SmallDictionaryOptions());
  const auto ids = testing::AddChain(memory, {{1}, {2, 9}, {3}, {4}});
  memory.MoveStmOverflowToWm(0);
  const auto orphans = memory.Absorb(ids[3], ids[1]);  // L2 disappears into L4
  EXPECT_EQ(orphans, (std::vector<WordId>{2, 9}));
  EXPECT_FALSE(memory.Contains(ids[1]));
  EXPECT_EQ(memory.at(ids[3]).neighbours, (std::set<LocationId>{ids[0], ids[2]}));
  EXPECT_EQ(memory.at(ids[0]).neighbours, (std::set<LocationId>{ids[3]}));
  EXPECT_EQ(memory.at(ids[3]).images, (std::vector<ImageIndex>{3, 1}));
}

TEST(MemoryTest, ReleaseAndRestoreKeepTheGraph) {
  Memory memory(DescriptorKind::kFloat, 2, testing::SmallDictionaryOptions());
  const auto ids = testing::AddChain(memory, {{1, 5}, {2, 5}, {3}});
  memory.MoveStmOverflowToWm(0);
  std::vector<WordId> orphans;
  Location released = memory.Release(ids[1], &orphans);
  EXPECT_EQ(orphans, (std::vector<WordId>{2}));             // word 5 is still L1's
  EXPECT_TRUE(memory.at(ids[0]).neighbours.count(ids[1]));  // links to LTM stay
  memory.Restore(std::move(released));
  EXPECT_TRUE(memory.InWorkingMemory(ids[1]));
  EXPECT_EQ(memory.dictionary().References(5).size(), 2u);
}

TEST(MemoryTest, WorkingMemoryNeighbourhoodPassesThroughStmButHoldsOnlyWm) {
  Memory memory(DescriptorKind::kFloat, 2, testing::SmallDictionaryOptions());
  const auto ids = testing::AddChain(memory, {{1}, {2}, {3}, {4}, {5}});
  memory.MoveStmOverflowToWm(3);                              // WM: L1, L2; STM: L3, L4, L5
  memory.AddLinksOf(ids[4], ids[0], /*link_together=*/true);  // L5 <-> L1 loop closure
  const Neighbourhood expected = {{ids[0], 0}, {ids[1], 1}};
  EXPECT_EQ(memory.WmNeighbourhood(ids[0], 4), expected);
}

TEST(MemoryTest, AllWorkingMemoryNeighbourhoodsAtOnceGiveEachOnesAnswer) {
  Memory memory(DescriptorKind::kFloat, 2, testing::SmallDictionaryOptions());
  const auto ids =
      testing::AddChain(memory, {{1}, {2}, {3}, {4}, {5}, {6}, {7}, {8}, {9}, {10}, {11}, {12}});
  memory.MoveStmOverflowToWm(4);                    // WM: L1..L8; STM: L9..L12
  memory.at(ids[10]).loop_closures.insert(ids[1]);  // L11 <-> L2
  memory.at(ids[1]).loop_closures.insert(ids[10]);
  std::vector<WordId> orphans;
  memory.Release(ids[4], &orphans);  // L5 to LTM: L4's and L6's links to it stay
  const Neighbourhoods all = memory.WmNeighbourhoods(2);
  ASSERT_EQ(all.size(), memory.working_memory().size());
  // By hand: L2 reaches L1, L3 and (through STM's L11) L10, L12 of STM, then L4 at 2.
  EXPECT_EQ(all.at(ids[1]), (Neighbourhood{{ids[1], 0}, {ids[0], 1}, {ids[2], 1}, {ids[3], 2}}));
  EXPECT_EQ(all.at(ids[3]), (Neighbourhood{{ids[3], 0}, {ids[2], 1}, {ids[1], 2}}));  // not L5
  EXPECT_EQ(all.at(ids[7]), (Neighbourhood{{ids[7], 0}, {ids[6], 1}, {ids[5], 2}}));
  EXPECT_EQ(memory.WmNeighbourhoods(3).at(ids[0]),
            (Neighbourhood{{ids[0], 0}, {ids[1], 1}, {ids[2], 2}, {ids[3], 3}}));
  for (LocationId id : memory.working_memory()) {
    EXPECT_EQ(all.at(id), memory.WmNeighbourhood(id, 2)) << "location " << id;
  }
}

}  // namespace
}  // namespace memloop
