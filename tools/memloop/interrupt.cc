#include "interrupt.h"

#include <csignal>

namespace memloop::cli {
namespace {

volatile std::sig_atomic_t received = 0;

void Record(int signal) { received = signal; }

struct sigaction previous_int {};
struct sigaction previous_term {};

}  // namespace

InterruptWatch::InterruptWatch() {
  received = 0;
  struct sigaction action {};
  action.sa_handler = Record;
  sigemptyset(&action.sa_mask);
  // SA_RESTART: SQLite's and the image readers' system calls go on; SA_RESETHAND: a second signal
  // takes the default action.
  action.sa_flags = SA_RESTART | SA_RESETHAND;
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
