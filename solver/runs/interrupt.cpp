#include "interrupt.hpp"

#include <csignal>

namespace pd::solver {
namespace {

volatile std::sig_atomic_t received = 0;

extern "C" void on_interrupt(int signal) {
  received = signal;
  // The next one ends the process (the default, not the handler before ours).
  std::signal(signal, SIG_DFL);
}

}  // namespace

CatchInterrupts::CatchInterrupts() {
  received = 0;
  previous_int_ = std::signal(SIGINT, on_interrupt);
  previous_term_ = std::signal(SIGTERM, on_interrupt);
}

CatchInterrupts::~CatchInterrupts() {
  std::signal(SIGINT, previous_int_ == SIG_ERR ? SIG_DFL : previous_int_);
  std::signal(SIGTERM, previous_term_ == SIG_ERR ? SIG_DFL : previous_term_);
}

int interrupt_signal() { return received; }

const char* interrupt_name(int signal) {
  return signal == SIGINT ? "SIGINT" : signal == SIGTERM ? "SIGTERM" : "a signal";
}

}  // namespace pd::solver
