#pragma once

#include <chrono>
#include <cstdio>
#include <string>

namespace memloop::cli {

// Feedback on long work. On a terminal (stderr), a one-line bar redrawn in place. Otherwise (a
// log file, a pipe), a whole line on stdout at every multiple of kLineEvery items and, in
// between, after kLineSeconds without one, so that a log never stays silent for long.
class Progress {
 public:
  static constexpr int kLineEvery = 500;
  static constexpr double kLineSeconds = 30;

  // `total`: items to do, or <= 0 when unknown (a camera, a video without a frame count).
  explicit Progress(int total, std::string unit = "images");
  ~Progress();
  // `loop_closures` < 0: not counted (writing images).
  void Update(int done, int loop_closures = -1);
  // A whole line on `stream` (stdout or stderr), above the bar.
  void Print(const std::string& line, std::FILE* stream);

 private:
  std::string Counts(int done, int loop_closures) const;

  int total_;
  std::string unit_;
  bool terminal_;
  bool drawn_ = false;
  int last_line_done_ = 0;
  std::chrono::steady_clock::time_point start_;
  std::chrono::steady_clock::time_point last_line_;
};

}  // namespace memloop::cli
