#include "progress.h"

#include <unistd.h>

#include <string>

namespace memloop::cli {

Progress::Progress(int total) : total_(total), enabled_(isatty(fileno(stderr)) != 0) {}

Progress::~Progress() {
  if (drawn_) std::fputc('\n', stderr);
}

void Progress::Print(const std::string& line, std::FILE* stream) {
  if (drawn_) std::fputs("\r\033[K", stderr);  // clear the bar; the next Update draws it again
  std::fflush(stderr);
  std::fputs((line + "\n").c_str(), stream);
  std::fflush(stream);
}

void Progress::Update(int done, int loop_closures) {
  if (!enabled_) return;
  drawn_ = true;
  constexpr int kWidth = 30;
  if (total_ > 0) {
    const int filled = done * kWidth / total_;
    std::fprintf(stderr, "\r[%s%s] %d/%d images, %d loop closures",
                 std::string(filled, '#').c_str(), std::string(kWidth - filled, ' ').c_str(), done,
                 total_, loop_closures);
  } else {
    std::fprintf(stderr, "\r%d images, %d loop closures", done, loop_closures);
  }
  std::fflush(stderr);
}

}  // namespace memloop::cli
