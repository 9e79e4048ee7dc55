#include "detector/fleet_places.h"

#include <cstdint>
#include <set>

#include "detector/appearance_retrieval.h"
#include "memloop/errors.h"

namespace memloop {

void FleetPlaces::Reload(LtmDatabase& database) {
  for (ForeignPlace& place : database.ReadForeignPlaces()) {
    ids_[{place.robot, place.origin_location}] = place.location;
    places_[place.location] = std::move(place);
  }
}

void FleetPlaces::Follow(const std::string& uri, int descriptor_cv_type, int descriptor_dim) {
  std::set<std::pair<std::string, LocationId>> imported;
  for (const auto& entry : ids_) imported.insert(entry.first);
  follower_ =
      std::make_unique<FleetFollower>(uri, descriptor_cv_type, descriptor_dim, std::move(imported));
}

std::vector<LocationId> FleetPlaces::Import(size_t count, ImageIndex image, Memory& memory,
                                            LongTermMemory& ltm, BayesFilter& filter,
                                            AppearanceIndex* appearance) {
  std::vector<LocationId> ids;
  if (!follower_ || count == 0) return ids;
  for (const FleetLocation& place : follower_->Take(count)) {
    ids.push_back(ImportOne(place, image, memory, ltm, filter, appearance));
  }
  return ids;
}

size_t FleetPlaces::CatchUp(double seconds, ImageIndex image, Memory& memory, LongTermMemory& ltm,
                            BayesFilter& filter, AppearanceIndex* appearance) {
  if (!follower_) return 0;
  size_t imported = 0;
  for (bool complete = false; !complete;) {
    if (!follower_->WaitForFreshPoll(seconds, &complete)) {
      throw DatabaseError(ltm.path(), "the fleet's places could not be read within " +
                                          std::to_string(static_cast<int>(seconds)) + " s");
    }
    imported += Import(SIZE_MAX, image, memory, ltm, filter, appearance).size();
  }
  return imported;
}

std::vector<std::string> FleetPlaces::TakeNotices() {
  return follower_ ? follower_->TakeNotices() : std::vector<std::string>{};
}

LocationId FleetPlaces::ImportOne(const FleetLocation& place, ImageIndex image, Memory& memory,
                                  LongTermMemory& ltm, BayesFilter& filter,
                                  AppearanceIndex* appearance) {
  Dictionary& dictionary = memory.dictionary();
  // Each of its robot's words once, quantized as an image's features are (III-A).
  std::map<WordId, int> row_of_word;
  cv::Mat rows;
  for (size_t row = 0; row < place.words.size(); ++row) {
    if (row_of_word.emplace(place.words[row], rows.rows).second) {
      rows.push_back(place.descriptors.row(static_cast<int>(row)));
    }
  }
  const WordId first_new_word = dictionary.next_word_id();
  const std::vector<WordId> words = dictionary.Quantize(rows, nullptr);
  Location location;
  location.id = memory.ReserveId();
  location.weight = place.weight;
  for (WordId word : place.words) location.signature.words.push_back(words[row_of_word.at(word)]);
  location.signature.keypoints = place.keypoints;
  // Its neighbours among the places of its robot imported before it (still in the map), both
  // ways: Restore links those in memory, LTM's are written here.
  for (LocationId origin : place.neighbours) {
    const auto neighbour = ids_.find({place.robot, origin});
    if (neighbour == ids_.end()) continue;
    const LocationId id = neighbour->second;
    if (ltm.Contains(id)) {
      ltm.AddLink(id, location.id, /*loop_closure=*/false);
    } else if (!memory.Contains(id)) {
      continue;  // merged into another place since
    }
    location.neighbours.insert(id);
  }
  if (appearance != nullptr) {
    // Over each word once: new words join the vocabulary once.
    Signature unique;
    unique.words = words;
    Appearance description = DescribeNewLocation(*appearance, ltm, unique, rows, first_new_word);
    ltm.StoreAppearance(location.id, description);
    appearance->Add(location.id, std::move(description));
  }
  const LocationId id = location.id;
  memory.Restore(std::move(location));
  filter.Add(id);  // a new state, probability 0
  ForeignPlace origin{id, place.robot, place.id, place.images, image};
  ltm.RecordForeignPlace(origin);
  ids_[{place.robot, place.id}] = id;
  places_[id] = std::move(origin);
  return id;
}

}  // namespace memloop
