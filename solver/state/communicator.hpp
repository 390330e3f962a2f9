#pragma once
// The seam between the solution methods and where the particles live. The
// time loop and the minimiser do every reduction over particles (energies,
// broken-bond counts, stop conditions, the stable time step, dot products)
// and every update of the neighbours a rank does not own through this
// interface, never by themselves. The serial communicator below is the
// identity; the distributed one (mpi_communicator.hpp: ranks owning slabs of
// the plate, ghost particles within one horizon, partition.hpp) implements
// the same functions; the kernels never see it.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "particle_state.hpp"

namespace pd::solver {

class Communicator {
public:
  virtual ~Communicator() = default;
  virtual int rank() const = 0;
  virtual int size() const = 0;
  bool is_root() const { return rank() == 0; }  // the rank that prints and writes shared files

  // Reductions of one value per rank, in a fixed order (results must not
  // depend on timing).
  virtual double sum(double local) const = 0;
  virtual std::uint64_t sum(std::uint64_t local) const = 0;
  virtual double min(double local) const = 0;
  virtual double max(double local) const = 0;
  virtual bool any(bool local) const = 0;

  // Brings the copies of particles owned by other ranks (within one horizon
  // of this rank's own) up to date: after the positions change, before forces.
  // In two halves, so that work which reads no ghost can run in between:
  // start sends the owned displacements the others need and posts the
  // receives; finish waits for them and writes the ghosts' displacements.
  // Between the two, nothing may read a ghost's displacement or change an
  // owned one. One process: both do nothing.
  virtual void start_ghost_update(ParticleState& state) const = 0;
  virtual void finish_ghost_update(ParticleState& state) const = 0;
  void update_ghosts(ParticleState& state) const {
    start_ghost_update(state);
    finish_ghost_update(state);
  }
  // The same for one value per local particle (`values`: owned, then
  // ghosts): the owners' values overwrite the ghosts'. For what a pass over
  // whole families gives per particle and a later pass reads at both ends of
  // a bond, which a ghost's incomplete local family cannot give: a
  // state-based model's theta_i / m_i, between its dilatation pass and its
  // forces (ForceField::set_ghost_exchange). A second exchange per step.
  // Between start and finish nothing may read a ghost's entry or change an owned one.
  virtual void start_ghost_value_update(std::vector<double>& values) const = 0;
  virtual void finish_ghost_value_update(std::vector<double>& values) const = 0;
  void update_ghost_values(std::vector<double>& values) const {
    start_ghost_value_update(values);
    finish_ghost_value_update(values);
  }

  // The ghost exchanges' cost on this process, for the run's report: bytes
  // it sends per update of the displacements and per update of one value per
  // particle, and the wall time both kinds of update took so far, waiting
  // for the neighbours included [s] (0 on one process); of that, the time
  // spent in the finishing halves (waiting for the messages that had not
  // arrived, and writing the ghosts).
  virtual std::uint64_t ghost_bytes_sent_per_update() const { return 0; }
  virtual std::uint64_t ghost_value_bytes_sent_per_update() const { return 0; }
  virtual double ghost_update_seconds() const { return 0; }
  virtual double ghost_wait_seconds() const { return 0; }

  // Output and checkpoints: per-particle values of the particles this rank
  // owns (its local particles 0 .. owned_count - 1, `components` values
  // each, interleaved), put together in the particle file's order on the
  // root; `whole` is left empty on the other ranks.
  virtual void gather_owned(const double* owned, std::size_t owned_count, std::size_t components,
                            std::vector<double>& whole) const = 0;
  // The same for rows of different lengths (a particle's bond states): `rows`
  // holds the owned particles' rows one after the other, `lengths` their sizes.
  virtual void gather_owned_rows(const std::vector<std::uint8_t>& rows, const std::vector<std::uint32_t>& lengths,
                                 std::vector<std::uint8_t>& whole) const = 0;
  // The root's `bytes` onto every rank (a restart's bond states, which the
  // root alone converts: runs/checkpoint_layout.hpp); the others' are replaced.
  virtual void broadcast_from_root(std::vector<std::uint8_t>& bytes) const = 0;
};

class SerialCommunicator final : public Communicator {
public:
  int rank() const override { return 0; }
  int size() const override { return 1; }
  double sum(double local) const override { return local; }
  std::uint64_t sum(std::uint64_t local) const override { return local; }
  double min(double local) const override { return local; }
  double max(double local) const override { return local; }
  bool any(bool local) const override { return local; }
  void start_ghost_update(ParticleState&) const override {}
  void finish_ghost_update(ParticleState&) const override {}
  void start_ghost_value_update(std::vector<double>&) const override {}
  void finish_ghost_value_update(std::vector<double>&) const override {}
  void gather_owned(const double* owned, std::size_t owned_count, std::size_t components,
                    std::vector<double>& whole) const override {
    whole.assign(owned, owned + owned_count * components);
  }
  void gather_owned_rows(const std::vector<std::uint8_t>& rows, const std::vector<std::uint32_t>&,
                         std::vector<std::uint8_t>& whole) const override {
    whole = rows;
  }
  void broadcast_from_root(std::vector<std::uint8_t>&) const override {}
};

// The communicator of a one-process run.
inline const Communicator& serial_communicator() {
  static const SerialCommunicator serial;
  return serial;
}

}  // namespace pd::solver
