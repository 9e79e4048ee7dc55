#include "detector/neighbourhood_cache.h"

#include <gtest/gtest.h>

#include <random>

namespace memloop {
namespace {

Memory EmptyMemory() { return Memory(DescriptorKind::kFloat, 2, DictionaryOptions()); }

// A chain of `n` locations, all moved to WM.
std::vector<LocationId> Chain(Memory& memory, int n) {
  std::vector<LocationId> ids;
  for (int i = 0; i < n; ++i) {
    ids.push_back(memory.AddToStm(Signature(), i, ids.empty() ? kNoLocation : ids.back()).id);
  }
  memory.MoveStmOverflowToWm(0);
  return ids;
}

// 1 - 2 - ... - 13, range 1; then a loop closure 13 -> 1 (L_t = 13 takes 1's link to 2 and a
// link to 1): 1's neighbourhood gains 13, 13's gains 1 and 2, 2's gains 13. Touched: 13, 1 and 2
// (under a quarter of WM); within one link of them now: 1, 2, 3, 12 and 13, searched again; the
// other 8 are kept.
TEST(NeighbourhoodCacheTest, KeepsWhatAChangeCannotReach) {
  Memory memory = EmptyMemory();
  Chain(memory, 13);
  NeighbourhoodCache cache;
  EXPECT_EQ(cache.Update(memory, 1).at(4), (Neighbourhood{{4, 0}, {3, 1}, {5, 1}}));
  EXPECT_EQ(cache.searched(), 13u);  // the first search is of all

  memory.AddLinksOf(13, 1, /*link_together=*/true);
  const Neighbourhoods& kept = cache.Update(memory, 1);
  EXPECT_EQ(cache.searched(), 5u);
  EXPECT_EQ(kept.at(1), (Neighbourhood{{1, 0}, {2, 1}, {13, 1}}));
  EXPECT_EQ(kept.at(13), (Neighbourhood{{13, 0}, {1, 1}, {2, 1}, {12, 1}}));
  EXPECT_EQ(kept.at(2), (Neighbourhood{{2, 0}, {1, 1}, {3, 1}, {13, 1}}));
  EXPECT_EQ(kept.at(4), (Neighbourhood{{4, 0}, {3, 1}, {5, 1}}));
  EXPECT_EQ(kept, memory.WmNeighbourhoods(1));

  EXPECT_EQ(cache.Update(memory, 1), memory.WmNeighbourhoods(1));
  EXPECT_EQ(cache.searched(), 0u);  // nothing changed
}

// One new location at the end of a chain of 200: only the few within range of it are searched.
TEST(NeighbourhoodCacheTest, ANewLocationSearchesOnlyItsSurroundings) {
  Memory memory = EmptyMemory();
  const std::vector<LocationId> ids = Chain(memory, 200);
  NeighbourhoodCache cache;
  cache.Update(memory, 4);
  memory.AddToStm(Signature(), 200, ids.back());
  memory.MoveStmOverflowToWm(0);
  EXPECT_EQ(cache.Update(memory, 4), memory.WmNeighbourhoods(4));
  EXPECT_EQ(cache.searched(),
            6u);  // the new one, and the last 5 of the chain (its old end, 4 more)
}

// Every kind of change, drawn at random, against a search of all after each.
TEST(NeighbourhoodCacheTest, AgreesWithASearchOfAllAfterEveryChange) {
  Memory memory = EmptyMemory();
  std::vector<LocationId> ids = Chain(memory, 60);
  std::vector<Location> in_ltm;
  NeighbourhoodCache cache;
  std::mt19937 random(7);
  const auto any = [&](const IdSet& set) {
    auto it = set.begin();
    std::advance(it, random() % set.size());
    return *it;
  };
  for (int step = 0; step < 400; ++step) {
    const IdSet& wm = memory.working_memory();
    switch (random() % 6) {
      case 0:  // a new image, into STM, then WM
        ids.push_back(memory.AddToStm(Signature(), step, ids.back()).id);
        memory.MoveStmOverflowToWm(static_cast<int>(random() % 3));
        break;
      case 1:  // a loop closure
        if (wm.size() > 2) memory.AddLinksOf(any(wm), any(wm), /*link_together=*/true);
        break;
      case 2:  // a transfer to LTM
        if (wm.size() > 10) {
          std::vector<WordId> orphans;
          const LocationId id = any(wm);
          if (id != ids.back()) in_ltm.push_back(memory.Release(id, &orphans));
        }
        break;
      case 3:  // a retrieval
        if (!in_ltm.empty()) {
          memory.Restore(std::move(in_ltm.back()));
          in_ltm.pop_back();
        }
        break;
      case 4: {  // a merge
        const LocationId survivor = any(wm), absorbed = any(wm);
        if (survivor != absorbed && absorbed != ids.back()) memory.Absorb(survivor, absorbed);
        break;
      }
      default:  // nothing: the cache must still be right
        break;
    }
    const int range = step < 350 ? 3 : 2;  // a change of range searches all again
    ASSERT_EQ(cache.Update(memory, range), memory.WmNeighbourhoods(range)) << "step " << step;
  }
}

}  // namespace
}  // namespace memloop
