#include "local_bonds.hpp"

#include "error.hpp"

namespace pd::solver {
namespace {

template <class T>
std::vector<T> pick(const std::vector<T>& whole, const std::vector<std::uint32_t>& ids) {
  std::vector<T> local;
  if (whole.empty()) return local;
  local.reserve(ids.size());
  for (auto i : ids) local.push_back(whole[i]);
  return local;
}

DirectionalShapes pick_shapes(const DirectionalShapes& whole, const std::vector<std::uint32_t>& ids) {
  DirectionalShapes local;
  if (whole.row.empty()) return local;
  local.row.assign(ids.size(), DirectionalShapes::none);
  for (std::size_t l = 0; l < ids.size(); ++l) {
    if (!whole.has(ids[l])) continue;
    local.row[l] = static_cast<std::uint32_t>(local.coefficients.size());
    local.coefficients.push_back(whole.coefficients[whole.row[ids[l]]]);
  }
  return local;
}

}  // namespace

LocalBonds local_bonds(const ParticleSet& whole, const BondSetup& whole_setup,
                       const std::vector<std::uint32_t>& ids, std::size_t owned_count) {
  LocalBonds r;
  ParticleSet& p = r.particles;
  p = empty_like(whole);
  p.cell_offsets.clear();  // no cell polygons: the solver's set-up is done
  p.x = pick(whole.x, ids);
  p.y = pick(whole.y, ids);
  p.volume = pick(whole.volume, ids);
  p.cell_size = pick(whole.cell_size, ids);
  p.horizon = pick(whole.horizon, ids);
  p.region = pick(whole.region, ids);
  p.material = pick(whole.material, ids);

  std::vector<std::uint32_t> local_of(whole.size(), Families::none);
  for (std::size_t l = 0; l < ids.size(); ++l) local_of[ids[l]] = static_cast<std::uint32_t>(l);

  BondSetup& s = r.setup;
  s.horizon = whole_setup.horizon;
  s.horizon_mode = whole_setup.horizon_mode;
  s.lambda = pick(whole_setup.lambda, ids);
  s.shapes = pick_shapes(whole_setup.shapes, ids);
  s.dilatation_shapes = pick_shapes(whole_setup.dilatation_shapes, ids);
  s.lambda_iterations = whole_setup.lambda_iterations;
  s.lambda_from_cache = whole_setup.lambda_from_cache;

  // The families: the whole plate's lattices (their cells now name local
  // particles), every local particle in its cell; an owned particle keeps its
  // family as it is (a stencil or a list), a ghost gets none.
  const Families& whole_families = whole_setup.families;
  Families& f = s.families;
  const std::size_t n = ids.size();
  f.particle_count = n;
  f.xmin = whole_families.xmin;
  f.ymin = whole_families.ymin;
  f.levels = whole_families.levels;
  for (StencilLevel& level : f.levels)
    for (std::uint32_t& at : level.at_cell)
      if (at != Families::none) at = local_of[at];
  s.energy_weight.stencil = whole_setup.energy_weight.stencil;
  f.level = pick(whole_families.level, ids);
  f.cell = pick(whole_families.cell, ids);
  f.on_stencil.assign(n, 0);
  f.offsets.assign(n + 1, 0);
  for (std::size_t l = 0; l < n; ++l) {
    if (l < owned_count && whole_families.on_stencil[ids[l]]) {
      f.on_stencil[l] = 1;  // its neighbours are local (the partition's ghosts): the stencil's cells hold them
    } else if (l < owned_count) {
      whole_families.for_each_bond(ids[l], [&](const BondRef& b) {
        const std::uint32_t j = local_of[b.neighbor];
        if (j == Families::none)
          throw Error("local_bonds: particle " + std::to_string(b.neighbor) + ", a neighbour of particle " +
                      std::to_string(ids[l]) + ", is not among the local particles");
        f.neighbors.push_back(j);
        f.partial_volume.push_back(b.partial_volume);
        s.energy_weight.listed.push_back(whole_setup.energy_weight(b));
        const bool intact = b.on_stencil || whole_setup.listed_intact[b.index];
        s.listed_intact.push_back(intact ? 1 : 0);
        s.precrack_cut += intact ? 0 : 1;
      });
    }
    f.offsets[l + 1] = f.neighbors.size();
  }
  return r;
}

}  // namespace pd::solver
