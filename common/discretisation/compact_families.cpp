#include "compact_families.hpp"

#include <algorithm>
#include <cmath>

#include "error.hpp"

namespace pd {

std::uint64_t Families::bond_count() const {
  return static_cast<std::uint64_t>(stencil_particle_count()) * stencil_size() + neighbors.size();
}

std::size_t Families::stencil_particle_count() const {
  return static_cast<std::size_t>(std::count(on_stencil.begin(), on_stencil.end(), std::uint8_t{1}));
}

void Families::make_listed(const std::vector<std::uint32_t>& particles) {
  std::vector<std::uint8_t> convert(particle_count, 0);
  for (auto i : particles)
    if (on_stencil[i]) convert[i] = 1;
  std::vector<std::uint64_t> new_offsets(particle_count + 1, 0);
  std::vector<std::uint32_t> new_neighbors;
  std::vector<double> new_phi;
  for (std::uint32_t i = 0; i < particle_count; ++i) {
    if (convert[i] || !on_stencil[i])
      for_each_bond(i, [&](const BondRef& b) {
        new_neighbors.push_back(b.neighbor);
        new_phi.push_back(b.partial_volume);
      });
    new_offsets[i + 1] = new_neighbors.size();
  }
  for (std::uint32_t i = 0; i < particle_count; ++i)
    if (convert[i]) on_stencil[i] = 0;
  offsets.swap(new_offsets);
  neighbors.swap(new_neighbors);
  partial_volume.swap(new_phi);
}

FamilyCollector::FamilyCollector(const ParticleSet& p) {
  const std::size_t n = p.size();
  const double dx = p.spacing;
  f_.particle_count = n;
  f_.spacing = dx;
  f_.xmin = p.xmin;
  f_.ymin = p.ymin;
  f_.on_stencil.assign(n, 0);
  f_.cell.assign(n, -1);
  f_.offsets.reserve(n + 1);
  f_.offsets.push_back(0);
  if (!(dx > 0) || n == 0) return;
  f_.nx = std::lround((p.xmax - p.xmin) / dx);
  f_.ny = std::lround((p.ymax - p.ymin) / dx);
  if (f_.nx <= 0 || f_.ny <= 0) return;
  f_.at_cell.assign(static_cast<std::size_t>(f_.nx * f_.ny), Families::none);
  for (std::uint32_t i = 0; i < n; ++i) {
    if (p.region[i] != static_cast<std::uint8_t>(Region::uniform_square) || p.volume[i] != dx * dx) continue;
    const long col = static_cast<long>(std::floor((p.x[i] - p.xmin) / dx));
    const long row = static_cast<long>(std::floor((p.y[i] - p.ymin) / dx));
    if (col < 0 || col >= f_.nx || row < 0 || row >= f_.ny) continue;
    f_.cell[i] = row * f_.nx + col;
    f_.at_cell[static_cast<std::size_t>(f_.cell[i])] = i;
  }
  // The reference: the first square whose surroundings, one horizon and one
  // cell beyond, are all squares, so that its family is a whole interior family.
  const long reach = static_cast<long>(std::ceil(p.horizon_nominal / dx)) + 1;
  for (std::uint32_t i = 0; i < n && reference_ == Families::none; ++i) {
    if (f_.cell[i] < 0) continue;
    const long col = static_cast<long>(f_.cell[i] % f_.nx), row = static_cast<long>(f_.cell[i] / f_.nx);
    if (col < reach || col + reach >= f_.nx || row < reach || row + reach >= f_.ny) continue;
    bool interior = true;
    for (long r = row - reach; r <= row + reach && interior; ++r)
      for (long c = col - reach; c <= col + reach && interior; ++c)
        interior = f_.at_cell[static_cast<std::size_t>(r * f_.nx + c)] != Families::none;
    if (interior) reference_ = i;
  }
}

bool FamilyCollector::matches_stencil(std::uint32_t i, const std::uint32_t* neighbors, const double* phi,
                                      std::size_t count) const {
  if (f_.cell[i] < 0 || count != f_.stencil_size() || count == 0) return false;
  const long col = static_cast<long>(f_.cell[i] % f_.nx), row = static_cast<long>(f_.cell[i] / f_.nx);
  for (std::size_t o = 0; o < count; ++o) {
    const long c = col + f_.stencil_di[o], r = row + f_.stencil_dj[o];
    if (c < 0 || c >= f_.nx || r < 0 || r >= f_.ny) return false;
    if (f_.at_cell[static_cast<std::size_t>(r * f_.nx + c)] != neighbors[o]) return false;
    // The same analytic partial area of the same relative geometry: equal up
    // to round-off (~1e-13 seen); far below what a float damage weight resolves.
    if (std::fabs(phi[o] - f_.stencil_phi[o]) > 1e-9) return false;
  }
  return true;
}

void FamilyCollector::append_listed(std::uint32_t, const std::uint32_t* neighbors, const double* phi,
                                    std::size_t count) {
  f_.neighbors.insert(f_.neighbors.end(), neighbors, neighbors + count);
  f_.partial_volume.insert(f_.partial_volume.end(), phi, phi + count);
  f_.offsets.push_back(f_.neighbors.size());
}

void FamilyCollector::take_stencil_from(std::uint32_t i, const std::uint32_t* neighbors, const double* phi,
                                        std::size_t count) {
  const long col = static_cast<long>(f_.cell[i] % f_.nx), row = static_cast<long>(f_.cell[i] / f_.nx);
  for (std::size_t o = 0; o < count; ++o) {
    const auto c = f_.cell[neighbors[o]];
    if (c < 0) {  // not a lattice family after all: keep every family as a list
      f_.stencil_di.clear();
      f_.stencil_dj.clear();
      f_.stencil_phi.clear();
      return;
    }
    f_.stencil_di.push_back(static_cast<long>(c % f_.nx) - col);
    f_.stencil_dj.push_back(static_cast<long>(c / f_.nx) - row);
    f_.stencil_phi.push_back(phi[o]);
  }
  // The particles before the reference were kept as lists: drop the lists
  // that are the stencil (in place; rows only move towards the front).
  std::uint64_t write = 0, read_begin = 0;
  for (std::uint32_t q = 0; q < i; ++q) {
    const std::uint64_t read_end = f_.offsets[q + 1];
    const std::size_t size = static_cast<std::size_t>(read_end - read_begin);
    if (matches_stencil(q, f_.neighbors.data() + read_begin, f_.partial_volume.data() + read_begin, size)) {
      f_.on_stencil[q] = 1;
    } else {
      std::copy(f_.neighbors.begin() + static_cast<std::ptrdiff_t>(read_begin),
                f_.neighbors.begin() + static_cast<std::ptrdiff_t>(read_end),
                f_.neighbors.begin() + static_cast<std::ptrdiff_t>(write));
      std::copy(f_.partial_volume.begin() + static_cast<std::ptrdiff_t>(read_begin),
                f_.partial_volume.begin() + static_cast<std::ptrdiff_t>(read_end),
                f_.partial_volume.begin() + static_cast<std::ptrdiff_t>(write));
      write += size;
    }
    f_.offsets[q + 1] = write;
    read_begin = read_end;
  }
  f_.neighbors.resize(write);
  f_.partial_volume.resize(write);
}

void FamilyCollector::add(std::uint32_t i, const std::uint32_t* neighbors, const double* phi, std::size_t count) {
  if (i != next_)
    throw Error("families must be collected in particle order: got particle " + std::to_string(i) + ", expected " +
                std::to_string(next_));
  ++next_;
  if (i == reference_) take_stencil_from(i, neighbors, phi, count);
  if (!f_.stencil_phi.empty() && matches_stencil(i, neighbors, phi, count)) {
    f_.on_stencil[i] = 1;
    f_.offsets.push_back(f_.neighbors.size());
  } else {
    append_listed(i, neighbors, phi, count);
  }
}

Families FamilyCollector::finish() {
  if (next_ != f_.particle_count)
    throw Error("families of " + std::to_string(next_) + " of " + std::to_string(f_.particle_count) +
                " particles collected");
  f_.neighbors.shrink_to_fit();
  f_.partial_volume.shrink_to_fit();
  return std::move(f_);
}

Families compact_families(const ParticleSet& p) {
  FamilyCollector collector(p);
  for (std::uint32_t i = 0; i < p.size(); ++i) {
    const auto first = p.family_offsets[i];
    collector.add(i, p.neighbors.data() + first, p.partial_volume.data() + first,
                  static_cast<std::size_t>(p.family_offsets[i + 1] - first));
  }
  return collector.finish();
}

ParticlesAndFamilies read_compact_particle_file(const std::string& path) {
  std::optional<FamilyCollector> collector;
  ParticlesAndFamilies r;
  r.particles = read_particle_file(path, [&](const ParticleSet& particles, std::uint32_t i,
                                             const std::uint32_t* neighbors, const double* phi, std::size_t count) {
    if (!collector) collector.emplace(particles);
    collector->add(i, neighbors, phi, count);
  });
  if (!collector) collector.emplace(r.particles);  // no particles, no families
  r.families = collector->finish();
  return r;
}

}  // namespace pd
