#include "detector/likelihood.h"

#include <algorithm>
#include <cmath>
#include <unordered_map>

namespace memloop {

IdMap<double> ScoreWorkingMemory(const Signature& z_t, const Memory& memory, size_t image_words) {
  if (image_words == 0) image_words = z_t.size();
  std::unordered_map<LocationId, int> pairs;
  for (const auto& [word, count] : z_t.Histogram()) {
    for (const auto& [location, occurrences] : memory.dictionary().References(word)) {
      if (memory.InWorkingMemory(location)) pairs[location] += std::min(count, occurrences);
    }
  }
  IdMap<double> scores;
  scores.reserve(memory.working_memory().size());
  for (LocationId id : memory.working_memory()) {
    const auto found = pairs.find(id);
    scores.emplace_hint(scores.end(), id,
                        found == pairs.end()
                            ? 0.0
                            : SimilarityFromPairs(found->second, static_cast<int>(image_words),
                                                  memory.at(id).signature.size()));
  }
  return scores;
}

IdMap<double> ScoreWorkingMemoryTfIdf(const Signature& z_t, const Memory& memory) {
  IdMap<double> scores;
  scores.reserve(memory.working_memory().size());
  for (LocationId id : memory.working_memory()) scores.emplace_hint(scores.end(), id, 0.0);
  const double locations = static_cast<double>(memory.size());  // N: STM and WM
  for (const auto& [word, count] : z_t.Histogram()) {
    const auto& references = memory.dictionary().References(word);
    if (references.empty()) continue;
    const double idf = std::log10(locations / static_cast<double>(references.size()));
    if (idf <= 0) continue;  // a word every location holds tells nothing
    for (const auto& [location, occurrences] : references) {
      const auto score = scores.find(location);
      if (score == scores.end()) continue;  // STM
      score->second += occurrences * idf / memory.at(location).signature.size();
    }
  }
  return scores;
}

Likelihood ComputeLikelihood(const IdMap<double>& scores, double min_sigma_ratio,
                             double no_signal_virtual_place) {
  Likelihood likelihood;
  likelihood.scores = scores;
  double sum = 0;
  int non_null = 0;
  for (const auto& [id, score] : scores) {
    if (score > 0) {
      sum += score;
      ++non_null;
    }
  }
  if (non_null > 0) {
    likelihood.mean = sum / non_null;
    double squares = 0;
    for (const auto& [id, score] : scores) {
      if (score > 0) squares += (score - likelihood.mean) * (score - likelihood.mean);
    }
    likelihood.stddev = std::sqrt(squares / non_null);
  }
  const double mu = likelihood.mean;
  // With one non-null score sigma says nothing (not a tie): only an estimable sigma is floored.
  const double sigma =
      non_null >= 2 ? std::max(likelihood.stddev, min_sigma_ratio * mu) : likelihood.stddev;
  likelihood.values.reserve(scores.size());
  bool stands_out = false;
  for (const auto& [id, score] : scores) {
    // Eq. 3. A non-null score with sigma = 0 equals mu, so (s - sigma) / mu = 1 too.
    const bool above = score > 0 && score >= mu + sigma;
    stands_out = stands_out || (above && sigma > 0);
    likelihood.values.emplace_hint(likelihood.values.end(), id, above ? (score - sigma) / mu : 1.0);
  }
  // Eq. 4; mu/sigma is taken as 1 where sigma cannot be estimated (fewer than 2 non-null scores)
  // or, as written (ratio 0), is 0.
  likelihood.virtual_place = (sigma > 0 ? mu / sigma : 1.0) + 1.0;
  constexpr double kSigmaEpsilon = 1e-4;  // the 2011 code's
  if (no_signal_virtual_place > 0 && (!stands_out || sigma <= kSigmaEpsilon)) {
    likelihood.virtual_place = no_signal_virtual_place;
  }
  return likelihood;
}

}  // namespace memloop
