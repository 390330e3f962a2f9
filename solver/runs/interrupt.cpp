#include "interrupt.hpp"

#include <csignal>

namespace pd::solver {
namespace {

volatile std::sig_atomic_t received = 0;

extern "C" void on_interrupt(int signal) {
  received = signal;
  // The next one ends the process as it would have without the handler.
  std::signal(signal, SIG_DFL);
}

}  // namespace

void catch_interrupts() {
  std::signal(SIGINT, on_interrupt);
  std::signal(SIGTERM, on_interrupt);
}

int interrupt_signal() { return received; }

const char* interrupt_name(int signal) { return signal == SIGINT ? "SIGINT" : signal == SIGTERM ? "SIGTERM" : "a signal"; }

}  // namespace pd::solver
