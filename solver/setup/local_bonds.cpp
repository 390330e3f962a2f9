#include "local_bonds.hpp"

#include <algorithm>
#include <type_traits>

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

LocalRows local_rows(BondTable whole, std::vector<std::uint8_t> whole_intact,
                     std::vector<std::uint64_t> whole_entry_bond, const std::vector<std::uint32_t>& ids,
                     std::size_t owned_count, std::size_t first_row) {
  if (first_row > owned_count) throw Error("local_rows: the first row cut lies beyond the owned particles");
  if ((!whole_entry_bond.empty() && whole_entry_bond.size() != whole.size()) ||
      (!whole_intact.empty() && whole_intact.size() != whole.size()))
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
  BondTable::for_each_particle_array([&](const char*, auto member) { t.*member = pick(whole.*member, ids); });
  for (std::size_t l = 0; l < n; ++l) {
    t.offsets[l + 1] = t.offsets[l];
    if (l < first_row || l >= owned_count) {
      if (dual) t.dual_begin[l] = t.offsets[l];
      continue;
    }
    const std::uint32_t i = ids[l];
    t.offsets[l + 1] += whole.offsets[i + 1] - whole.offsets[i];
    if (dual) t.dual_begin[l] = t.offsets[l] + (whole.dual_begin[i] - whole.offsets[i]);
  }
  // Array by array, each of the whole table's freed once cut: the cut-out
  // and the whole table are never held together (a process's set-up peak).
  const auto cut = [&](auto& from, auto& into) {
    if (from.empty()) return;
    into.reserve(t.offsets[n]);
    for (std::size_t l = first_row; l < owned_count; ++l) {
      const std::uint32_t i = ids[l];
      into.insert(into.end(), from.begin() + static_cast<std::ptrdiff_t>(whole.offsets[i]),
                  from.begin() + static_cast<std::ptrdiff_t>(whole.offsets[i + 1]));
    }
    std::remove_reference_t<decltype(from)>().swap(from);
  };
  for (std::size_t l = first_row; l < owned_count; ++l)
    for (auto e = whole.offsets[ids[l]]; e < whole.offsets[ids[l] + 1]; ++e)
      if (local_of[whole.neighbor[e]] == Families::none)
        throw Error("local_rows: particle " + std::to_string(whole.neighbor[e]) + ", in the row of particle " +
                    std::to_string(ids[l]) + ", is not among the local particles");
  for (auto& j : whole.neighbor) j = local_of[j];  // (in place: another row's may name none)
  BondTable::for_each_entry_array([&](const char*, auto member) { cut(whole.*member, t.*member); });
  cut(whole_intact, r.intact);
  cut(whole_entry_bond, r.entry_bond);
  return r;
}

LocalRows joined_rows(std::vector<LocalRows> pieces, const std::vector<std::size_t>& first_row,
                      std::size_t owned_count) {
  LocalRows r;
  if (pieces.empty()) return r;
  if (first_row.size() != pieces.size() || first_row.front() != 0)
    throw Error("joined_rows: each piece needs its first row, the first piece row 0");
  BondTable& t = r.table;
  const BondTable& front = pieces.front().table;
  const std::size_t n = front.particle_count;
  const bool dual = !front.dual_begin.empty();
  t.particle_count = n;
  t.critical_stretch = front.critical_stretch;
  t.offsets.assign(n + 1, 0);
  if (dual) t.dual_begin.assign(n, 0);
  // (A ghost's values are the first piece's: unused, as local_rows says.)
  BondTable::for_each_particle_array([&](const char*, auto member) { t.*member = front.*member; });
  std::size_t holder = 0;  // the piece whose rows hold row l
  for (std::size_t l = 0; l < n; ++l) {
    while (holder + 1 < pieces.size() && l >= first_row[holder + 1] && l < owned_count) ++holder;
    const BondTable& piece = pieces[l < owned_count ? holder : 0].table;
    if (piece.particle_count != n) throw Error("joined_rows: the pieces are cut for other particles");
    t.offsets[l + 1] = t.offsets[l] + (piece.offsets[l + 1] - piece.offsets[l]);
    if (dual) t.dual_begin[l] = t.offsets[l] + (piece.dual_begin[l] - piece.offsets[l]);
    if (l < owned_count)
      BondTable::for_each_particle_array([&](const char*, auto member) {
        if (!(t.*member).empty()) (t.*member)[l] = (piece.*member)[l];
      });
  }
  // Array by array, each piece's freed once copied.
  const auto join = [&](auto member) {
    auto& into = member(r);
    if (member(pieces.front()).empty()) return;
    into.reserve(t.offsets[n]);
    for (LocalRows& piece : pieces) {
      auto& from = member(piece);
      into.insert(into.end(), from.begin(), from.end());
      std::remove_reference_t<decltype(from)>().swap(from);
    }
  };
  BondTable::for_each_entry_array([&](const char*, auto member) {
    join([member](LocalRows& x) -> auto& { return x.table.*member; });
  });
  join([](LocalRows& x) -> auto& { return x.intact; });
  join([](LocalRows& x) -> auto& { return x.entry_bond; });
  if (t.neighbor.size() != t.offsets[n]) throw Error("joined_rows: a piece holds rows beyond its own");
  return r;
}

std::vector<std::uint64_t> family_starts(const Families& families) {
  std::vector<std::uint64_t> first(families.particle_count + 1, 0);
  for (std::uint32_t i = 0; i < families.particle_count; ++i) first[i + 1] = first[i] + families.family_size(i);
  return first;
}

}  // namespace pd::solver
