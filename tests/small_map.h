// Helpers for unit tests: the whole map (memory, LTM in a temporary file, filter and the editor
// that keeps them in agreement) around a Memory whose words are 2-D points (small_memory.h).
#pragma once

#include <gtest/gtest.h>

#include "detector/bayes_filter.h"
#include "detector/consistency.h"
#include "detector/map_editor.h"
#include "detector/transfer.h"
#include "small_memory.h"
#include "storage/long_term_memory.h"
#include "temp_dir.h"

namespace memloop::testing {

struct SmallMap {
  explicit SmallMap(const LtmOptions& ltm_options = {})
      : memory(DescriptorKind::kFloat, 2, SmallDictionaryOptions()),
        ltm(dir.File("map.db"), LtmDatabase::Mode::kCreate, ltm_options),
        filter(FilterOptions()),
        editor(memory, ltm, filter) {}

  // Chains added by hand never went through a filter update: WM locations get the state (0)
  // the detector gives a location entering WM, then the whole map is checked.
  bool CheckConsistencyEmpty() {
    for (LocationId id : memory.working_memory()) filter.Add(id);
    const std::vector<std::string> problems =
        CheckConsistency(memory, ltm, filter, editor.past_matches());
    for (const std::string& line : problems) ADD_FAILURE() << line;
    return problems.empty();
  }

  // A chain L1 .. L5 of `words` (AddChain) whose L2, L3 and L4 are then transferred to LTM (a WM
  // budget of 2; L1 the heaviest, L5 immune): the five ids.
  std::vector<LocationId> ChainWithMiddleInLtm(const std::vector<std::vector<WordId>>& words) {
    const std::vector<LocationId> ids = AddChain(memory, words);
    memory.MoveStmOverflowToWm(0);
    memory.at(ids[0]).weight = 5;
    TransferTrigger trigger;
    trigger.max_wm_locations = 2;
    trigger.dictionary_size_at_start = memory.dictionary().size();
    Transfer(trigger, {ids[4]}, {}, memory, editor);
    return ids;
  }

  TempDir dir;
  Memory memory;
  LongTermMemory ltm;
  BayesFilter filter;
  MapEditor editor;
};

}  // namespace memloop::testing
