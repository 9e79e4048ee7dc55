#include "memloop/loop_closure_edits.h"

#include <gtest/gtest.h>

namespace memloop {
namespace {

MapLoopClosure Loop(ImageIndex query, ImageIndex match, double probability) {
  MapLoopClosure loop;
  loop.query_image = query;
  loop.match_image = match;
  loop.probability = probability;
  return loop;
}

LoopClosureEdit Edit(long long id, EditAction action, ImageIndex query, ImageIndex match) {
  LoopClosureEdit edit;
  edit.id = id;
  edit.action = action;
  edit.query_image = query;
  edit.match_image = match;
  return edit;
}

std::vector<std::pair<ImageIndex, ImageIndex>> Pairs(const std::vector<MapLoopClosure>& loops) {
  std::vector<std::pair<ImageIndex, ImageIndex>> pairs;
  for (const MapLoopClosure& loop : loops) pairs.emplace_back(loop.query_image, loop.match_image);
  return pairs;
}

TEST(LoopClosureEditsTest, RejectedLeaveAddedJoinUndoneCountForNothing) {
  const std::vector<MapLoopClosure> detected = {Loop(10, 2, 0.5), Loop(20, 5, 0.6),
                                                Loop(30, 7, 0.7)};
  std::vector<LoopClosureEdit> edits = {
      Edit(1, EditAction::kReject, 5, 20),  // the pair either way round
      Edit(2, EditAction::kAdd, 40, 1), Edit(3, EditAction::kReject, 30, 7),
      Edit(4, EditAction::kAdd, 10, 2),  // already there: nothing added
  };
  edits[2].undone = true;  // edit 3 taken back
  const std::vector<MapLoopClosure> edited = EditedLoopClosures(detected, edits);
  using P = std::pair<ImageIndex, ImageIndex>;
  EXPECT_EQ(Pairs(edited), (std::vector<P>{{10, 2}, {30, 7}, {40, 1}}));
  EXPECT_DOUBLE_EQ(edited[1].probability, 0.7);  // the detected one, as recorded
  EXPECT_EQ(edited[0].added_by_edit, 0);
  EXPECT_EQ(edited[2].added_by_edit, 2);
  EXPECT_DOUBLE_EQ(edited[2].probability, 0);
  // No edit: the detected ones as they are. An added one later rejected is gone.
  EXPECT_EQ(Pairs(EditedLoopClosures(detected, {})), Pairs(detected));
  edits.push_back(Edit(5, EditAction::kReject, 1, 40));
  EXPECT_EQ(Pairs(EditedLoopClosures(detected, edits)), (std::vector<P>{{10, 2}, {30, 7}}));
}

TEST(LoopClosureEditsTest, ActionNames) {
  EXPECT_STREQ(EditActionName(EditAction::kReject), "reject");
  EXPECT_STREQ(EditActionName(EditAction::kAdd), "add");
  EXPECT_STREQ(EditActionName(EditAction::kUndo), "undo");
}

}  // namespace
}  // namespace memloop
