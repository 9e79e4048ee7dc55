#include "detector/consistency.h"

#include <cmath>
#include <map>

namespace memloop {
namespace {

class Problems {
 public:
  explicit Problems(size_t max) : max_(max) {}
  bool full() const { return lines_.size() >= max_; }
  void Add(const std::string& line) {
    if (!full()) lines_.push_back(line);
  }
  std::vector<std::string> Take() { return std::move(lines_); }

 private:
  size_t max_;
  std::vector<std::string> lines_;
};

std::string Name(LocationId id) { return "location " + std::to_string(id); }

const std::set<LocationId>& LinksOfType(const Location& location, bool loop_closure) {
  return loop_closure ? location.loop_closures : location.neighbours;
}

// Both ends of every link exist, and each end links back with the same type.
void CheckLinks(const Location& location, const Memory& memory, LongTermMemory& ltm,
                Problems& problems) {
  for (const bool loop_closure : {false, true}) {
    const char* type = loop_closure ? "loop-closure link" : "neighbour link";
    for (LocationId other : LinksOfType(location, loop_closure)) {
      if (other == location.id) {
        problems.Add(Name(location.id) + " has a " + type + " to itself");
        continue;
      }
      std::optional<Location> from_ltm;
      const Location* far = nullptr;
      if (memory.Contains(other)) {
        far = &memory.at(other);
      } else if ((from_ltm = ltm.Peek(other))) {
        far = &*from_ltm;
      }
      if (far == nullptr) {
        problems.Add(Name(location.id) + " has a " + type + " to " + Name(other) +
                     ", which is neither in memory nor in LTM");
      } else if (!LinksOfType(*far, loop_closure).count(location.id)) {
        problems.Add(Name(location.id) + " has a one-way " + type + " to " + Name(other));
      }
    }
  }
}

void CheckMemory(const Memory& memory, Problems& problems) {
  size_t stm_and_wm = memory.working_memory().size();
  for (LocationId id : memory.stm()) {
    ++stm_and_wm;
    if (!memory.Contains(id)) problems.Add("STM holds " + Name(id) + ", which does not exist");
    if (memory.InWorkingMemory(id)) problems.Add(Name(id) + " is in both STM and WM");
  }
  for (LocationId id : memory.working_memory()) {
    if (!memory.Contains(id)) problems.Add("WM holds " + Name(id) + ", which does not exist");
  }
  if (stm_and_wm != memory.size()) {
    problems.Add("memory holds " + std::to_string(memory.size()) + " locations, STM and WM " +
                 std::to_string(stm_and_wm));
  }
}

// Each memory location's words are in the dictionary with its exact count, and every dictionary
// word is referenced by memory (an unreferenced word should have left).
void CheckWords(const Memory& memory, Problems& problems) {
  const Dictionary& dictionary = memory.dictionary();
  std::map<WordId, std::map<LocationId, int>> expected;
  for (const auto& [id, location] : memory.locations()) {
    for (const auto& [word, count] : location.signature.Histogram()) {
      expected[word][id] = count;
      if (!dictionary.Contains(word)) {
        problems.Add(Name(id) + " holds word " + std::to_string(word) +
                     ", which is not in the dictionary");
      }
    }
  }
  for (WordId word : dictionary.Ids()) {
    const auto& references = dictionary.References(word);
    if (references.empty()) problems.Add("word " + std::to_string(word) + " has no reference");
    const auto found = expected.find(word);
    if (found == expected.end() ? !references.empty() : references != found->second) {
      problems.Add("word " + std::to_string(word) + " has wrong references");
    }
  }
  if (dictionary.index().size() != dictionary.size()) {
    problems.Add("the dictionary holds " + std::to_string(dictionary.size()) +
                 " words, its index " + std::to_string(dictionary.index().size()));
  }
}

void CheckLtmLocation(LocationId id, const Memory& memory, LongTermMemory& ltm,
                      Problems& problems) {
  if (memory.Contains(id)) problems.Add(Name(id) + " is in both memory and LTM");
  const std::optional<Location> location = ltm.Peek(id);
  if (!location) {
    problems.Add(Name(id) + " is listed in LTM but cannot be read");
    return;
  }
  CheckLinks(*location, memory, ltm, problems);
  if (ltm.LinksOf(id) != location->Links()) {
    problems.Add("LTM's link graph in memory disagrees with the map file about " + Name(id));
  }
  const Dictionary& dictionary = memory.dictionary();
  for (const auto& [word, count] : location->signature.Histogram()) {
    if (dictionary.Contains(word)) {
      if (!dictionary.IsReferencedByLtm(word)) {
        problems.Add("word " + std::to_string(word) + " of LTM " + Name(id) +
                     " is in the dictionary but not marked as held by LTM");
      }
    } else if (!ltm.LoadWord(word)) {
      problems.Add("word " + std::to_string(word) + " of LTM " + Name(id) +
                   " is neither in the dictionary nor stored");
    }
  }
}

void CheckFilter(const Memory& memory, const BayesFilter& filter, Problems& problems) {
  for (const auto& [id, probability] : filter.posterior()) {
    if (!memory.InWorkingMemory(id))
      problems.Add("the filter has a state for " + Name(id) + ", which is not in WM");
    if (!(probability >= 0 && probability <= 1)) {
      problems.Add("p(S_t = " + std::to_string(id) + ") = " + std::to_string(probability));
    }
  }
  for (LocationId id : memory.working_memory()) {
    if (!filter.posterior().count(id)) problems.Add("WM " + Name(id) + " has no filter state");
  }
  if (!(filter.virtual_place() >= 0 && filter.virtual_place() <= 1)) {
    problems.Add("p(S_t = -1) = " + std::to_string(filter.virtual_place()));
  }
}

// Retrieval by appearance searches exactly the described LTM locations (locations of a map made
// before descriptions, or with retrieval by appearance off, have none).
void CheckAppearance(const Memory& memory, const LongTermMemory& ltm,
                     const AppearanceIndex& appearance, Problems& problems) {
  for (const auto& [id, location] : memory.locations()) {
    if (appearance.Searched(id)) problems.Add(Name(id) + " is in memory but searched in LTM");
  }
  size_t searched_in_ltm = 0;
  for (LocationId id : ltm.ids()) {
    if (appearance.Searched(id)) {
      ++searched_in_ltm;
    } else if (appearance.Find(id) != nullptr) {
      problems.Add("LTM " + Name(id) + " is described but not searched");
    }
  }
  if (searched_in_ltm != appearance.searched_size()) {
    problems.Add("the appearance index searches " + std::to_string(appearance.searched_size()) +
                 " locations, " + std::to_string(searched_in_ltm) + " of them in LTM");
  }
}

}  // namespace

std::vector<LocationId> LtmLocationsToCheck(const Memory& memory, const LongTermMemory& ltm,
                                            LtmCheck check, size_t newest) {
  const std::set<LocationId>& all = ltm.ids();
  if (check == LtmCheck::kEvery) return {all.begin(), all.end()};
  std::set<LocationId> chosen;
  for (const auto& [id, location] : memory.locations()) {
    for (const auto* links : {&location.neighbours, &location.loop_closures}) {
      for (LocationId other : *links) {
        if (all.count(other)) chosen.insert(other);
      }
    }
  }
  size_t taken = 0;
  for (auto id = all.rbegin(); id != all.rend() && taken < newest; ++id, ++taken) {
    chosen.insert(*id);
  }
  return {chosen.begin(), chosen.end()};
}

std::vector<std::string> CheckConsistency(const Memory& memory, LongTermMemory& ltm,
                                          const BayesFilter& filter,
                                          const std::vector<PastMatch>& past_matches,
                                          const AppearanceIndex* appearance, bool whole_image,
                                          size_t max_problems, LtmCheck ltm_check) {
  Problems problems(max_problems);
  for (const auto& [id, location] : memory.locations()) {
    if (location.signature.whole_image.empty() == whole_image) {
      problems.Add(Name(id) + (whole_image ? " has no" : " has a") + " whole-image descriptor");
    }
  }
  if (appearance != nullptr) CheckAppearance(memory, ltm, *appearance, problems);
  CheckMemory(memory, problems);
  CheckWords(memory, problems);
  CheckFilter(memory, filter, problems);
  for (const auto& [id, location] : memory.locations()) {
    if (problems.full()) break;
    CheckLinks(location, memory, ltm, problems);
  }
  for (LocationId id : LtmLocationsToCheck(memory, ltm, ltm_check)) {
    if (problems.full()) break;
    CheckLtmLocation(id, memory, ltm, problems);
  }
  for (const PastMatch& match : past_matches) {
    if (match.matched == match.matcher)
      problems.Add("a past match of " + Name(match.matched) + " with itself");
  }
  return problems.Take();
}

}  // namespace memloop
