// SIGINT / SIGTERM during a run: the current image is finished, the map closed and the CSV
// completed, then memloop exits 128 + the signal (130 for Ctrl-C, 143 for SIGTERM).
#pragma once

#include <stdexcept>
#include <string>

namespace memloop::cli {

// While alive, SIGINT and SIGTERM only set a flag, read between images. A second signal of the
// same kind acts as usual (stops at once), for a run that will not come to an end.
class InterruptWatch {
 public:
  InterruptWatch();
  ~InterruptWatch();
  InterruptWatch(const InterruptWatch&) = delete;
  InterruptWatch& operator=(const InterruptWatch&) = delete;

  // The signal received, 0 if none.
  int signal() const;
};

// Thrown once an interrupted run has closed everything; main exits 128 + signal().
class Interrupted : public std::runtime_error {
 public:
  Interrupted(int signal, const std::string& message)
      : std::runtime_error(message), signal_(signal) {}
  int signal() const { return signal_; }

 private:
  int signal_;
};

// "SIGINT", "SIGTERM".
std::string SignalName(int signal);

}  // namespace memloop::cli
