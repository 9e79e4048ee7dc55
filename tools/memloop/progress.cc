#include "progress.h"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

namespace memloop::cli {

Progress::Progress(int total, std::string unit)
    : total_(total),
      unit_(std::move(unit)),
      terminal_(isatty(fileno(stderr)) != 0),
      start_(std::chrono::steady_clock::now()),
      last_line_(start_) {}

Progress::~Progress() {
  if (drawn_) std::fputc('\n', stderr);
}

void Progress::Print(const std::string& line, std::FILE* stream) {
  if (drawn_) std::fputs("\r\033[K", stderr);  // clear the bar; the next Update draws it again
  std::fflush(stderr);
  std::fputs((line + "\n").c_str(), stream);
  std::fflush(stream);
}

std::string Progress::Counts(int done, int loop_closures) const {
  std::string text = std::to_string(done);
  if (total_ > 0) text += "/" + std::to_string(total_);
  text += " " + unit_;
  if (loop_closures >= 0) text += ", " + std::to_string(loop_closures) + " loop closures";
  return text;
}

void Progress::Update(int done, int loop_closures) {
  const auto now = std::chrono::steady_clock::now();
  if (!terminal_) {
    const double since_line = std::chrono::duration<double>(now - last_line_).count();
    // At every multiple of kLineEvery (so a log's lines do not depend on the machine's speed),
    // and in between after kLineSeconds.
    if (done / kLineEvery == last_line_done_ / kLineEvery && since_line < kLineSeconds) return;
    last_line_done_ = done;
    last_line_ = now;
    const double elapsed = std::chrono::duration<double>(now - start_).count();
    Print("progress: " + Counts(done, loop_closures) + " (" +
              std::to_string(static_cast<long long>(std::lround(elapsed))) + " s)",
          stdout);
    return;
  }
  drawn_ = true;
  constexpr int kWidth = 30;
  std::string bar;
  if (total_ > 0) {
    const int filled = std::min(done, total_) * kWidth / total_;
    bar = "[" + std::string(filled, '#') + std::string(kWidth - filled, ' ') + "] ";
  }
  std::fprintf(stderr, "\r%s%s", bar.c_str(), Counts(done, loop_closures).c_str());
  std::fflush(stderr);
}

}  // namespace memloop::cli
