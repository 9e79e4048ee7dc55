// The rule of every command that writes: an output is never one of the command's inputs nor
// another of its outputs, however it is spelled (relative, absolute, "..", a symlink, a hard
// link), and a whole file is written beside its target and renamed into place, so that a failure
// (a full disk, a kill) leaves the old file or none, never a partial or empty one.
#pragma once

#include <functional>
#include <string>
#include <vector>

namespace memloop {

// A path a command was given, and what it is to the command ("the map (--db)", "--out").
struct NamedPath {
  std::string role;
  std::string path;
  // An input folder whose every file is read (a plain folder of images): a file written into it
  // would be read as an input next time, so an output inside it counts as an input.
  bool every_file_read = false;
};

// Throws InputError naming the output and the input (or the other output) it resolves to, before
// anything is opened for writing. Outputs that do not exist yet compare by their resolved paths
// (their folders' symlinks and dangling symlinks followed); existing ones by device and inode.
void CheckOutputsAreNotInputs(const std::vector<NamedPath>& inputs,
                              const std::vector<NamedPath>& outputs);

// Writes `path` whole: `write` fills a new file beside it (same folder, same extension, so that
// writers that choose a format by extension work), which is flushed to disk and renamed over
// `path`. On any failure the new file is removed, `path` keeps what it held, and InputError names
// `path`, `what` ("the export file") and the system's reason. A `path` that is a device (e.g.
// /dev/stdout) is written directly. `sync` false: not flushed to disk before the rename (many
// files written at once, each of which a kill still leaves whole or absent).
void WriteWholeFile(const std::string& path, const std::string& what,
                    const std::function<void(const std::string& temporary_path)>& write,
                    bool sync = true);
// The same for text.
void WriteWholeFile(const std::string& path, const std::string& what, const std::string& text);

}  // namespace memloop
