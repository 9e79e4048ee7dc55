#include "interrupt.h"

#include <unistd.h>

#include <csignal>

namespace memloop::cli {
namespace {

volatile std::sig_atomic_t received = 0;

// The first signal ends the run after the current image; a second one ends the process now,
// saying so (the map is as a kill leaves it: it resumes from its last checkpoint).
void Record(int signal) {
  if (received == 0) {
    received = signal;
    static const char kFirst[] =
        "memloop: stopping after the current image (a second signal stops at once)\n";
    [[maybe_unused]] const ssize_t wrote = write(STDERR_FILENO, kFirst, sizeof(kFirst) - 1);
    return;
  }
  static const char kLine[] =
      "memloop: a second signal: stopping now; the map goes on from its last checkpoint with "
      "--resume\n";
  [[maybe_unused]] const ssize_t wrote = write(STDERR_FILENO, kLine, sizeof(kLine) - 1);
  _exit(128 + signal);
}

struct sigaction previous_int {};
struct sigaction previous_term {};

}  // namespace

InterruptWatch::InterruptWatch() {
  received = 0;
  struct sigaction action {};
  action.sa_handler = Record;
  sigemptyset(&action.sa_mask);
  // SA_RESTART: SQLite's and the image readers' system calls go on.
  action.sa_flags = SA_RESTART;
  sigaction(SIGINT, &action, &previous_int);
  sigaction(SIGTERM, &action, &previous_term);
}

InterruptWatch::~InterruptWatch() {
  sigaction(SIGINT, &previous_int, nullptr);
  sigaction(SIGTERM, &previous_term, nullptr);
}

int InterruptWatch::signal() const { return received; }

std::string SignalName(int signal) {
  switch (signal) {
    case SIGINT:
      return "SIGINT";
    case SIGTERM:
      return "SIGTERM";
    default:
      return "signal " + std::to_string(signal);
  }
}

}  // namespace memloop::cli
