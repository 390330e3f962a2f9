#include "local_bonds.hpp"

#include <algorithm>

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
  const std::size_t n = ids.size();
  s.families = Families::lattices_renumbered(whole_families, n, local_of);
  Families& f = s.families;
  s.energy_weight.stencil = whole_setup.energy_weight.stencil;
  f.level = pick(whole_families.level, ids);
  f.cell = pick(whole_families.cell, ids);
  f.on_stencil.assign(n, 0);
  f.offsets.assign(n + 1, 0);
  // The owned lists reserved to size (grown bond by bond they would take up
  // to twice their memory, beside the whole plate's set-up).
  std::uint64_t listed = 0;
  for (std::size_t l = 0; l < owned_count; ++l)
    if (!whole_families.on_stencil[ids[l]]) listed += whole_families.family_size(ids[l]);
  f.neighbors.reserve(listed);
  f.partial_volume.reserve(listed);
  s.energy_weight.listed.reserve(listed);
  s.listed_intact.reserve(listed);
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

LocalRows local_rows(const BondTable& whole, const std::vector<std::uint8_t>& whole_intact,
                     const std::vector<std::uint64_t>& whole_entry_bond, const std::vector<std::uint32_t>& ids,
                     std::size_t owned_count) {
  if (whole_entry_bond.size() != whole.size() || (!whole_intact.empty() && whole_intact.size() != whole.size()))
    throw Error("local_rows: the entries' states or bonds do not fit the table");
  std::vector<std::uint32_t> local_of(whole.particle_count, Families::none);
  for (std::size_t l = 0; l < ids.size(); ++l) local_of[ids[l]] = static_cast<std::uint32_t>(l);

  LocalRows r;
  BondTable& t = r.table;
  const std::size_t n = ids.size();
  const bool dual = !whole.dual_begin.empty();
  t.particle_count = n;
  t.critical_stretch = whole.critical_stretch;
  t.offsets.assign(n + 1, 0);
  if (dual) t.dual_begin.assign(n, 0);
  // Per-particle values of every local particle (a ghost's are its whole
  // plate's, unused: its row is empty and its results are discarded).
  t.family_area = pick(whole.family_area, ids);
  t.weighted_volume = pick(whole.weighted_volume, ids);
  const auto copy_entries = [](const auto& from, auto& into, std::uint64_t begin, std::uint64_t end) {
    if (!from.empty()) into.insert(into.end(), from.begin() + static_cast<std::ptrdiff_t>(begin),
                                   from.begin() + static_cast<std::ptrdiff_t>(end));
  };
  for (std::size_t l = 0; l < n; ++l) {
    const std::uint64_t start = t.neighbor.size();
    if (dual) t.dual_begin[l] = start;
    if (l < owned_count) {
      const std::uint32_t i = ids[l];
      const std::uint64_t begin = whole.offsets[i], end = whole.offsets[i + 1];
      for (auto e = begin; e < end; ++e) {
        const std::uint32_t j = local_of[whole.neighbor[e]];
        if (j == Families::none)
          throw Error("local_rows: particle " + std::to_string(whole.neighbor[e]) + ", in the row of particle " +
                      std::to_string(i) + ", is not among the local particles");
        t.neighbor.push_back(j);
      }
      copy_entries(whole.xi_x, t.xi_x, begin, end);
      copy_entries(whole.xi_y, t.xi_y, begin, end);
      copy_entries(whole.rest_length, t.rest_length, begin, end);
      copy_entries(whole.stiffness, t.stiffness, begin, end);
      copy_entries(whole.energy_stiffness, t.energy_stiffness, begin, end);
      copy_entries(whole.critical_extension, t.critical_extension, begin, end);
      copy_entries(whole.entry_halves, t.entry_halves, begin, end);
      copy_entries(whole.damage_weight, t.damage_weight, begin, end);
      copy_entries(whole.volume_over_length, t.volume_over_length, begin, end);
      copy_entries(whole.partner_volume_over_length, t.partner_volume_over_length, begin, end);
      copy_entries(whole_intact, r.intact, begin, end);
      copy_entries(whole_entry_bond, r.entry_bond, begin, end);
      if (dual) t.dual_begin[l] = start + (whole.dual_begin[i] - begin);
    }
    t.offsets[l + 1] = t.neighbor.size();
  }
  return r;
}

std::vector<std::uint64_t> family_starts(const Families& families) {
  std::vector<std::uint64_t> first(families.particle_count + 1, 0);
  for (std::uint32_t i = 0; i < families.particle_count; ++i) first[i + 1] = first[i] + families.family_size(i);
  return first;
}

void number_by_file(std::vector<std::uint64_t>& entry_bond, const std::vector<std::uint64_t>& first_bond,
                    const std::vector<std::uint64_t>& file_family_start) {
  if (first_bond.size() != file_family_start.size() + 1)
    throw Error("number_by_file: the file's family starts do not fit the particles");
  for (std::uint64_t& bond : entry_bond) {
    if (bond >= first_bond.back()) throw Error("number_by_file: a bond beyond the families");
    // The particle whose family holds the bond (the last one starting at or before it).
    const auto owner = static_cast<std::size_t>(std::upper_bound(first_bond.begin(), first_bond.end(), bond) -
                                                first_bond.begin()) - 1;
    bond = file_family_start[owner] + (bond - first_bond[owner]);
  }
}

}  // namespace pd::solver
