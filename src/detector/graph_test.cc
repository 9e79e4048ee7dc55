#include "detector/graph.h"

#include <gtest/gtest.h>

#include <map>

namespace memloop {
namespace {

TEST(GraphTest, BreadthFirstWithinRangeSortedByDistanceThenId) {
  // 1 - 2 - 3 - 4 - 5 - 6, and a loop closure 6 - 2.
  const std::map<LocationId, std::vector<LocationId>> links = {
      {1, {2}}, {2, {1, 3, 6}}, {3, {2, 4}}, {4, {3, 5}}, {5, {4, 6}}, {6, {5, 2}}};
  const auto links_of = [&](LocationId id) { return links.at(id); };
  const Neighbourhood expected = {{1, 0}, {2, 1}, {3, 2}, {6, 2}, {4, 3}, {5, 3}};
  EXPECT_EQ(FindNeighbourhood(1, 4, links_of), expected);
  const Neighbourhood within_one = {{1, 0}, {2, 1}};
  EXPECT_EQ(FindNeighbourhood(1, 1, links_of), within_one);
  const Neighbourhood alone = {{1, 0}};
  EXPECT_EQ(FindNeighbourhood(1, 0, links_of), alone);
}

}  // namespace
}  // namespace memloop
