#pragma once

#include <cstdio>
#include <string>

namespace memloop::cli {

// A one-line progress bar on stderr, drawn only when stderr is a terminal.
class Progress {
 public:
  explicit Progress(int total);
  ~Progress();
  void Update(int done, int loop_closures);
  // A whole line on `stream` (stdout or stderr), above the bar.
  void Print(const std::string& line, std::FILE* stream);

 private:
  int total_;
  bool enabled_;
  bool drawn_ = false;
};

}  // namespace memloop::cli
