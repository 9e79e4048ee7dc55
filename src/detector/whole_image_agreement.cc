#include "detector/whole_image_agreement.h"

#include <algorithm>

namespace memloop {

void WholeImageAgreement::Observe(const Likelihood& likelihood, double min_z) {
  if (images_ <= 0) return;
  LocationId best = kNoLocation;
  double best_z = min_z;
  for (const auto& [id, z] : likelihood.whole_image_z) {
    if (z >= best_z) {
      best = id;
      best_z = z;
    }
  }
  bests_.push_back(best);
  while (static_cast<int>(bests_.size()) > images_) bests_.pop_front();
}

void WholeImageAgreement::Require(const Memory& memory, int range, Hypothesis& hypothesis) const {
  if (images_ <= 0 || !hypothesis.eligible) return;
  if (static_cast<int>(bests_.size()) < images_) return hypothesis.Refuse();
  const Neighbourhood near = memory.WmNeighbourhood(hypothesis.id, range);
  const auto in_reach = [&](LocationId id) {
    return std::any_of(near.begin(), near.end(),
                       [id](const auto& entry) { return entry.first == id; });
  };
  if (!std::all_of(bests_.begin(), bests_.end(), in_reach) ||
      std::all_of(bests_.begin(), bests_.end(),
                  [&](LocationId id) { return id == bests_.back(); })) {
    hypothesis.Refuse();
  }
}

}  // namespace memloop
