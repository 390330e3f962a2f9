#pragma once
// A process's ghost exchanges as the force field sees them (docs/solver.md,
// "Running on several processes (MPI)"): each in two halves, start and
// finish (Communicator::start_ghost_update and the like), so that the
// evaluation computes what reads no ghost while the messages travel. Unset
// on one process: an evaluation then exchanges nothing and splits nothing.
#include <functional>
#include <vector>

namespace pd::solver {

struct GhostExchange {
  // The ghosts' displacements (of the state the evaluation reads): start
  // before anything of the evaluation, finish before it reads a ghost's.
  std::function<void()> start_displacements, finish_displacements;
  // One value per local particle (a state-based model's theta_i / m_i).
  std::function<void(std::vector<double>&)> start_values, finish_values;

  bool set() const { return static_cast<bool>(start_displacements); }
  // Both halves at once, where nothing can run in between.
  void displacements() const {
    if (!set()) return;
    start_displacements();
    finish_displacements();
  }
  void values(std::vector<double>& per_particle) const {
    if (!set()) return;
    start_values(per_particle);
    finish_values(per_particle);
  }
};

}  // namespace pd::solver
