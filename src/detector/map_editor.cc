#include "detector/map_editor.h"

#include <algorithm>

namespace memloop {

MapEditor::MapEditor(Memory& memory, LongTermMemory& ltm, BayesFilter& filter,
                     AppearanceIndex* appearance)
    : memory_(memory), ltm_(ltm), filter_(filter), appearance_(appearance) {}

void MapEditor::ReleaseWords(const std::vector<WordId>& orphans) {
  Dictionary& dictionary = memory_.dictionary();
  for (WordId word : orphans) {
    if (dictionary.IsReferencedByLtm(word)) ltm_.StoreWord(word, dictionary.Descriptor(word));
    dictionary.Remove(word);
  }
}

void MapEditor::LinkLoopClosure(LocationId t, LocationId i, bool absorbed) {
  for (const LinkToLtm& link : memory_.AddLinksOf(t, i, /*link_together=*/true)) {
    ltm_.AddLink(link.ltm_location, t, link.loop_closure);
  }
  if (absorbed) past_matches_.push_back({i, t});
}

void MapEditor::ReplaceSignature(LocationId id, Signature signature) {
  ReleaseWords(memory_.ReplaceSignature(id, std::move(signature)));
}

void MapEditor::Merge(LocationId survivor, LocationId absorbed) {
  // Links of `absorbed` to LTM locations: the survivor gets them here, and the LTM side is
  // redirected to the survivor below, so no link is written twice.
  const std::vector<LocationId> linked = memory_.at(absorbed).Links();
  ReleaseWords(memory_.Absorb(survivor, absorbed));
  ltm_.RedirectLocation(absorbed, survivor, linked);
  filter_.Remove(absorbed);
  if (appearance_ != nullptr) appearance_->Erase(absorbed);
  for (PastMatch& match : past_matches_) {
    if (match.matcher == absorbed) match.matcher = survivor;
    if (match.matched == absorbed || match.matched == match.matcher) match.matched = kNoLocation;
  }
}

void MapEditor::AbsorbPastMatches(const std::set<LocationId>& keep) {
  for (size_t k = 0; k < past_matches_.size(); ++k) {
    const PastMatch match = past_matches_[k];
    if (match.matched == kNoLocation) continue;
    if (!memory_.InWorkingMemory(match.matched) || !memory_.Contains(match.matcher)) {
      past_matches_[k].matched = kNoLocation;
      continue;
    }
    if (keep.count(match.matched)) continue;
    Merge(match.matcher, match.matched);  // marks this entry (and any other of L_i) done
  }
  past_matches_.erase(std::remove_if(past_matches_.begin(), past_matches_.end(),
                                     [](const PastMatch& m) { return m.matched == kNoLocation; }),
                      past_matches_.end());
}

void MapEditor::TransferToLtm(LocationId id) {
  std::vector<WordId> orphans;
  Location location = memory_.Release(id, &orphans);
  for (WordId word : location.signature.words) memory_.dictionary().MarkReferencedByLtm(word);
  ReleaseWords(orphans);
  ltm_.Store(location);
  filter_.Remove(id);
  if (appearance_ != nullptr) appearance_->Enter(id);
}

}  // namespace memloop
