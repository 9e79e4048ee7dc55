#include "detector/appearance_retrieval.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "memloop/errors.h"

namespace memloop {

double AppearanceMinZ(const MemoryOptions& options, size_t searched) {
  if (searched < 2) return options.appearance_min_z;
  const double chance_best = std::sqrt(2.0 * std::log(static_cast<double>(searched)));
  return std::max(options.appearance_min_z, options.appearance_chance_multiple * chance_best);
}

Appearance DescribeNewLocation(AppearanceIndex& appearance, LongTermMemory& ltm,
                               const Signature& signature, const cv::Mat& descriptors,
                               WordId first_new_word) {
  if (!appearance.frozen()) {
    std::vector<WordId> new_words;
    cv::Mat rows;
    for (size_t row = 0; row < signature.words.size(); ++row) {
      if (signature.words[row] < first_new_word) continue;
      new_words.push_back(signature.words[row]);
      rows.push_back(descriptors.row(static_cast<int>(row)));
    }
    const int first_entry = static_cast<int>(appearance.vocabulary_words().size());
    const int collected = appearance.CollectWords(new_words, rows);
    if (collected > 0) {
      const cv::Mat added = appearance.vocabulary().rowRange(first_entry, first_entry + collected);
      ltm.StoreAppearanceVocabulary(
          first_entry, std::vector<WordId>(new_words.begin(), new_words.begin() + collected),
          std::vector<unsigned char>(added.data, added.data + added.total() * added.elemSize()));
    }
  }
  return appearance.Describe(signature.words, descriptors);
}

void ReloadAppearance(LtmDatabase& database, const Memory& memory, const LongTermMemory& ltm,
                      AppearanceIndex& appearance) {
  const Dictionary& dictionary = memory.dictionary();
  std::vector<WordId> words;
  cv::Mat rows;
  for (const auto& [word, bytes] : database.ReadAppearanceVocabulary()) {
    cv::Mat row(1, dictionary.descriptor_dim(), dictionary.descriptor_cv_type());
    if (bytes.size() != row.total() * row.elemSize()) {
      throw DatabaseError(database.path(), "cannot resume: the appearance vocabulary is damaged");
    }
    std::copy(bytes.begin(), bytes.end(), row.data);
    words.push_back(word);
    rows.push_back(row);
  }
  try {
    appearance.Reload(words, rows);
    for (auto& [id, entries] : database.ReadAppearances()) {
      if (!memory.Contains(id) && !ltm.Contains(id)) continue;  // merged since
      appearance.Add(id, std::move(entries));
      if (ltm.Contains(id)) appearance.Enter(id);
    }
  } catch (const Error& error) {
    throw DatabaseError(database.path(), std::string("cannot resume: ") + error.what());
  }
}

}  // namespace memloop
