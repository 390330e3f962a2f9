#pragma once
// The processes of a run: one, or several started by mpirun when pd-solve
// is built with MPI (docs/solver.md, "Running on several processes (MPI)").
// Callers never need to know whether MPI is built in: without it, or when
// pd-solve was not started by mpirun, there is one process of rank 0.
#include <exception>
#include <functional>
#include <memory>
#include <string>

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
// The processes of the run on this process's machine (those sharing its
// memory: MPI_Comm_split_type, MPI_COMM_TYPE_SHARED, whatever the launcher);
// 1 without MPI. Counted once, as MPI starts, so not collective.
int processes_on_this_machine();

// Errors on several processes: a failure should be reported once, by the
// process that saw it. Thrown on a process whose part went well, or whose
// error another process reports (the caller exits non-zero without a message).
struct ReportedByAnotherProcess : std::exception {
  const char* what() const noexcept override { return "the error is reported by another process"; }
};

// Runs `step` on every process and agrees on its outcome (collective; `step`
// itself must make no collective call, or a process that failed before it
// would leave the others waiting there). If it failed on every process (the
// same input read by all: a bad scene key, a refused table), the root
// throws its error and the others ReportedByAnotherProcess, so that the
// message appears once; if on some processes only, each of them throws its
// error with its rank named ("process 1 of 2: ...") and the others
// ReportedByAnotherProcess. On one process: step() as it is.
void on_every_process(const std::function<void()>& step);
// Runs `step` on the root alone, for what one process does for the whole run
// (the output folder's lock), and agrees on its outcome (collective): its
// error is printed once, by the root, without a rank.
void on_the_root(const std::function<void()>& step);
// Runs `write` on every process, for a file the processes gather onto the
// root and the root alone writes (snapshots, arrival.vtp, a checkpoint,
// summary.json: `write` may make collective calls, which every process
// makes), and agrees on the root's outcome (collective): a write that
// failed on the root (a full disk, a folder removed or replaced by a file
// during the run) is printed once, by the root, without a rank, and every
// process ends with status 1 (before 7 December 2026 the root said it with
// its rank and MPI_Abort ended the others). An error of another process is
// its own, as any other.
void written_by_the_root(const std::function<void()>& write);
// Whether every process knows of the run's failure (on_every_process
// failed): then they all exit by themselves, and nobody needs abort_all.
bool failure_known_to_all();
// `message` naming this process ("process 1 of 2: message") on several processes.
std::string with_process_rank(const std::string& message);

// The communicator of `partition` over all processes of the run (collective).
// pd::Error when pd-solve is built without MPI.
std::unique_ptr<Communicator> distributed_communicator(const Partition& partition);

}  // namespace pd::solver
