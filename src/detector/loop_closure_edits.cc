#include "memloop/loop_closure_edits.h"

#include <algorithm>
#include <chrono>

#include "memloop/errors.h"
#include "storage/ltm_database.h"
#include "storage/map_writer_lock.h"

namespace memloop {

namespace {

bool SamePair(ImageIndex a1, ImageIndex b1, ImageIndex a2, ImageIndex b2) {
  return (a1 == a2 && b1 == b2) || (a1 == b2 && b1 == a2);
}

double Now() {
  return std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
}

std::string Pair(ImageIndex query, ImageIndex match) {
  return "images " + std::to_string(query) + " and " + std::to_string(match);
}

// The map open to write one edit: refused while a run writes it (the lock), the edit's row
// written in a transaction of its own. The file's identity and format are checked, not every
// page (kAttach): an edit adds one row to a table of its own, and quick_check would read a 1 GB
// map whole for each (2.5 s; memloop inspect checks the pages).
class EditSession {
 public:
  explicit EditSession(const std::string& path)
      : lock_(path),
        // On a server, kOpen takes the robot's lock there, as lock_ does for a file.
        database_(path, IsServerMap(path) ? LtmDatabase::Mode::kOpen : LtmDatabase::Mode::kAttach) {
    lock_.Adopt();
    database_.CreateEditTable();
    database_.Begin();
  }
  LtmDatabase& database() { return database_; }
  std::vector<MapLoopClosure> LoopClosures() {
    return EditedLoopClosures(database_.ReadLoopClosures(), database_.ReadEdits());
  }
  LoopClosureEdit Write(LoopClosureEdit edit) {
    edit.time = Now();
    edit.id = database_.WriteEdit(edit);
    database_.Commit();
    return edit;
  }

 private:
  MapWriterLock lock_;
  LtmDatabase database_;
};

void CheckImage(LtmDatabase& database, ImageIndex image) {
  if (image < 0 || database.ReadHolder(image) == kNoLocation) {
    throw InputError(database.path(),
                     "image " + std::to_string(image) + " is not in the map's Long-Term Memory");
  }
}

MapLoopClosure* FindPair(std::vector<MapLoopClosure>& loops, ImageIndex a, ImageIndex b) {
  for (MapLoopClosure& loop : loops) {
    if (SamePair(loop.query_image, loop.match_image, a, b)) return &loop;
  }
  return nullptr;
}

}  // namespace

const char* EditActionName(EditAction action) {
  switch (action) {
    case EditAction::kReject:
      return "reject";
    case EditAction::kAdd:
      return "add";
    case EditAction::kUndo:
      return "undo";
  }
  return "?";
}

std::vector<MapLoopClosure> EditedLoopClosures(const std::vector<MapLoopClosure>& recorded,
                                               const std::vector<LoopClosureEdit>& edits) {
  std::vector<MapLoopClosure> loops = recorded;
  for (const LoopClosureEdit& edit : edits) {
    if (edit.undone || edit.action == EditAction::kUndo) continue;
    const auto same = [&](const MapLoopClosure& loop) {
      return SamePair(loop.query_image, loop.match_image, edit.query_image, edit.match_image);
    };
    if (edit.action == EditAction::kReject) {
      loops.erase(std::remove_if(loops.begin(), loops.end(), same), loops.end());
    } else if (std::none_of(loops.begin(), loops.end(), same)) {
      MapLoopClosure added;
      added.query_image = edit.query_image;
      added.match_image = edit.match_image;
      added.added_by_edit = edit.id;
      loops.push_back(added);
    }
  }
  return loops;
}

std::vector<LoopClosureEdit> ReadLoopClosureEdits(const std::string& map_path) {
  LtmDatabase database(map_path, LtmDatabase::Mode::kRead);
  return database.ReadEdits();
}

LoopClosureEdit RejectLoopClosure(const std::string& map_path, ImageIndex query_image,
                                  ImageIndex match_image, const std::string& who) {
  EditSession session(map_path);
  std::vector<MapLoopClosure> loops = session.LoopClosures();
  if (FindPair(loops, query_image, match_image) == nullptr) {
    throw InputError(map_path,
                     Pair(query_image, match_image) + " are not one of the map's loop closures");
  }
  LoopClosureEdit edit;
  edit.action = EditAction::kReject;
  edit.query_image = std::max(query_image, match_image);
  edit.match_image = std::min(query_image, match_image);
  edit.who = who;
  return session.Write(edit);
}

LoopClosureEdit AddLoopClosure(const std::string& map_path, ImageIndex query_image,
                               ImageIndex match_image, const std::string& who) {
  EditSession session(map_path);
  LtmDatabase& database = session.database();
  CheckImage(database, query_image);
  CheckImage(database, match_image);
  if (database.ReadHolder(query_image) == database.ReadHolder(match_image)) {
    throw InputError(map_path, Pair(query_image, match_image) +
                                   " are one location of the map (Rehearsal merged them): not a "
                                   "loop closure");
  }
  std::vector<MapLoopClosure> loops = session.LoopClosures();
  if (FindPair(loops, query_image, match_image) != nullptr) {
    throw InputError(
        map_path, Pair(query_image, match_image) + " are already one of the map's loop closures");
  }
  LoopClosureEdit edit;
  edit.action = EditAction::kAdd;
  edit.query_image = std::max(query_image, match_image);
  edit.match_image = std::min(query_image, match_image);
  edit.who = who;
  return session.Write(edit);
}

LoopClosureEdit UndoEdit(const std::string& map_path, long long edit_id, const std::string& who) {
  EditSession session(map_path);
  const std::vector<LoopClosureEdit> edits = session.database().ReadEdits();
  const auto found = std::find_if(edits.begin(), edits.end(),
                                  [&](const LoopClosureEdit& edit) { return edit.id == edit_id; });
  if (found == edits.end()) {
    throw InputError(map_path, "the map has no edit " + std::to_string(edit_id));
  }
  if (found->action == EditAction::kUndo) {
    throw InputError(
        map_path, "edit " + std::to_string(edit_id) + " is an undo; make the edit again instead");
  }
  if (found->undone) {
    throw InputError(map_path, "edit " + std::to_string(edit_id) + " is already undone");
  }
  LoopClosureEdit undo;
  undo.action = EditAction::kUndo;
  undo.undone_edit = edit_id;
  undo.who = who;
  return session.Write(undo);
}

}  // namespace memloop
