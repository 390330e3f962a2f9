#pragma once
// The seam between the solution methods and where the particles live. The
// time loop and the minimiser do every reduction over particles (energies,
// broken-bond counts, stop conditions, the stable time step, dot products)
// and every update of the neighbours a rank does not own through this
// interface, never by themselves. This build runs on one process: the serial
// communicator below is the identity. A distributed one (ranks owning
// subdomains, ghost particles within one horizon) implements the same
// functions; the kernels never see it.
#include <cstdint>

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
  virtual void update_ghosts(ParticleState& state) const = 0;
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
  void update_ghosts(ParticleState&) const override {}
};

// The communicator of a one-process run.
inline const Communicator& serial_communicator() {
  static const SerialCommunicator serial;
  return serial;
}

}  // namespace pd::solver
