// Helpers for tests that run the memloop tool as a user does.
#pragma once

#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "temp_dir.h"

namespace memloop {

struct Outcome {
  int exit_code = -1;
  std::string output;  // stdout and stderr
};

// A shell command's exit code and output (stdout and stderr).
inline Outcome Shell(const std::string& command) {
  Outcome outcome;
  FILE* pipe = popen((command + " 2>&1").c_str(), "r");
  char buffer[4096];
  size_t read = 0;
  while ((read = fread(buffer, 1, sizeof(buffer), pipe)) > 0) outcome.output.append(buffer, read);
  const int status = pclose(pipe);
  outcome.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return outcome;
}

// `environment`: "NAME=value ..." set for the tool only.
inline Outcome MemloopWithEnvironment(const std::string& environment,
                                      const std::string& arguments) {
  return Shell(environment + " " + MEMLOOP_CLI + " " + arguments);
}

inline Outcome Memloop(const std::string& arguments) {
  return MemloopWithEnvironment("", arguments);
}

inline std::string ReadFile(const std::string& path) { return testing::ReadBytes(path); }

inline bool Contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

// A CSV without its timing columns (names ending in _ms), which vary from run to run.
inline std::string WithoutTimes(const std::string& csv) {
  std::istringstream in(csv);
  std::string line;
  std::getline(in, line);
  std::vector<bool> keep;
  std::string kept;
  std::stringstream header(line);
  for (std::string column; std::getline(header, column, ',');) {
    keep.push_back(column.size() < 3 || column.substr(column.size() - 3) != "_ms");
  }
  for (in.seekg(0); std::getline(in, line);) {
    std::stringstream row(line);
    size_t index = 0;
    for (std::string cell; std::getline(row, cell, ','); ++index) {
      if (index < keep.size() && keep[index]) kept += cell + ",";
    }
    kept += "\n";
  }
  return kept;
}

// Rows of a run CSV (its lines but the header).
inline int CsvRows(const std::string& path) {
  const std::string text = ReadFile(path);
  const int lines = static_cast<int>(std::count(text.begin(), text.end(), '\n'));
  return std::max(0, lines - 1);
}

// Rows of a run CSV's text with a loop closure (a matched image, the 4th column).
inline int RowsWithLoopClosure(const std::string& csv) {
  std::istringstream in(csv);
  std::string line;
  std::getline(in, line);
  int count = 0;
  while (std::getline(in, line)) {
    std::istringstream row(line);
    std::string cell;
    for (int column = 0; column < 4; ++column) std::getline(row, cell, ',');
    count += !cell.empty();
  }
  return count;
}

// Starts the tool with `arguments` (stdout and stderr to `log`, TMPDIR set to `temporary_folder`
// if given); returns its pid.
inline pid_t Start(const std::vector<std::string>& arguments, const std::string& log,
                   const std::string& temporary_folder = "") {
  const pid_t child = fork();
  if (child == 0) {
    if (!temporary_folder.empty()) setenv("TMPDIR", temporary_folder.c_str(), 1);
    if (freopen(log.c_str(), "w", stdout) == nullptr) _exit(126);
    dup2(fileno(stdout), fileno(stderr));
    std::vector<char*> argv = {const_cast<char*>(MEMLOOP_CLI)};
    for (const std::string& argument : arguments)
      argv.push_back(const_cast<char*>(argument.c_str()));
    argv.push_back(nullptr);
    execv(MEMLOOP_CLI, argv.data());
    _exit(127);
  }
  return child;
}

// Sends `signal` to `child` once `csv` has at least `rows` rows; returns its wait status. On a
// machine so busy that this thread sleeps through the rest of the run, the child exits first.
inline int SignalAfterRows(pid_t child, const std::string& csv, int rows, int signal) {
  int status = 0;
  while (waitpid(child, &status, WNOHANG) != child) {
    if (CsvRows(csv) >= rows) {
      kill(child, signal);
      waitpid(child, &status, 0);
      break;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  return status;
}

}  // namespace memloop
