#include "detector/whole_image_likelihood.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include "features/whole_image_descriptor.h"

namespace memloop {

bool SeenBefore(const Location& location, ImageIndex before) {
  if (before == kNoImage) return true;
  const auto first = std::min_element(location.images.begin(), location.images.end());
  return first != location.images.end() && *first < before;
}

IdMap<double> ScoreWholeImage(const std::vector<uint8_t>& descriptor, const Memory& memory,
                              ImageIndex before) {
  IdMap<double> scores;
  scores.reserve(memory.working_memory().size());
  for (LocationId id : memory.working_memory()) {
    const Location& location = memory.at(id);
    if (!SeenBefore(location, before)) continue;
    scores.emplace_hint(scores.end(), id,
                        WholeImageSimilarity(descriptor, location.signature.whole_image));
  }
  return scores;
}

WholeImageLikelihood ComputeWholeImageLikelihood(const IdMap<double>& scores, double gain,
                                                 double min_z) {
  WholeImageLikelihood channel;
  channel.values.reserve(scores.size());
  const double count = static_cast<double>(scores.size());
  double sum = 0, squares = 0;
  for (const auto& [id, score] : scores) sum += score;
  if (count > 0) channel.mean = sum / count;
  for (const auto& [id, score] : scores) squares += (score - channel.mean) * (score - channel.mean);
  if (count > 0) channel.stddev = std::sqrt(squares / count);
  constexpr double kNoSpread = 1e-9;
  const bool weighed = scores.size() >= 2 && channel.stddev > kNoSpread && gain > 0;
  double values = 0;
  for (const auto& [id, score] : scores) {
    const double z = weighed ? (score - channel.mean) / channel.stddev : 0;
    const double value = z > min_z ? std::exp(gain * (z - min_z)) : 1.0;
    values += value;
    channel.z.emplace_hint(channel.z.end(), id, z);
    channel.values.emplace_hint(channel.values.end(), id, value);
  }
  channel.virtual_place = count > 0 ? values / count : 1.0;
  return channel;
}

void MultiplyLikelihood(WholeImageLikelihood channel, Likelihood& likelihood) {
  for (auto& [id, value] : likelihood.values) {
    const auto found = channel.values.find(id);
    if (found != channel.values.end()) value *= found->second;
  }
  likelihood.virtual_place *= channel.virtual_place;
  likelihood.whole_image_z = std::move(channel.z);
  likelihood.whole_image_values = std::move(channel.values);
}

double WordLikelihood(const Likelihood& likelihood, LocationId id) {
  const auto value = likelihood.values.find(id);
  if (value == likelihood.values.end()) return 0;
  const auto factor = likelihood.whole_image_values.find(id);
  return factor == likelihood.whole_image_values.end() ? value->second
                                                       : value->second / factor->second;
}

bool WordsRecognize(const Likelihood& likelihood, const Memory& memory, ImageIndex before,
                    double min_value) {
  if (min_value <= 0) return false;
  return std::any_of(likelihood.values.begin(), likelihood.values.end(), [&](const auto& entry) {
    return WordLikelihood(likelihood, entry.first) >= min_value &&
           SeenBefore(memory.at(entry.first), before);
  });
}

void WeighWholeImage(const std::vector<uint8_t>& descriptor, const Memory& memory,
                     const FilterOptions& options, ImageIndex before, Likelihood& likelihood) {
  if (WordsRecognize(likelihood, memory, before, options.whole_image_words_first)) return;
  MultiplyLikelihood(
      ComputeWholeImageLikelihood(ScoreWholeImage(descriptor, memory, before),
                                  options.whole_image_gain, options.whole_image_min_z),
      likelihood);
}

bool SupportedByWholeImage(const Likelihood& likelihood, LocationId id, double min_z) {
  if (min_z <= 0) return false;
  const auto z = likelihood.whole_image_z.find(id);
  return z != likelihood.whole_image_z.end() && z->second >= min_z;
}

}  // namespace memloop
