// What a refused command must leave as it was (a folder's files and their bytes), and the means
// to make what it refuses (a map edited by another tool, a read-only folder).
#pragma once

#include <gtest/gtest.h>
#include <sqlite3.h>

#include <cstdlib>
#include <filesystem>
#include <functional>
#include <map>
#include <optional>
#include <sstream>
#include <string>

#include "cli_helpers.h"

namespace memloop {

// Every file of a folder (recursively) with its bytes: compared before and after a refusal.
inline std::map<std::string, std::string> FolderState(const std::string& folder) {
  std::map<std::string, std::string> state;
  for (const auto& entry : std::filesystem::recursive_directory_iterator(folder)) {
    std::error_code error;  // a looping symlink has no type
    if (entry.is_regular_file(error))
      state[entry.path().string()] = ReadFile(entry.path().string());
  }
  return state;
}

// The files that differ between two states, by name: for a readable failure message.
inline std::string Differences(const std::map<std::string, std::string>& before,
                               const std::map<std::string, std::string>& after) {
  std::string text;
  for (const auto& [path, bytes] : after) {
    const auto old = before.find(path);
    if (old == before.end())
      text += " created " + path;
    else if (old->second != bytes)
      text += " changed " + path;
  }
  for (const auto& [path, bytes] : before) {
    if (!after.count(path)) text += " removed " + path;
  }
  return text;
}

// Lines of a refusal's output, CLI11's "Run with --help" hint after a usage error aside.
inline int MessageLines(const std::string& output) {
  std::istringstream in(output);
  int count = 0;
  for (std::string line; std::getline(in, line);) {
    count += !line.empty() && !Contains(line, "Run with --help");
  }
  return count;
}

// `arguments` run with `folder` mounted read-only, in a mount namespace of their own (needs
// the privilege to mount: none when unshare is refused).
inline std::optional<Outcome> MemloopWithFolderReadOnly(const std::string& folder,
                                                        const std::string& arguments) {
  const std::string mount = "mount --bind " + folder + " " + folder +
                            " && mount -o remount,ro,bind " + folder + " " + folder;
  if (std::system(("unshare -m sh -c '" + mount + "' >/dev/null 2>&1").c_str()) != 0) {
    return std::nullopt;
  }
  return MemloopWithEnvironment("unshare -m sh -c '" + mount + " && exec \"$0\" \"$@\"'",
                                arguments);
}

// Runs `sql` on a map (a copy, for a test's damaged map), as a tool that edits the file would.
inline void Edit(const std::string& path, const std::string& sql) {
  sqlite3* db = nullptr;
  ASSERT_EQ(sqlite3_open(path.c_str(), &db), SQLITE_OK);
  char* message = nullptr;
  EXPECT_EQ(sqlite3_exec(db, sql.c_str(), nullptr, nullptr, &message), SQLITE_OK)
      << (message ? message : "");
  sqlite3_free(message);
  sqlite3_close(db);
}

// Runs `sql` on `map` through a connection that folds nothing into the file, then `while_open`
// while that connection still holds the map's -wal with content, as a killed run leaves it.
inline void WithALog(const std::string& map, const std::string& sql,
                     const std::function<void()>& while_open) {
  sqlite3* writer = nullptr;
  ASSERT_EQ(sqlite3_open(map.c_str(), &writer), SQLITE_OK);
  ASSERT_EQ(sqlite3_exec(writer, ("PRAGMA wal_autocheckpoint=0; " + sql).c_str(), nullptr, nullptr,
                         nullptr),
            SQLITE_OK);
  while_open();
  sqlite3_close(writer);
}

}  // namespace memloop
