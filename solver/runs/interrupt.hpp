#pragma once
// Ctrl-C (SIGINT) and SIGTERM during a dynamic run's time steps: the run
// finishes its step, writes a checkpoint and its progress files, and stops
// with an error that says where (docs/solver.md, "Interrupting a run");
// during a quasi-static run's load steps it stops after its load step, or
// within it (the step abandoned), with the checkpoint of the last completed
// one. A second signal ends the process at once. Elsewhere (set-up) the
// signals keep their default: they end the process, and a restart goes on
// from the last checkpoint.

namespace pd::solver {

// While it lives, SIGINT and SIGTERM are caught. The processes of an MPI
// run each see the signal at another step (mpirun and batch systems send
// SIGTERM to every process): the run loop agrees on it (the largest signal
// number over the processes) before it stops.
class CatchInterrupts {
public:
  CatchInterrupts();
  ~CatchInterrupts();
  CatchInterrupts(const CatchInterrupts&) = delete;
  CatchInterrupts& operator=(const CatchInterrupts&) = delete;

private:
  void (*previous_int_)(int) = nullptr;  // the handlers before, put back at the end
  void (*previous_term_)(int) = nullptr;
};

// 0 while no signal was caught; else the signal's number.
int interrupt_signal();
// "SIGINT", "SIGTERM".
const char* interrupt_name(int signal);

}  // namespace pd::solver
