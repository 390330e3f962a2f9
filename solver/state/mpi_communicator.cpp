#include "mpi_communicator.hpp"

#include <algorithm>

#include "error.hpp"

namespace pd::solver {
namespace {
// Message tags of the ghost updates: displacements, one value per particle
// (no other point-to-point traffic).
constexpr int ghost_tag = 7, ghost_value_tag = 8;

std::vector<int> offsets_of(const std::vector<int>& counts) {
  std::vector<int> offsets(counts.size(), 0);
  for (std::size_t r = 1; r < counts.size(); ++r) offsets[r] = offsets[r - 1] + counts[r - 1];
  return offsets;
}
}  // namespace

MpiCommunicator::MpiCommunicator(MPI_Comm comm, const Partition& part) : comm_(comm) {
  MPI_Comm_rank(comm_, &rank_);
  MPI_Comm_size(comm_, &size_);
  if (rank_ != part.rank || size_ != part.size)
    throw Error("the partition was made for process " + std::to_string(part.rank) + " of " +
                std::to_string(part.size) + ", not " + std::to_string(rank_) + " of " + std::to_string(size_));
  whole_count_ = part.whole_count;

  // What this process needs from each owner: its ghosts, grouped by owner
  // (ascending global ids within a group, as the ghosts are).
  std::vector<int> wanted_count(size_, 0);
  for (int owner : part.ghost_owner) ++wanted_count[owner];
  std::vector<std::uint32_t> wanted_ids;  // grouped by owner
  std::vector<int> wanted_offset = offsets_of(wanted_count);
  wanted_ids.resize(part.ghosts.size());
  {
    std::vector<int> next = wanted_offset;
    for (std::size_t g = 0; g < part.ghosts.size(); ++g) wanted_ids[next[part.ghost_owner[g]]++] = part.ghosts[g];
  }
  std::vector<int> asked_count(size_, 0);
  MPI_Alltoall(wanted_count.data(), 1, MPI_INT, asked_count.data(), 1, MPI_INT, comm_);
  std::vector<int> asked_offset = offsets_of(asked_count);
  std::vector<std::uint32_t> asked_ids(asked_offset.back() + asked_count.back());
  MPI_Alltoallv(wanted_ids.data(), wanted_count.data(), wanted_offset.data(), MPI_UINT32_T, asked_ids.data(),
                asked_count.data(), asked_offset.data(), MPI_UINT32_T, comm_);

  // Local indices: owned particles are 0 .. owned - 1 in ascending global id,
  // ghosts follow in ascending global id.
  const auto owned_index = [&](std::uint32_t id) {
    const auto at = std::lower_bound(part.owned.begin(), part.owned.end(), id);
    if (at == part.owned.end() || *at != id)
      throw Error("a process asked for particle " + std::to_string(id) + ", which process " +
                  std::to_string(rank_) + " does not own");
    return static_cast<std::uint32_t>(at - part.owned.begin());
  };
  const auto ghost_index = [&](std::uint32_t id) {
    const auto at = std::lower_bound(part.ghosts.begin(), part.ghosts.end(), id);
    return static_cast<std::uint32_t>(part.owned.size() + (at - part.ghosts.begin()));
  };
  for (int r = 0; r < size_; ++r) {
    if (asked_count[r] > 0) {
      Link link;
      link.process = r;
      for (int k = 0; k < asked_count[r]; ++k) link.particles.push_back(owned_index(asked_ids[asked_offset[r] + k]));
      link.buffer.assign(2 * link.particles.size(), 0.0);
      link.values.assign(link.particles.size(), 0.0);
      sends_.push_back(std::move(link));
    }
    if (wanted_count[r] > 0) {
      Link link;
      link.process = r;
      for (int k = 0; k < wanted_count[r]; ++k) link.particles.push_back(ghost_index(wanted_ids[wanted_offset[r] + k]));
      link.buffer.assign(2 * link.particles.size(), 0.0);
      link.values.assign(link.particles.size(), 0.0);
      receives_.push_back(std::move(link));
    }
  }
  // The buffers never move from here on: the persistent requests point into them.
  requests_ = persistent_requests(&Link::buffer, ghost_tag);
  value_requests_ = persistent_requests(&Link::values, ghost_value_tag);

  // The gather order of outputs and checkpoints.
  const int owned = static_cast<int>(part.owned.size());
  owned_counts_.assign(size_, 0);
  MPI_Gather(&owned, 1, MPI_INT, owned_counts_.data(), 1, MPI_INT, 0, comm_);
  owned_displacements_ = offsets_of(owned_counts_);
  if (rank_ == 0) gathered_ids_.resize(whole_count_);
  MPI_Gatherv(part.owned.data(), owned, MPI_UINT32_T, gathered_ids_.data(), owned_counts_.data(),
              owned_displacements_.data(), MPI_UINT32_T, 0, comm_);
}

std::vector<MPI_Request> MpiCommunicator::persistent_requests(std::vector<double> Link::*buffer, int tag) {
  std::vector<MPI_Request> requests;
  for (Link& link : receives_) {
    std::vector<double>& b = link.*buffer;
    requests.emplace_back();
    MPI_Recv_init(b.data(), static_cast<int>(b.size()), MPI_DOUBLE, link.process, tag, comm_, &requests.back());
  }
  for (Link& link : sends_) {
    std::vector<double>& b = link.*buffer;
    requests.emplace_back();
    MPI_Send_init(b.data(), static_cast<int>(b.size()), MPI_DOUBLE, link.process, tag, comm_, &requests.back());
  }
  return requests;
}

MpiCommunicator::~MpiCommunicator() {
  for (MPI_Request& r : requests_) MPI_Request_free(&r);
  for (MPI_Request& r : value_requests_) MPI_Request_free(&r);
}

double MpiCommunicator::sum(double local) const {
  double r = 0;
  MPI_Allreduce(&local, &r, 1, MPI_DOUBLE, MPI_SUM, comm_);
  return r;
}
std::uint64_t MpiCommunicator::sum(std::uint64_t local) const {
  std::uint64_t r = 0;
  MPI_Allreduce(&local, &r, 1, MPI_UINT64_T, MPI_SUM, comm_);
  return r;
}
double MpiCommunicator::min(double local) const {
  double r = 0;
  MPI_Allreduce(&local, &r, 1, MPI_DOUBLE, MPI_MIN, comm_);
  return r;
}
double MpiCommunicator::max(double local) const {
  double r = 0;
  MPI_Allreduce(&local, &r, 1, MPI_DOUBLE, MPI_MAX, comm_);
  return r;
}
bool MpiCommunicator::any(bool local) const {
  int value = local ? 1 : 0, r = 0;
  MPI_Allreduce(&value, &r, 1, MPI_INT, MPI_LOR, comm_);
  return r != 0;
}

template <class Pack>
void MpiCommunicator::start(std::vector<MPI_Request>& requests, bool& in_flight, Pack&& pack) const {
  if (in_flight) throw Error("a ghost update was started twice without finishing");
  const double begin = MPI_Wtime();
  MPI_Startall(static_cast<int>(receives_.size()), requests.data());
  for (Link& link : sends_) pack(link);  // into the buffer the persistent send reads
  MPI_Startall(static_cast<int>(sends_.size()), requests.data() + receives_.size());
  in_flight = true;
  start_seconds_ += MPI_Wtime() - begin;
}

template <class Unpack>
void MpiCommunicator::finish(std::vector<MPI_Request>& requests, bool& in_flight, Unpack&& unpack) const {
  if (!in_flight) throw Error("a ghost update was finished that had not been started");
  const double begin = MPI_Wtime();
  MPI_Waitall(static_cast<int>(requests.size()), requests.data(), MPI_STATUSES_IGNORE);
  for (const Link& link : receives_) unpack(link);
  in_flight = false;
  finish_seconds_ += MPI_Wtime() - begin;
}

void MpiCommunicator::start_ghost_update(ParticleState& state) const {
  const Kinematics& k = state.motion;
  start(requests_, displacements_in_flight_, [&](Link& link) {
    for (std::size_t m = 0; m < link.particles.size(); ++m) {
      link.buffer[2 * m] = k.ux[link.particles[m]];
      link.buffer[2 * m + 1] = k.uy[link.particles[m]];
    }
  });
}

void MpiCommunicator::finish_ghost_update(ParticleState& state) const {
  Kinematics& k = state.motion;
  finish(requests_, displacements_in_flight_, [&](const Link& link) {
    for (std::size_t m = 0; m < link.particles.size(); ++m) {
      k.ux[link.particles[m]] = link.buffer[2 * m];
      k.uy[link.particles[m]] = link.buffer[2 * m + 1];
    }
  });
}

void MpiCommunicator::start_ghost_value_update(std::vector<double>& values) const {
  start(value_requests_, values_in_flight_, [&](Link& link) {
    for (std::size_t m = 0; m < link.particles.size(); ++m) link.values[m] = values[link.particles[m]];
  });
}

void MpiCommunicator::finish_ghost_value_update(std::vector<double>& values) const {
  finish(value_requests_, values_in_flight_, [&](const Link& link) {
    for (std::size_t m = 0; m < link.particles.size(); ++m) values[link.particles[m]] = link.values[m];
  });
}

std::uint64_t MpiCommunicator::ghost_bytes_sent_per_update() const {
  std::uint64_t bytes = 0;
  for (const Link& link : sends_) bytes += link.buffer.size() * sizeof(double);
  return bytes;
}

std::uint64_t MpiCommunicator::ghost_value_bytes_sent_per_update() const {
  std::uint64_t bytes = 0;
  for (const Link& link : sends_) bytes += link.values.size() * sizeof(double);
  return bytes;
}

void MpiCommunicator::gather_owned(const double* owned, std::size_t owned_count, std::size_t components,
                                   std::vector<double>& whole) const {
  const int width = static_cast<int>(components);
  std::vector<int> counts(owned_counts_), offsets(owned_displacements_);
  for (int r = 0; r < size_; ++r) counts[r] *= width, offsets[r] *= width;
  std::vector<double> gathered(rank_ == 0 ? whole_count_ * components : 0);
  MPI_Gatherv(owned, static_cast<int>(owned_count * components), MPI_DOUBLE, gathered.data(), counts.data(),
              offsets.data(), MPI_DOUBLE, 0, comm_);
  whole.clear();
  if (rank_ != 0) return;
  whole.resize(whole_count_ * components);
  for (std::size_t m = 0; m < whole_count_; ++m)
    std::copy_n(gathered.data() + m * components, components, whole.data() + gathered_ids_[m] * components);
}

void MpiCommunicator::gather_owned_rows(const std::vector<std::uint8_t>& rows, const std::vector<std::uint32_t>& lengths,
                                        std::vector<std::uint8_t>& whole) const {
  // The row lengths first (to place the rows), then the rows.
  std::vector<std::uint32_t> gathered_lengths(rank_ == 0 ? whole_count_ : 0);
  MPI_Gatherv(lengths.data(), static_cast<int>(lengths.size()), MPI_UINT32_T, gathered_lengths.data(),
              owned_counts_.data(), owned_displacements_.data(), MPI_UINT32_T, 0, comm_);
  const int local_bytes = static_cast<int>(rows.size());
  std::vector<int> byte_counts(size_, 0);
  MPI_Gather(&local_bytes, 1, MPI_INT, byte_counts.data(), 1, MPI_INT, 0, comm_);
  const std::vector<int> byte_offsets = offsets_of(byte_counts);
  std::vector<std::uint8_t> gathered(rank_ == 0 ? static_cast<std::size_t>(byte_offsets.back() + byte_counts.back()) : 0);
  MPI_Gatherv(rows.data(), local_bytes, MPI_UINT8_T, gathered.data(), byte_counts.data(), byte_offsets.data(),
              MPI_UINT8_T, 0, comm_);
  whole.clear();
  if (rank_ != 0) return;
  std::vector<std::uint64_t> row_length(whole_count_, 0), start(whole_count_ + 1, 0);
  for (std::size_t m = 0; m < whole_count_; ++m) row_length[gathered_ids_[m]] = gathered_lengths[m];
  for (std::size_t i = 0; i < whole_count_; ++i) start[i + 1] = start[i] + row_length[i];
  whole.resize(start[whole_count_]);
  std::uint64_t from = 0;
  for (std::size_t m = 0; m < whole_count_; ++m) {
    const auto id = gathered_ids_[m];
    std::copy_n(gathered.data() + from, row_length[id], whole.data() + start[id]);
    from += row_length[id];
  }
}

void MpiCommunicator::broadcast_from_root(std::vector<std::uint8_t>& bytes) const {
  std::uint64_t size = bytes.size();
  MPI_Bcast(&size, 1, MPI_UINT64_T, 0, comm_);
  bytes.resize(static_cast<std::size_t>(size));
  // In pieces below MPI's int count (a plate's bond states may pass 2^31).
  constexpr std::uint64_t piece = std::uint64_t{1} << 30;
  for (std::uint64_t from = 0; from < size; from += piece)
    MPI_Bcast(bytes.data() + from, static_cast<int>(std::min(piece, size - from)), MPI_UINT8_T, 0, comm_);
}

}  // namespace pd::solver
