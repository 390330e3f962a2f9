#pragma once
// Ctrl-C (SIGINT) and SIGTERM during a dynamic run: the run finishes its time
// step, writes a checkpoint and its progress files, and stops with an error
// that says where (docs/solver.md, "Interrupting a run"). A second signal
// ends the process at once. Runs on several processes keep the default
// (the signal ends them; their last interval's checkpoint stays).

namespace pd::solver {

// Installs the handlers (once; pd-solve on one process only).
void catch_interrupts();
// 0 while no signal came; else the signal's number.
int interrupt_signal();
// "SIGINT", "SIGTERM".
const char* interrupt_name(int signal);

}  // namespace pd::solver
