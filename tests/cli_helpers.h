// Helpers for tests that run the memloop tool as a user does.
#pragma once

#include <sys/wait.h>

#include <cstdio>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>
#include <vector>

namespace memloop {

struct Outcome {
  int exit_code = -1;
  std::string output;  // stdout and stderr
};

inline Outcome Memloop(const std::string& arguments) {
  Outcome outcome;
  FILE* pipe = popen((std::string(MEMLOOP_CLI) + " " + arguments + " 2>&1").c_str(), "r");
  char buffer[4096];
  size_t read = 0;
  while ((read = fread(buffer, 1, sizeof(buffer), pipe)) > 0) outcome.output.append(buffer, read);
  const int status = pclose(pipe);
  outcome.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return outcome;
}

inline std::string ReadFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

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

}  // namespace memloop
