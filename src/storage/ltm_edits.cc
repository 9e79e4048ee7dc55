// The map's edits of its loop closures: one row each, never changed or removed (an undo is a row
// too), so that the history of a map's corrections stays in it.
#include "memloop/errors.h"
#include "storage/ltm_database.h"

namespace memloop {

void LtmDatabase::CreateEditTable() {
  if (on_server_) return;  // fleet_schema.h made it
  connection_->Execute(
      "CREATE TABLE IF NOT EXISTS loop_closure_edits(id INTEGER PRIMARY KEY,"
      " action TEXT NOT NULL, query_image INTEGER, match_image INTEGER, undone_edit INTEGER,"
      " who TEXT NOT NULL, time REAL NOT NULL)");
}

long long LtmDatabase::WriteEdit(const LoopClosureEdit& edit) {
  auto& insert = Cached(
      "INSERT INTO loop_closure_edits(action, query_image, match_image, undone_edit, who, time)"
      " VALUES(?,?,?,?,?,?)");
  insert.Bind(1, std::string(EditActionName(edit.action)));
  if (edit.action == EditAction::kUndo) {
    insert.BindNull(2).BindNull(3).Bind(4, edit.undone_edit);
  } else {
    insert.Bind(2, static_cast<long long>(edit.query_image))
        .Bind(3, static_cast<long long>(edit.match_image))
        .BindNull(4);
  }
  insert.Bind(5, edit.who).Bind(6, edit.time).Run();
  return QueryNumber("SELECT last_insert_rowid()");
}

std::vector<LoopClosureEdit> LtmDatabase::ReadEdits() {
  std::vector<LoopClosureEdit> edits;
  if (!HasTable("loop_closure_edits")) return edits;
  auto& query = Cached(
      "SELECT id, action, query_image, match_image, undone_edit, who, time"
      " FROM loop_closure_edits ORDER BY id");
  while (query.Step()) {
    LoopClosureEdit edit;
    edit.id = query.Int(0);
    const std::string action = query.Text(1);
    if (action == "reject") {
      edit.action = EditAction::kReject;
    } else if (action == "add") {
      edit.action = EditAction::kAdd;
    } else if (action == "undo") {
      edit.action = EditAction::kUndo;
    } else {
      query.Reset();
      throw DatabaseError(path(), "edit " + std::to_string(edit.id) + " has an unknown action '" +
                                      action + "' (a newer memloop's map?)");
    }
    if (!query.IsNull(2)) edit.query_image = static_cast<ImageIndex>(query.Int(2));
    if (!query.IsNull(3)) edit.match_image = static_cast<ImageIndex>(query.Int(3));
    if (!query.IsNull(4)) edit.undone_edit = query.Int(4);
    edit.who = query.Text(5);
    edit.time = query.Double(6);
    edits.push_back(std::move(edit));
  }
  query.Reset();
  for (const LoopClosureEdit& undo : edits) {
    if (undo.action != EditAction::kUndo) continue;
    for (LoopClosureEdit& edit : edits) {
      if (edit.id == undo.undone_edit) edit.undone = true;
    }
  }
  return edits;
}

LocationId LtmDatabase::ReadHolder(ImageIndex image) {
  auto& query = Cached("SELECT location_id FROM location_images WHERE image=?");
  query.Bind(1, static_cast<long long>(image));
  const LocationId holder = query.Step() ? static_cast<LocationId>(query.Int(0)) : kNoLocation;
  query.Reset();
  return holder;
}

std::vector<std::pair<ImageIndex, LocationId>> LtmDatabase::ReadHolders() {
  std::vector<std::pair<ImageIndex, LocationId>> holders;
  auto& query = Cached("SELECT image, location_id FROM location_images ORDER BY image");
  while (query.Step()) {
    holders.emplace_back(static_cast<ImageIndex>(query.Int(0)),
                         static_cast<LocationId>(query.Int(1)));
  }
  query.Reset();
  return holders;
}

}  // namespace memloop
