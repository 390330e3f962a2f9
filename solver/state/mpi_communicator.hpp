#pragma once
// The Communicator of a run on several MPI processes (communicator.hpp),
// each owning one slab of the plate (partition.hpp). Compiled only when
// pd-solve is built with MPI (CMake option PD_WITH_MPI).
//
// Reductions: MPI_Allreduce (the same reduction tree on every call for a
// given process count, so a run's numbers do not depend on timing).
// Ghosts: the displacements (ux, uy) of the particles other processes own
// and this one's bonds reach, one message per neighbouring process and
// direction, through persistent requests (MPI_Send_init / MPI_Recv_init) on
// pack and unpack buffers allocated once: a step only starts and waits. One
// value per ghost (update_ghost_values: a state-based model's theta / m)
// goes the same way, on requests and buffers of its own. Each update is
// split in two (start: post the receives, pack, post the sends; finish:
// wait, unpack), so that the force evaluation can compute what reads no
// ghost while the messages travel (docs/solver.md, "Time loop").
#include <mpi.h>

#include <cstdint>
#include <vector>

#include "communicator.hpp"
#include "partition.hpp"

namespace pd::solver {

class MpiCommunicator final : public Communicator {
public:
  // Collective: the processes tell each other which of their particles each needs.
  MpiCommunicator(MPI_Comm comm, const Partition& partition);
  ~MpiCommunicator() override;
  MpiCommunicator(const MpiCommunicator&) = delete;
  MpiCommunicator& operator=(const MpiCommunicator&) = delete;

  int rank() const override { return rank_; }
  int size() const override { return size_; }
  double sum(double local) const override;
  std::uint64_t sum(std::uint64_t local) const override;
  double min(double local) const override;
  double max(double local) const override;
  bool any(bool local) const override;
  void start_ghost_update(ParticleState& state) const override;
  void finish_ghost_update(ParticleState& state) const override;
  void start_ghost_value_update(std::vector<double>& values) const override;
  void finish_ghost_value_update(std::vector<double>& values) const override;
  void gather_owned(const double* owned, std::size_t owned_count, std::size_t components,
                    std::vector<double>& whole) const override;
  void gather_owned_rows(const std::vector<std::uint8_t>& rows, const std::vector<std::uint32_t>& lengths,
                         std::vector<std::uint8_t>& whole) const override;
  void broadcast_from_root(std::vector<std::uint8_t>& bytes) const override;

  std::uint64_t ghost_bytes_sent_per_update() const override;
  std::uint64_t ghost_value_bytes_sent_per_update() const override;
  // Posting and packing, and waiting and unpacking, together; the second part alone.
  double ghost_update_seconds() const override { return start_seconds_ + finish_seconds_; }
  double ghost_wait_seconds() const override { return finish_seconds_; }

private:
  // One neighbouring process in one direction: the local particles whose
  // displacements go to it (or come from it), and the buffers of the messages.
  struct Link {
    int process = 0;
    std::vector<std::uint32_t> particles;  // local indices
    std::vector<double> buffer;            // 2 values per particle: ux, uy [m]
    std::vector<double> values;            // 1 value per particle (update_ghost_values)
  };
  // The persistent requests of every link's `buffer` (or `values`): receives first, then sends.
  std::vector<MPI_Request> persistent_requests(std::vector<double> Link::*buffer, int tag);
  // The two halves of one exchange on `requests`. start: start the
  // receives, pack(link) every send buffer, start the sends. finish: wait
  // for all, unpack(link) every receive buffer. `in_flight` guards the
  // pairing (an exchange finished that was not started, or started twice,
  // is a programming error).
  template <class Pack>
  void start(std::vector<MPI_Request>& requests, bool& in_flight, Pack&& pack) const;
  template <class Unpack>
  void finish(std::vector<MPI_Request>& requests, bool& in_flight, Unpack&& unpack) const;

  MPI_Comm comm_;
  int rank_ = 0, size_ = 1;
  mutable std::vector<Link> sends_, receives_;  // (the updates fill the buffers)
  mutable std::vector<MPI_Request> requests_, value_requests_;  // displacements; one value per particle
  // The root's map from the gathered order (process by process, each its
  // owned particles ascending) to global ids.
  std::vector<std::uint32_t> gathered_ids_;
  std::vector<int> owned_counts_, owned_displacements_;
  std::size_t whole_count_ = 0;
  mutable double start_seconds_ = 0, finish_seconds_ = 0;  // both kinds of update
  mutable bool displacements_in_flight_ = false, values_in_flight_ = false;
};

}  // namespace pd::solver
