// The parameters a map was made with (its info table), and the check that a resumed or localized
// run uses the same values of those that define the map.
#pragma once

#include "memloop/options.h"
#include "storage/ltm_database.h"

namespace memloop {

// The options stored in the map; a parameter newer than the map keeps its default.
Options OptionsOf(LtmDatabase& database);

// Resuming (or localizing) with other values of the parameters that define the map is refused,
// naming each (ParameterError).
void CheckMapParameters(LtmDatabase& database, const Options& options);

}  // namespace memloop
