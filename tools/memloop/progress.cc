#include "progress.h"

#include <unistd.h>

#include <string>

namespace memloop::cli {

Progress::Progress(int total) : total_(total), enabled_(isatty(fileno(stderr)) != 0) {}

Progress::~Progress() {
  if (enabled_) std::fputc('\n', stderr);
}

void Progress::Update(int done, int loop_closures) {
  if (!enabled_) return;
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
