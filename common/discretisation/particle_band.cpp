#include "particle_band.hpp"

#include <optional>

#include "error.hpp"

namespace pd {
namespace {

// The families of the kept particles `ids` (global, ascending) out of
// families collected in global numbering with only theirs kept, renumbered;
// a family that reaches a particle not kept becomes the list of the rest.
Families renumbered(const Families& whole, const std::vector<std::uint32_t>& ids,
                    const std::vector<std::uint32_t>& local_of, std::vector<std::uint8_t>& complete) {
  const std::size_t n = ids.size();
  Families f = Families::lattices_renumbered(whole, n, local_of);
  f.level.resize(n);
  f.cell.resize(n);
  f.on_stencil.assign(n, 0);
  f.offsets.assign(n + 1, 0);
  complete.assign(n, 1);
  for (std::size_t l = 0; l < n; ++l) {
    const std::uint32_t i = ids[l];
    f.level[l] = whole.level[i];
    f.cell[l] = whole.cell[i];
    bool inside = true;
    whole.for_each_bond(i, [&](const BondRef& b) { inside = inside && local_of[b.neighbor] != Families::none; });
    if (whole.on_stencil[i] && inside) {
      f.on_stencil[l] = 1;
    } else {
      whole.for_each_bond(i, [&](const BondRef& b) {
        if (local_of[b.neighbor] == Families::none) return;
        f.neighbors.push_back(local_of[b.neighbor]);
        f.partial_volume.push_back(b.partial_volume);
      });
      complete[l] = inside ? 1 : 0;
    }
    f.offsets[l + 1] = f.neighbors.size();
  }
  return f;
}

// Keeps the particles `ids` (ascending) of `p`, in place: per-particle
// arrays and cells; no families.
void keep_in_place(ParticleSet& p, const std::vector<std::uint32_t>& ids) {
  const auto compact = [&](auto& values) {
    for (std::size_t l = 0; l < ids.size(); ++l) values[l] = values[ids[l]];  // ids[l] >= l
    values.resize(ids.size());
    values.shrink_to_fit();
  };
  std::uint64_t vertices = 0;
  for (std::size_t l = 0; l < ids.size(); ++l) {
    const std::uint64_t begin = p.cell_offsets[ids[l]], end = p.cell_offsets[ids[l] + 1];
    for (auto v = begin; v < end; ++v, ++vertices) {  // vertices <= v: moves towards the front only
      p.cell_vx[vertices] = p.cell_vx[v];
      p.cell_vy[vertices] = p.cell_vy[v];
    }
    p.cell_offsets[l + 1] = vertices;
  }
  p.cell_offsets.resize(ids.size() + 1);
  p.cell_offsets.shrink_to_fit();
  for (auto* v : {&p.cell_vx, &p.cell_vy}) {
    v->resize(vertices);
    v->shrink_to_fit();
  }
  for (auto* v : {&p.x, &p.y, &p.volume, &p.cell_size, &p.horizon}) compact(*v);
  compact(p.region);
  compact(p.material);
  std::vector<std::uint64_t>().swap(p.family_offsets);
}

}  // namespace

ParticleBand read_particle_band(const std::string& path, int axis, double lo, double hi) {
  return read_particle_band(path, [&](const ParticleSet&) { return BandChoice{axis, lo, hi}; });
}

ParticleBand read_particle_band(const std::string& path, const BandChooser& choose_band,
                                const WholeArraysVisitor& visit_whole) {
  ParticleBand band;
  std::vector<std::uint32_t> local_of;  // per particle of the file: its local index, or none
  std::optional<FamilyCollector> collector;
  // The per-particle arrays come before the first family: the band is chosen then.
  const auto choose = [&](const ParticleSet& whole) {
    const BandChoice c = choose_band(whole);
    if (!(c.lo <= c.hi) || (c.axis != 0 && c.axis != 1))
      throw Error(path + ": cannot read the band [" + std::to_string(c.lo) + ", " + std::to_string(c.hi) +
                  "] m along axis " + std::to_string(c.axis));
    const std::vector<double>& position = c.axis == 0 ? whole.x : whole.y;
    local_of.assign(whole.size(), Families::none);
    std::vector<std::uint8_t> keep(whole.size(), 0);
    for (std::uint32_t i = 0; i < whole.size(); ++i)
      if (position[i] >= c.lo && position[i] <= c.hi) {
        local_of[i] = static_cast<std::uint32_t>(band.global_id.size());
        band.global_id.push_back(i);
        keep[i] = 1;
      }
    collector.emplace(whole, std::move(keep));
  };
  ParticleSet whole = read_particle_file(
      path, [&](const ParticleSet& read, std::uint32_t i, const std::uint32_t* family, const double* phi,
                std::size_t count) {
        if (!collector) choose(read);
        collector->add(i, family, phi, count);
      });
  if (!collector) choose(whole);  // no bonds
  if (visit_whole) visit_whole(whole);
  band.whole_count = whole.size();
  band.whole_bond_count = whole.family_offsets.back();

  // The kept particles, moved to the front of the whole set's own arrays (the
  // local order is the file's): no second copy of them at the read's peak,
  // and the rest freed before the families are renumbered.
  ParticleSet& p = band.particles;
  p = std::move(whole);
  keep_in_place(p, band.global_id);
  band.families = renumbered(collector->finish(), band.global_id, local_of, band.family_complete);
  collector.reset();
  for (BoundarySet& set : p.sets) {
    std::size_t kept = 0;
    for (const std::uint32_t i : set.particles)
      if (local_of[i] != Families::none) set.particles[kept++] = local_of[i];  // ascending: local order is global order
    set.particles.resize(kept);
    set.particles.shrink_to_fit();
  }
  return band;
}

}  // namespace pd
