// The CSV files memloop reads (run CSVs, a fleet's pairs): one line's fields.
#pragma once

#include <string>
#include <vector>

namespace memloop {

// Splits one CSV line; fields may be quoted ("a,b" and "" for a quote inside).
std::vector<std::string> SplitCsvLine(const std::string& line);

}  // namespace memloop
