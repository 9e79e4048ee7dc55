// Corrections a person makes to a map's loop closures (`memloop view`): a wrong one rejected, a
// missed one added, either taken back. Each edit is a row of the map (who, when, what), never a
// change of what the detector recorded: inspect, export and the viewer show the loop closures as
// edited, --resume and localization keep the edits, and an undo restores the recorded ones.
// The links the detector uses to find places are the detector's own: an edit does not move them.
#pragma once

#include <string>
#include <vector>

#include "memloop/map_info.h"
#include "memloop/types.h"

namespace memloop {

enum class EditAction { kReject, kAdd, kUndo };

struct LoopClosureEdit {
  long long id = 0;  // 1, 2, ... in the order made
  EditAction action = EditAction::kReject;
  ImageIndex query_image = kNoImage;  // reject, add: the pair (query: the later image)
  ImageIndex match_image = kNoImage;
  long long undone_edit = 0;  // undo: the edit it takes back
  std::string who;            // as the editor gave it (the viewer: the user's login name)
  double time = 0;            // seconds since the epoch (UTC)
  bool undone = false;        // read back: a later undo took it back
};

const char* EditActionName(EditAction action);  // "reject", "add", "undo"

// The loop closures `recorded` after `edits` (in their order; undone ones are not applied):
// a rejected pair leaves the list, an added one joins it at the end (probability 0,
// `added` set). A pair is the same either way round.
std::vector<MapLoopClosure> EditedLoopClosures(const std::vector<MapLoopClosure>& recorded,
                                               const std::vector<LoopClosureEdit>& edits);

// The map's edits in the order made, `undone` set on those taken back; none for a map never
// edited. Throws DatabaseError as InspectMap does.
std::vector<LoopClosureEdit> ReadLoopClosureEdits(const std::string& map_path);

// Each writes one edit into the map and returns it as stored. Refused, with the map unchanged:
// DatabaseError while a run writes the map (naming its pid) or when the file is not a memloop
// map; InputError naming the problem for an image the map does not hold, a pair that is not one
// of its loop closures (reject) or already is (add), a pair of one location, or an edit that
// does not exist or is an undo or already undone (undo).
// `memloop export` estimates an added loop closure's pose from the two locations' words, as it
// does for a detected one whose pose was not kept.
LoopClosureEdit RejectLoopClosure(const std::string& map_path, ImageIndex query_image,
                                  ImageIndex match_image, const std::string& who);
LoopClosureEdit AddLoopClosure(const std::string& map_path, ImageIndex query_image,
                               ImageIndex match_image, const std::string& who);
LoopClosureEdit UndoEdit(const std::string& map_path, long long edit_id, const std::string& who);

}  // namespace memloop
