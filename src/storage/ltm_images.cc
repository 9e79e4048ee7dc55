// The map's images (name, time stamp, session) as LtmDatabase stores them: what a resumed run
// checks its input against, `memloop inspect` lists by session and `memloop export` gives a
// back-end with each loop closure.
#include "storage/fleet_schema.h"
#include "storage/ltm_database.h"

namespace memloop {

void LtmDatabase::CreateImageTable() {
  connection_->Execute(
      "CREATE TABLE IF NOT EXISTS images(image INTEGER PRIMARY KEY, session INTEGER NOT NULL,"
      " name TEXT NOT NULL, stamp REAL);"
      "CREATE INDEX IF NOT EXISTS images_session ON images(session, image);"
      "CREATE TABLE IF NOT EXISTS location_views(location_id INTEGER PRIMARY KEY,"
      " image INTEGER NOT NULL);"
      "CREATE TABLE IF NOT EXISTS whole_images(location_id INTEGER PRIMARY KEY,"
      " descriptor BLOB NOT NULL);");
}

void LtmDatabase::WriteWholeImage(const Location& location) {
  const std::vector<uint8_t>& descriptor = location.signature.whole_image;
  auto& statement =
      Cached(descriptor.empty() ? "DELETE FROM whole_images WHERE location_id=?"
                                : "INSERT OR REPLACE INTO whole_images(location_id, descriptor)"
                                  " VALUES(?,?)");
  statement.Bind(1, static_cast<long long>(location.id));
  if (!descriptor.empty()) {
    statement.BindBlob(2, descriptor.data(), static_cast<int>(descriptor.size()));
  }
  statement.Run();
}

long long LtmDatabase::CountWholeImages() {
  if (!has_whole_images_) has_whole_images_ = HasTable("whole_images");
  return *has_whole_images_ ? QueryNumber("SELECT count(*) FROM whole_images") : 0;
}

std::vector<uint8_t> LtmDatabase::ReadWholeImage(LocationId id) {
  if (!has_whole_images_) has_whole_images_ = HasTable("whole_images");
  if (!*has_whole_images_) return {};
  auto& query = Cached("SELECT descriptor FROM whole_images WHERE location_id=?");
  query.Bind(1, static_cast<long long>(id));
  std::vector<uint8_t> descriptor;
  if (query.Step()) descriptor = query.Blob(0);
  query.Reset();
  return descriptor;
}

void LtmDatabase::WriteView(const Location& location) {
  auto& statement =
      Cached(location.signature.image == kNoImage
                 ? "DELETE FROM location_views WHERE location_id=?"
                 : "INSERT OR REPLACE INTO location_views(location_id, image) VALUES(?,?)");
  statement.Bind(1, static_cast<long long>(location.id));
  if (location.signature.image != kNoImage) {
    statement.Bind(2, static_cast<long long>(location.signature.image));
  }
  statement.Run();
}

ImageIndex LtmDatabase::ReadView(LocationId id) {
  if (!has_views_) has_views_ = HasTable("location_views");
  if (!*has_views_) return kNoImage;
  auto& query = Cached("SELECT image FROM location_views WHERE location_id=?");
  query.Bind(1, static_cast<long long>(id));
  const ImageIndex image = query.Step() ? static_cast<ImageIndex>(query.Int(0)) : kNoImage;
  query.Reset();
  return image;
}

void LtmDatabase::WriteImage(const MapImage& image) {
  // A NaN binds as NULL: no time stamp.
  Cached("INSERT OR REPLACE INTO images(image, session, name, stamp) VALUES(?,?,?,?)")
      .Bind(1, static_cast<long long>(image.index))
      .Bind(2, static_cast<long long>(image.session))
      .Bind(3, image.name)
      .Bind(4, image.timestamp)
      .Run();
}

namespace {

MapImage ImageOf(const SqlStatement& row, int first_column) {
  MapImage image;
  image.index = static_cast<ImageIndex>(row.Int(first_column));
  image.session = static_cast<int>(row.Int(first_column + 1));
  image.name = row.Text(first_column + 2);
  image.timestamp = row.IsNull(first_column + 3) ? kNoTimestamp : row.Double(first_column + 3);
  return image;
}

}  // namespace

std::vector<MapImage> LtmDatabase::ReadImages() {
  std::vector<MapImage> images;
  if (!HasTable("images")) return images;
  auto& query = Cached("SELECT image, session, name, stamp FROM images ORDER BY image");
  while (query.Step()) images.push_back(ImageOf(query, 0));
  query.Reset();
  return images;
}

std::vector<MapImage> LtmDatabase::ReadImagesOf(const std::string& robot) {
  std::vector<MapImage> images;
  if (!on_server_) return images;
  auto& query = Cached(std::string("SELECT image, session, name, stamp FROM ") + kFleetSchema +
                       ".images WHERE robot = ? ORDER BY image");
  query.Bind(1, robot);
  while (query.Step()) images.push_back(ImageOf(query, 0));
  query.Reset();
  return images;
}

std::vector<MapSession> LtmDatabase::ReadSessions() {
  std::vector<MapSession> sessions;
  if (!HasTable("images")) return sessions;
  auto& query = Cached(
      "SELECT session, min(image), max(image), count(*) FROM images GROUP BY session"
      " ORDER BY session");
  while (query.Step()) {
    MapSession session;
    session.id = static_cast<int>(query.Int(0));
    session.first_image = static_cast<ImageIndex>(query.Int(1));
    session.last_image = static_cast<ImageIndex>(query.Int(2));
    session.images = query.Int(3);
    sessions.push_back(session);
  }
  query.Reset();
  auto& image = Cached("SELECT image, session, name, stamp FROM images WHERE image=?");
  const auto read = [&](ImageIndex index) {
    image.Bind(1, static_cast<long long>(index));
    MapImage found;
    if (image.Step()) found = ImageOf(image, 0);
    image.Reset();
    return found;
  };
  for (MapSession& session : sessions) {
    const MapImage first = read(session.first_image);
    const MapImage last = read(session.last_image);
    session.first_name = first.name;
    session.first_timestamp = first.timestamp;
    session.last_name = last.name;
    session.last_timestamp = last.timestamp;
  }
  return sessions;
}

}  // namespace memloop
