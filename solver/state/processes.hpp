#pragma once
// The processes of a run: one, or several started by mpirun when pd-solve
// is built with MPI (docs/solver.md, "Running on several processes (MPI)").
// Callers never need to know whether MPI is built in: without it, or when
// pd-solve was not started by mpirun, there is one process of rank 0.
#include <memory>

#include "communicator.hpp"
#include "partition.hpp"

namespace pd::solver {

// MPI from construction to destruction when pd-solve was started by an MPI
// launcher (mpirun, mpiexec) and is built with MPI; nothing otherwise.
class ProcessSession {
public:
  ProcessSession(int& argc, char**& argv);
  ~ProcessSession();
  ProcessSession(const ProcessSession&) = delete;
  ProcessSession& operator=(const ProcessSession&) = delete;
  // Ends every process of the run with `code` (one failed process would
  // otherwise leave the others waiting in a collective call for ever).
  [[noreturn]] static void abort_all(int code);
};

int process_count();  // 1 without MPI
int process_rank();   // 0 without MPI

// The communicator of `partition` over all processes of the run (collective).
// pd::Error when pd-solve is built without MPI.
std::unique_ptr<Communicator> distributed_communicator(const Partition& partition);

}  // namespace pd::solver
