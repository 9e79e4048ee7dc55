// A map file's integrity on opening: SQLite's quick_check (every page of every table and index is
// read), once per file and process while the file stays unchanged.
#pragma once

#include <string>

#include "storage/sqlite_statement.h"

namespace memloop {

// Empty when the map at `path`, open through `connection`, passes SQLite's quick_check; else the
// first problem and how many there are. A file this process found intact, unchanged since (same
// inode, size and modification time, its write-ahead log's too), is not read whole again.
std::string MapIntegrityProblems(SqliteConnection& connection, const std::string& path);

// How many checks this process has run (tests).
long long MapIntegrityChecksRun();

}  // namespace memloop
