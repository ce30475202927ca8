// Signal handling for graceful stops.
#include "host/run/interrupt.h"

#include <atomic>
#include <csignal>
#include <cstdlib>

namespace romp::run {
namespace {

std::atomic<bool> requested{false};

extern "C" void on_signal(int signal) {
  if (requested.exchange(true)) std::_Exit(128 + signal);
}

}  // namespace

void install_interrupt_handler() {
  std::signal(SIGINT, on_signal);
  std::signal(SIGTERM, on_signal);
}

bool interrupt_requested() { return requested.load(); }

}  // namespace romp::run
