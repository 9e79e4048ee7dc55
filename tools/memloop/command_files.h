// What each command reads and writes, named for the rule that an output is never an input
// (src/util/output_files.h).
#pragma once

#include <string>
#include <vector>

#include "memloop/image_sequence.h"
#include "util/output_files.h"

namespace memloop::cli {

// What `memloop run` reads of `input` ("" for a camera): a plain folder (every file of it is
// read), a dataset folder's listing and images, a ROS 2 bag folder, or one file.
std::vector<NamedPath> RunInputs(const std::string& input, const SequenceOptions& options);

// A map file and the files beside it that are part of it: SQLite's -wal and -shm, memloop's
// -lock (map_writer_lock.h). `role` names it ("the map (--db)").
std::vector<NamedPath> MapFiles(const std::string& path, const std::string& role);

// A file an option names, "" giving none.
std::vector<NamedPath> FileIfGiven(const std::string& path, const std::string& role);

}  // namespace memloop::cli
