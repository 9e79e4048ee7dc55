#pragma once

#include <cstdio>

namespace memloop::cli {

// A one-line progress bar on stderr, drawn only when stderr is a terminal.
class Progress {
 public:
  explicit Progress(int total);
  ~Progress();
  void Update(int done, int loop_closures);

 private:
  int total_;
  bool enabled_;
};

}  // namespace memloop::cli
