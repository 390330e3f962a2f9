#pragma once
// Ctrl-C (SIGINT) and SIGTERM during a dynamic run's time steps: the run
// finishes its step, writes a checkpoint and its progress files, and stops
// with an error that says where (docs/solver.md, "Interrupting a run"). A
// second signal ends the process at once. Elsewhere (set-up, quasi-static
// load steps) and on several processes the signals keep their default: they
// end the process, and a restart goes on from the last checkpoint.

namespace pd::solver {

// While it lives, SIGINT and SIGTERM are caught (on one process only; the
// processes of an MPI run would each see the signal at another step).
class CatchInterrupts {
public:
  explicit CatchInterrupts(bool one_process);
  ~CatchInterrupts();
  CatchInterrupts(const CatchInterrupts&) = delete;
  CatchInterrupts& operator=(const CatchInterrupts&) = delete;

private:
  bool installed_ = false;
  void (*previous_int_)(int) = nullptr;  // the handlers before, put back at the end
  void (*previous_term_)(int) = nullptr;
};

// 0 while no signal was caught; else the signal's number.
int interrupt_signal();
// "SIGINT", "SIGTERM".
const char* interrupt_name(int signal);

}  // namespace pd::solver
