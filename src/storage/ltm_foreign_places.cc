// Places other robots of a fleet mapped, imported into this robot's map (fleet_places.h): the
// origin of each, which loop closures with them name.
#include <sstream>

#include "storage/ltm_database.h"

namespace memloop {
namespace {

std::string JoinImages(const std::vector<ImageIndex>& images) {
  std::ostringstream text;
  for (size_t i = 0; i < images.size(); ++i) text << (i ? ";" : "") << images[i];
  return text.str();
}

std::vector<ImageIndex> SplitImages(const std::string& text) {
  std::vector<ImageIndex> images;
  std::istringstream stream(text);
  std::string item;
  while (std::getline(stream, item, ';')) {
    if (!item.empty()) images.push_back(static_cast<ImageIndex>(std::stol(item)));
  }
  return images;
}

}  // namespace

void LtmDatabase::CreateForeignPlaceTable() {
  connection_->Execute(
      "CREATE TABLE IF NOT EXISTS foreign_places(location_id INTEGER PRIMARY KEY,"
      " origin_robot TEXT NOT NULL, origin_location INTEGER NOT NULL, origin_images TEXT NOT NULL,"
      " imported_image INTEGER NOT NULL)");
}

void LtmDatabase::WriteForeignPlace(const ForeignPlace& place) {
  Cached(
      "INSERT OR REPLACE INTO foreign_places(location_id, origin_robot, origin_location,"
      " origin_images, imported_image) VALUES(?,?,?,?,?)")
      .Bind(1, static_cast<long long>(place.location))
      .Bind(2, place.robot)
      .Bind(3, static_cast<long long>(place.origin_location))
      .Bind(4, JoinImages(place.images))
      .Bind(5, static_cast<long long>(place.imported_image))
      .Run();
}

std::vector<ForeignPlace> LtmDatabase::ReadForeignPlaces() {
  if (!has_foreign_) has_foreign_ = HasTable("foreign_places");
  std::vector<ForeignPlace> places;
  if (!*has_foreign_) return places;
  auto& query = Cached(
      "SELECT location_id, origin_robot, origin_location, origin_images, imported_image"
      " FROM foreign_places"
      " ORDER BY location_id");
  while (query.Step()) {
    ForeignPlace place;
    place.location = static_cast<LocationId>(query.Int(0));
    place.robot = query.Text(1);
    place.origin_location = static_cast<LocationId>(query.Int(2));
    place.imported_image = static_cast<ImageIndex>(query.Int(4));
    try {
      place.images = SplitImages(query.Text(3));
    } catch (const std::exception&) {
      query.Reset();
      throw DatabaseError(path(), "damaged: foreign place " + std::to_string(place.location) +
                                      " has unreadable images");
    }
    places.push_back(std::move(place));
  }
  query.Reset();
  return places;
}

}  // namespace memloop
