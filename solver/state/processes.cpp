#include "processes.hpp"

#include <algorithm>
#include <cstdlib>
#include <iostream>

#include "error.hpp"

#ifdef PD_WITH_MPI
#include <mpi.h>

#include "mpi_communicator.hpp"
#endif

namespace pd::solver {

#ifdef PD_WITH_MPI
namespace {
// Open MPI's launcher (OMPI_*) and the PMI/PMIx process managers set these
// in every process they start; a plain `pd-solve` never initialises MPI.
bool started_by_mpi_launcher() {
  for (const char* variable : {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_RANK"})
    if (std::getenv(variable)) return true;
  return false;
}
int machine_processes = 1;  // processes_on_this_machine, counted as MPI starts
bool mpi_running() {
  int initialised = 0, finalised = 0;
  MPI_Initialized(&initialised);
  MPI_Finalized(&finalised);
  return initialised && !finalised;
}
}  // namespace

ProcessSession::ProcessSession(int& argc, char**& argv) {
  if (!started_by_mpi_launcher()) return;
  // Only the main thread calls MPI (OpenMP threads work between the calls; inside
  // a parallel region the team's master, which is the main thread: lattice_sweep.hpp).
  int provided = 0;
  MPI_Init_thread(&argc, &argv, MPI_THREAD_FUNNELED, &provided);
  // The processes that share this machine's memory, whatever launcher
  // started them (before 7 December 2026 Open MPI's OMPI_COMM_WORLD_LOCAL_SIZE
  // alone: MPICH's processes counted as one each, and took every hardware thread).
  MPI_Comm shared = MPI_COMM_NULL;
  if (MPI_Comm_split_type(MPI_COMM_WORLD, MPI_COMM_TYPE_SHARED, 0, MPI_INFO_NULL, &shared) == MPI_SUCCESS &&
      shared != MPI_COMM_NULL) {
    MPI_Comm_size(shared, &machine_processes);
    MPI_Comm_free(&shared);
  }
}
ProcessSession::~ProcessSession() {
  if (mpi_running()) MPI_Finalize();
}
void ProcessSession::abort_all(int code) {
  if (mpi_running()) MPI_Abort(MPI_COMM_WORLD, code);
  std::exit(code);
}
int process_count() {
  if (!mpi_running()) return 1;
  int size = 1;
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  return size;
}
int process_rank() {
  if (!mpi_running()) return 0;
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  return rank;
}
int processes_on_this_machine() { return mpi_running() ? std::max(machine_processes, 1) : 1; }
std::unique_ptr<Communicator> distributed_communicator(const Partition& partition) {
  return std::make_unique<MpiCommunicator>(MPI_COMM_WORLD, partition);
}
namespace {
bool failure_agreed = false;
// How many processes failed (an MPI_Allreduce of `failed`).
int failed_processes(bool failed) {
  int mine = failed ? 1 : 0, all = 0;
  MPI_Allreduce(&mine, &all, 1, MPI_INT, MPI_SUM, MPI_COMM_WORLD);
  return all;
}
// Who runs a step, and whose outcome is agreed on.
enum class Agreed {
  every_process,  // all run it; any may fail
  root_only,      // the root alone runs it
  root_writes,    // all run it (its collective calls), the root alone may fail
};
// `step` run as `who` says, and the outcome agreed. An error that concerns
// the whole run (every process failed, or the root alone ran the step or
// wrote its file) is the root's to print, without a rank.
void agree_on(const std::function<void()>& step, Agreed who) {
  const bool root_only = who != Agreed::every_process;
  std::exception_ptr failure;
  try {
    if (who != Agreed::root_only || process_rank() == 0) step();
  } catch (const std::exception&) {
    // (Another process's error in a write the root makes: its own, as any other.)
    if (who == Agreed::root_writes && process_rank() != 0) throw;
    failure = std::current_exception();
  }
  if (process_count() == 1) {
    if (failure) std::rethrow_exception(failure);
    return;
  }
  const int failed = failed_processes(failure != nullptr);
  if (failed == 0) return;
  failure_agreed = true;
  const bool whole_run = root_only || failed == process_count();
  if (!failure || (whole_run && process_rank() != 0)) throw ReportedByAnotherProcess();
  if (whole_run) std::rethrow_exception(failure);  // the root, for all
  try {
    std::rethrow_exception(failure);
  } catch (const std::exception& e) {
    throw Error(with_process_rank(e.what()));
  }
}
}  // namespace
void on_every_process(const std::function<void()>& step) { agree_on(step, Agreed::every_process); }
void on_the_root(const std::function<void()>& step) { agree_on(step, Agreed::root_only); }
void written_by_the_root(const std::function<void()>& write) { agree_on(write, Agreed::root_writes); }
bool failure_known_to_all() { return failure_agreed; }
#else
ProcessSession::ProcessSession(int&, char**&) {
  // mpirun on a build without MPI would start independent one-process runs
  // that all write the same output folder.
  for (const char* variable : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE"}) {
    const char* size = std::getenv(variable);
    if (size && std::strtol(size, nullptr, 10) > 1) {
      std::cerr << "pd-solve: error: started by an MPI launcher (" << variable << "=" << size
                << "), but this pd-solve is built without MPI (CMake option PD_WITH_MPI); run it without mpirun\n";
      std::exit(1);
    }
  }
}
ProcessSession::~ProcessSession() = default;
void ProcessSession::abort_all(int code) { std::exit(code); }
int process_count() { return 1; }
int process_rank() { return 0; }
int processes_on_this_machine() { return 1; }
std::unique_ptr<Communicator> distributed_communicator(const Partition&) {
  throw Error("this pd-solve is built without MPI (CMake option PD_WITH_MPI)");
}
void on_every_process(const std::function<void()>& step) { step(); }
void on_the_root(const std::function<void()>& step) { step(); }
void written_by_the_root(const std::function<void()>& write) { write(); }
bool failure_known_to_all() { return false; }
#endif

std::string with_process_rank(const std::string& message) {
  const int count = process_count();
  if (count == 1) return message;
  return "process " + std::to_string(process_rank()) + " of " + std::to_string(count) + ": " + message;
}

}  // namespace pd::solver
