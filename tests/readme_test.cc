// The README's quick start runs as written from a fresh clone: each command of its first `sh`
// block after "## Quick start" is run (./build/memloop as built here, /tmp/ as a folder of the
// test's own) and must succeed, so the README cannot drift from the tool.
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "cli_helpers.h"
#include "memloop/run_csv.h"
#include "temp_dir.h"

namespace memloop {
namespace {

std::string Replaced(std::string text, const std::string& from, const std::string& to) {
  for (size_t at = text.find(from); at != std::string::npos; at = text.find(from, at + to.size()))
    text.replace(at, from.size(), to);
  return text;
}

// The commands of the first ```sh block after `heading`: continuation lines joined, comments
// (lines from "#", the rest of a line from "  #") cut.
std::vector<std::string> QuickStartCommands(const std::string& readme, const std::string& heading) {
  std::istringstream in(readme.substr(readme.find(heading)));
  std::vector<std::string> commands;
  std::string line;
  while (std::getline(in, line) && line != "```sh") {
  }
  std::string command;
  while (std::getline(in, line) && line != "```") {
    if (line.rfind("#", 0) == 0) continue;  // a comment line
    const size_t comment = line.find("  #");
    if (comment != std::string::npos) line = line.substr(0, comment);
    while (!line.empty() && line.back() == ' ') line.pop_back();
    const bool continues = !line.empty() && line.back() == '\\';
    command += continues ? line.substr(0, line.size() - 1) : line;
    if (!continues && !command.empty()) commands.push_back(command), command.clear();
  }
  return commands;
}

// Runs the commands of the README's block after `heading` in `dir` (for /tmp/).
void RunBlock(const std::string& heading, size_t min_commands, const testing::TempDir& dir) {
  const std::string readme = testing::ReadBytes(std::string(MEMLOOP_SOURCE_DIR) + "/README.md");
  ASSERT_NE(readme.find(heading), std::string::npos) << heading;
  const std::vector<std::string> commands = QuickStartCommands(readme, heading);
  ASSERT_GE(commands.size(), min_commands) << heading << " lost its commands";
  for (const std::string& written : commands) {
    ASSERT_EQ(written.rfind("./build/memloop ", 0), 0u) << "not a memloop command: " << written;
    const std::string command = Replaced(Replaced(written, "/tmp/", dir.path().string() + "/"),
                                         "./build/memloop", MEMLOOP_CLI);
    const int status = std::system((command + " > " + dir.File("out.txt") + " 2>&1").c_str());
    EXPECT_EQ(status, 0) << written << "\n" << ReadFile(dir.File("out.txt"));
  }
}

TEST(ReadmeTest, QuickStartCommandsRunAsWritten) {
  testing::TempDir dir;
  RunBlock("## Quick start", 5, dir);
  EXPECT_TRUE(Contains(ReadFile(dir.File("report.html")), "loop-closures"));
}

TEST(ReadmeTest, RobotDataCommandsRunAsWritten) {
  testing::TempDir dir;
  RunBlock("## Robot data", 5, dir);
  EXPECT_TRUE(Contains(ReadFile(dir.File("out.txt")), "exported "));  // the last command
  EXPECT_TRUE(Contains(ReadFile(dir.File("loops.g2o")), "\nEDGE_SE3:QUAT "));
  const std::vector<RunRow> rows = ReadRunCsv(dir.File("again.csv"));
  EXPECT_TRUE(std::any_of(rows.begin(), rows.end(),
                          [](const RunRow& row) { return row.session == 1; }));  // session 1's
}

}  // namespace
}  // namespace memloop
