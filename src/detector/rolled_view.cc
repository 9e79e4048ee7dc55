#include "detector/rolled_view.h"

#include "detector/likelihood.h"

namespace memloop {

void RolledView::Observe(const Features& features, const Dictionary& dictionary) {
  raised_.clear();
  present_ = !features.rolled_descriptors.empty();
  if (!present_) {
    view_ = Signature();
    return;
  }
  view_ = MatchSignature(Features{features.keypoints, features.rolled_descriptors, {}}, dictionary);
}

void RolledView::Raise(const Memory& memory, size_t image_words, IdMap<double>& scores) {
  raised_.clear();
  if (!present_ || view_.words.empty()) return;
  const IdMap<double> rolled = ScoreWorkingMemory(view_, memory, image_words);
  for (auto& [id, score] : scores) {
    const auto found = rolled.find(id);
    if (found == rolled.end() || found->second <= score) continue;
    score = found->second;
    raised_.insert(id);
  }
}

const Signature& RolledView::ViewOf(LocationId id, const Signature& z_t) const {
  return raised_.count(id) != 0 ? view_ : z_t;
}

}  // namespace memloop
