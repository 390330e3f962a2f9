#include "variable_horizon_bonds.hpp"

#include <algorithm>
#include <cmath>
#include <tuple>
#include <utility>

#include "error.hpp"

namespace pd::solver {

FamilyMembership::FamilyMembership(const Families& families) {
  pairs_.reserve(static_cast<std::size_t>(families.bond_count()));
  for (std::uint32_t i = 0; i < families.particle_count; ++i)
    families.for_each_bond(i, [&](const BondRef& b) { pairs_.push_back(std::uint64_t{i} << 32 | b.neighbor); });
  std::sort(pairs_.begin(), pairs_.end());
}

bool FamilyMembership::contains(std::uint32_t owner, std::uint32_t member) const {
  return std::binary_search(pairs_.begin(), pairs_.end(), std::uint64_t{owner} << 32 | member);
}

namespace {

// For every bond i -> j, the index of its reverse j -> i when that can share
// i's row entry with it: both exist with the same rest length, critical
// extension and state (equal horizons), so that the bond and the dual entry
// of its reverse see the same extension bit for bit (the same xi in float,
// the same |xi|) and break at the same step. `none` otherwise.
constexpr std::uint64_t none = ~std::uint64_t{0};
std::vector<std::uint64_t> mergeable_reverses(const std::vector<OwnedBond>& bonds, std::size_t n) {
  // Each owner's bonds are contiguous (owner order). The bonds into each
  // particle, listed per particle in bond order (a counting sort by
  // neighbour), are the reverses' candidates of that particle's own bonds:
  // with the owner's bonds marked by neighbour, each is found in one look-up
  // (no sort, no search; a family names a neighbour once).
  std::vector<std::uint64_t> first(n + 1, 0), into_first(n + 1, 0);
  for (std::size_t b = 0; b < bonds.size(); ++b) {
    if (b > 0 && bonds[b].owner < bonds[b - 1].owner)
      throw Error("variable_horizon_rows: the owned bonds are not in owner order");
    ++first[bonds[b].owner + 1];
    ++into_first[bonds[b].neighbor + 1];
  }
  for (std::size_t i = 0; i < n; ++i) {
    first[i + 1] += first[i];
    into_first[i + 1] += into_first[i];
  }
  std::vector<std::uint64_t> into(bonds.size());
  {
    std::vector<std::uint64_t> next(into_first.begin(), into_first.end() - 1);
    for (std::size_t b = 0; b < bonds.size(); ++b) into[next[bonds[b].neighbor]++] = b;
  }
  std::vector<std::uint64_t> reverse(bonds.size(), none);
  std::vector<std::uint64_t> own_bond_to(n, none);  // per neighbour: the current owner's bond to it
  for (std::size_t i = 0; i < n; ++i) {
    if (first[i] == first[i + 1] || into_first[i] == into_first[i + 1]) continue;
    for (auto b = first[i]; b < first[i + 1]; ++b) own_bond_to[bonds[b].neighbor] = b;
    for (auto k = into_first[i]; k < into_first[i + 1]; ++k) {
      const std::uint64_t back_index = into[k];  // j -> i
      const OwnedBond& back = bonds[back_index];
      const std::uint64_t b = own_bond_to[back.owner];  // i -> j
      if (b == none) continue;
      const OwnedBond& bond = bonds[b];
      if (back.rest_length == bond.rest_length && back.critical_extension == bond.critical_extension &&
          back.intact == bond.intact)
        reverse[b] = back_index;
    }
    for (auto b = first[i]; b < first[i + 1]; ++b) own_bond_to[bonds[b].neighbor] = none;
  }
  return reverse;
}

// The values of one row entry: of `from`'s row towards `to`, carrying bond b
// with the stiffness and damage weight given (an own, a dual or a combined
// entry: `halves` as BondTable::entry_halves counts them).
struct RowEntry {
  std::uint32_t neighbor;
  float xi_x, xi_y;
  double rest_length, stiffness, critical_extension;
  float damage_weight;
  std::uint8_t halves, state;
};
inline RowEntry row_entry(const ParticleSet& p, std::uint32_t from, std::uint32_t to, const OwnedBond& b,
                          double stiffness, float weight, std::uint8_t halves) {
  return {to,
          static_cast<float>(p.x[to] - p.x[from]),
          static_cast<float>(p.y[to] - p.y[from]),
          b.rest_length,
          stiffness,
          b.critical_extension,
          weight,
          halves,
          static_cast<std::uint8_t>(b.intact ? 1 : 0)};
}
// The own entry of bond k in its owner's row: with the dual entry of its
// reverse where the two are combined (mergeable_reverses; `reverse` empty: never).
inline RowEntry own_entry(const ParticleSet& p, const std::vector<OwnedBond>& bonds,
                          const std::vector<std::uint64_t>& reverse, std::size_t k) {
  const OwnedBond& b = bonds[k];
  if (reverse.empty() || reverse[k] == none)
    return row_entry(p, b.owner, b.neighbor, b, b.stiffness, b.owner_weight, 1);
  // The bond and the reaction of its reverse, both on i.
  const OwnedBond& back = bonds[reverse[k]];
  return row_entry(p, b.owner, b.neighbor, b, b.stiffness + dual_entry_stiffness(p, back),
                   b.owner_weight + back.neighbor_weight, 2);
}
// The dual entry of bond b in the row of its neighbour: the reaction on j,
// the same force [N] as a density of j's volume.
inline RowEntry dual_entry(const ParticleSet& p, const OwnedBond& b) {
  return row_entry(p, b.neighbor, b.owner, b, dual_entry_stiffness(p, b), b.neighbor_weight, 1);
}

// Calls `f` on each per-entry array a RowEntry fills (put_entry writes them;
// the state-based ones variable_horizon_rows fills itself; `with_halves`: a
// dual-horizon table's count of its entries' halves). A copy of rows takes
// every array a table holds (BondTable::for_each_entry_array).
template <class F>
void for_each_row_entry_array(BondTable& t, bool with_damage, bool with_halves, F&& f) {
  f(t.neighbor);
  f(t.xi_x);
  f(t.xi_y);
  f(t.rest_length);
  f(t.stiffness);
  f(t.critical_extension);
  if (with_damage) f(t.damage_weight);
  if (with_halves) f(t.entry_halves);
}
inline void resize_entries(BondTable& t, std::size_t size, bool with_damage, bool with_halves) {
  for_each_row_entry_array(t, with_damage, with_halves, [size](auto& v) { v.resize(size); });
}
// Writes entry e of table t and its state (the table's arrays sized to
// hold it; `with_halves`: a dual-horizon table, which counts its entries' halves).
inline void put_entry(BondTable& t, std::vector<std::uint8_t>& states, std::uint64_t e, const RowEntry& v,
                      bool with_damage, bool with_halves) {
  t.neighbor[e] = v.neighbor;
  t.xi_x[e] = v.xi_x;
  t.xi_y[e] = v.xi_y;
  t.rest_length[e] = v.rest_length;
  t.stiffness[e] = v.stiffness;
  t.critical_extension[e] = v.critical_extension;
  if (with_damage) t.damage_weight[e] = v.damage_weight;
  if (with_halves) t.entry_halves[e] = v.halves;
  states[e] = v.state;
}

}  // namespace

BondTable variable_horizon_rows(const ParticleSet& p, const std::vector<OwnedBond>& bonds, HorizonMode mode,
                                bool with_damage, std::vector<std::uint8_t>* intact, bool with_dilatation,
                                std::vector<std::uint64_t>* entry_bond) {
  if (mode == HorizonMode::uniform) throw Error("variable_horizon_rows: the run has one horizon");
  const std::size_t n = p.size();
  const bool dual = mode == HorizonMode::dual_horizon;
  // Dual horizons of a bond-based model: the own entry of i -> j also holds
  // the dual entry of j -> i where they break together (mergeable_reverses),
  // so that a pair of equal horizons is one entry in each row instead of two.
  // Not with the dilatation (a state-based model): its pre-pass sums a row's
  // own entries apart from its dual entries, which carry their owners'
  // dilatation (theory.md Sec. 6.8), and a combined entry would mix the two.
  const bool combine = dual && !with_dilatation;
  const std::vector<std::uint64_t> reverse = combine ? mergeable_reverses(bonds, n) : std::vector<std::uint64_t>{};
  const auto merged = [&](std::size_t b) { return combine && reverse[b] != none; };
  // Entries per row: own bonds, plus (dual horizon) the bonds others own
  // towards it that no own entry holds.
  std::vector<std::uint64_t> own_count(n, 0), dual_count(n, 0);
  for (std::size_t b = 0; b < bonds.size(); ++b) {
    ++own_count[bonds[b].owner];
    if (dual && !merged(b)) ++dual_count[bonds[b].neighbor];
  }
  BondTable t;
  t.particle_count = n;
  t.offsets.assign(n + 1, 0);
  for (std::size_t i = 0; i < n; ++i) t.offsets[i + 1] = t.offsets[i] + own_count[i] + dual_count[i];
  const std::size_t total = t.offsets[n];
  resize_entries(t, total, with_damage, dual);
  if (with_dilatation) {
    t.volume_over_length.resize(total);
    t.weighted_volume.assign(n, 0.0);
    // W_i holds the whole energy of i's own bonds, k_ij = 2 C(delta_i) (theory.md Sec. 6.8).
    t.energy_stiffness.assign(total, 0.0);
  }
  std::vector<std::uint8_t> states(total, 1);
  if (entry_bond) entry_bond->assign(total, 0);
  // Own bonds fill each row's front, dual entries follow in owner order.
  std::vector<std::uint64_t> next_own(t.offsets.begin(), t.offsets.end() - 1), next_dual(n);
  for (std::size_t i = 0; i < n; ++i) next_dual[i] = t.offsets[i] + own_count[i];
  if (dual) t.dual_begin = next_dual;
  const auto put = [&](std::uint64_t e, const RowEntry& v) { put_entry(t, states, e, v, with_damage, dual); };
  for (std::size_t index = 0; index < bonds.size(); ++index) {
    const OwnedBond& b = bonds[index];
    const std::uint64_t own = next_own[b.owner]++;
    put(own, own_entry(p, bonds, reverse, index));
    if (merged(index)) {
      if (entry_bond) (*entry_bond)[own] = index;  // the reverse breaks with it: the same state
      continue;
    }
    const std::uint64_t reaction = dual ? next_dual[b.neighbor]++ : 0;
    if (dual) put(reaction, dual_entry(p, b));
    if (entry_bond) {
      (*entry_bond)[own] = index;
      if (dual) (*entry_bond)[reaction] = index;
    }
    if (with_dilatation) {
      const double volume_over_length = b.dilatation_volume / b.rest_length;
      t.volume_over_length[own] = volume_over_length;
      t.weighted_volume[b.owner] += b.dilatation_volume;
      t.energy_stiffness[own] = 2.0 * b.stiffness;
      if (dual) t.volume_over_length[reaction] = volume_over_length * p.volume[b.owner] / p.volume[b.neighbor];
    }
  }
  if (with_damage) {
    t.family_area.assign(n, 0.0);
    for (std::size_t i = 0; i < n; ++i)
      for (auto e = t.offsets[i]; e < t.offsets[i + 1]; ++e) t.family_area[i] += t.damage_weight[e];
  }
  if (intact) *intact = std::move(states);
  return t;
}

double dual_horizon_state_stable_time_step(const BondTable& t, double dilatation_coefficient, double density,
                                           const std::vector<std::uint32_t>* rows) {
  if (t.dual_begin.empty() || t.weighted_volume.empty())
    throw Error("dual_horizon_state_stable_time_step: the table has no dual entries or no dilatation weights");
  const std::size_t n = t.particle_count;
  // g_i / m_i^2 per particle: how strongly i's dilatation answers a displacement (theory.md Sec. 5.4).
  std::vector<double> g(n, 0.0), g_over_m2(n, 0.0);
  for (std::size_t i = 0; i < n; ++i) {
    for (auto e = t.offsets[i]; e < t.own_end(i); ++e) g[i] += t.volume_over_length[e];
    g_over_m2[i] = dilatation_response(g[i], t.weighted_volume[i]);
  }
  double smallest = INFINITY;
  const std::size_t row_count = rows ? rows->size() : n;
  for (std::size_t k = 0; k < row_count; ++k) {
    const std::size_t i = rows ? (*rows)[k] : k;
    double stiffness_sum = 0, reactions = 0;
    for (auto e = t.offsets[i]; e < t.offsets[i + 1]; ++e) stiffness_sum += t.stiffness[e];
    for (auto e = t.dual_begin[i]; e < t.offsets[i + 1]; ++e)
      reactions += t.volume_over_length[e] * g_over_m2[t.neighbor[e]];
    smallest = std::min(smallest, dual_horizon_state_row_time_step(stiffness_sum, g[i], g_over_m2[i], reactions,
                                                                   dilatation_coefficient, density));
  }
  return smallest;
}

double dilatation_response(double g, double weighted_volume) {
  return weighted_volume > 0 ? g / (weighted_volume * weighted_volume) : 0.0;
}

double dual_horizon_state_row_time_step(double stiffness_sum, double g, double g_over_m2, double reactions,
                                        double dilatation_coefficient, double density) {
  const double r = 2.0 * stiffness_sum + 16.0 * std::fabs(dilatation_coefficient) * (g * g_over_m2 + reactions);
  return r > 0 ? 2.0 * std::sqrt(density / r) : INFINITY;
}

StencilChange stencil_change(const StencilLevel& before, const StencilLevel& after) {
  if (before.spacing != after.spacing || before.horizon != after.horizon || before.size() != after.size())
    return StencilChange::other;
  if (before.di == after.di && before.dj == after.dj && before.phi == after.phi) return StencilChange::same;
  using Bond = std::tuple<long, long, double>;
  const auto sorted = [](const StencilLevel& s) {
    std::vector<Bond> bonds;
    for (std::size_t o = 0; o < s.size(); ++o) bonds.emplace_back(s.di[o], s.dj[o], s.phi[o]);
    std::sort(bonds.begin(), bonds.end());
    return bonds;
  };
  return sorted(before) == sorted(after) ? StencilChange::order : StencilChange::other;
}

const std::vector<std::uint8_t>& changed_rows(const Families& now, const EarlierRowStiffness& earlier) {
  if (earlier.changed_rows.size() != earlier.same_row.size()) earlier.changed_rows = rows_changed_by_event(now, earlier);
  return earlier.changed_rows;
}

std::vector<std::uint8_t> rows_changed_by_event(const Families& now, const EarlierRowStiffness& earlier) {
  const std::size_t n = earlier.same_row.size();
  // What an event can change besides the rows it rebuilt: a stencil particle
  // sums its own entries in its level's stencil order, which the family that
  // defines the stencil sets (where that order changed, the level's stencil
  // particles sum theirs again); and a level's spacing and horizon choose
  // how its bonds' weights are computed (bond_weights.hpp: a level whose
  // stencil went or came computes its listed bonds' weights another way, to
  // round-off), so that the rows of its particles and of their neighbours,
  // which hold their dual entries, are summed again.
  const Families* before = earlier.families;
  std::vector<StencilChange> level_change(now.levels.size(), StencilChange::other);
  for (std::size_t l = 0; l < level_change.size() && before; ++l)
    // (A level new in this set holds children only, all summed.)
    level_change[l] = l < before->levels.size() ? stencil_change(before->levels[l], now.levels[l])
                                                : StencilChange::order;
  std::vector<std::uint8_t> changed(n, 0);
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint32_t e = earlier.same_row[i];
    const std::uint8_t l = now.level[i];
    const bool stencil = now.on_stencil[i];
    changed[i] = !(e != Families::none && before && before->on_stencil[e] == stencil && before->level[e] == l &&
                   (l == Families::no_level || level_change[l] == StencilChange::same ||
                    (!stencil && level_change[l] == StencilChange::order)));
  }
  // A particle that left its level's stencil or joined it (its family built
  // again, or the stencil's order changed) may weigh its bonds another way
  // (partial-volume weights: from the cell steps on the stencil, from the
  // positions on a list), which changes its dual entries in its neighbours' rows.
  if (earlier.origin.size() != n)
    throw Error("rows_changed_by_event: the origins are given for another particle count");
  for (std::uint32_t i = 0; i < n; ++i) {
    const std::uint32_t o = earlier.origin[i];
    const bool left_or_joined = before && o != Families::none && before->on_stencil[o] != now.on_stencil[i];
    if (left_or_joined ||
        (now.level[i] != Families::no_level && level_change[now.level[i]] == StencilChange::other)) {
      changed[i] = 1;
      now.for_each_bond(i, [&](const BondRef& b) { changed[b.neighbor] = 1; });
    }
  }
  return changed;
}

std::vector<std::uint32_t> particles_near(const ParticleSet& p, const std::vector<std::uint8_t>& marked,
                                          double reach) {
  const std::size_t n = p.size();
  std::vector<std::uint32_t> near;
  if (n == 0) return near;
  if (!(reach > 0)) throw Error("particles_near: the reach must be positive (the set's longest possible bond)");
  double xmin = INFINITY, xmax = -INFINITY, ymin = INFINITY, ymax = -INFINITY;
  for (std::size_t i = 0; i < n; ++i) {
    xmin = std::min(xmin, p.x[i]);
    xmax = std::max(xmax, p.x[i]);
    ymin = std::min(ymin, p.y[i]);
    ymax = std::max(ymax, p.y[i]);
  }
  // Squares a little wider than the reach: two particles within it are in
  // the same square or in neighbouring ones, whatever the round-off of the
  // division below.
  const double side = std::max(reach, 1e-12 * std::max(xmax - xmin, ymax - ymin)) * (1 + 1e-6);
  if (!(side > 0)) {  // one point: every particle
    for (std::uint32_t i = 0; i < n; ++i) near.push_back(i);
    return near;
  }
  const auto columns = static_cast<long>((xmax - xmin) / side) + 1, rows = static_cast<long>((ymax - ymin) / side) + 1;
  const auto square_of = [&](std::size_t i) {
    const long c = std::min(columns - 1, static_cast<long>((p.x[i] - xmin) / side));
    const long r = std::min(rows - 1, static_cast<long>((p.y[i] - ymin) / side));
    return std::pair<long, long>{c, r};
  };
  std::vector<std::uint8_t> holds_marked(static_cast<std::size_t>(columns * rows), 0);
  for (std::size_t i = 0; i < n; ++i)
    if (marked[i]) {
      const auto [c, r] = square_of(i);
      holds_marked[static_cast<std::size_t>(r * columns + c)] = 1;
    }
  // Each square next to (or at) a square holding a marked particle.
  std::vector<std::uint8_t> next_to_marked(holds_marked.size(), 0);
  for (long r = 0; r < rows; ++r)
    for (long c = 0; c < columns; ++c) {
      if (!holds_marked[static_cast<std::size_t>(r * columns + c)]) continue;
      for (long rr = std::max(0L, r - 1); rr <= std::min(rows - 1, r + 1); ++rr)
        for (long cc = std::max(0L, c - 1); cc <= std::min(columns - 1, c + 1); ++cc)
          next_to_marked[static_cast<std::size_t>(rr * columns + cc)] = 1;
    }
  for (std::uint32_t i = 0; i < n; ++i) {
    const auto [c, r] = square_of(i);
    if (next_to_marked[static_cast<std::size_t>(r * columns + c)]) near.push_back(i);
  }
  return near;
}

GeneralRowsPlan plan_general_rows(const ParticleSet& p, const Families& now, const std::vector<std::uint8_t>& is_lattice,
                                  const EarlierRowStiffness& earlier) {
  const KeptGeneralRows& old = *earlier.general_rows;
  const BondTable& old_table = *earlier.general_table;
  const std::size_t n = is_lattice.size(), old_n = old.is_lattice.size();
  if (earlier.same_row.size() != n || earlier.origin.size() != n || old_table.particle_count != old_n ||
      old_table.size() != old.intact.size())
    throw Error("dual_horizon_general_rows: the earlier rows are given for another particle count");
  GeneralRowsPlan plan;
  plan.new_of_old.assign(old_n, Families::none);
  // A particle's lattice membership decides which of its bonds the rows
  // hold: where it changed (a child is new), every row holding an entry of
  // it is built, the particle's own and those of its family members and of
  // the owners of its dual entries (the particles it is a member of).
  std::vector<std::uint8_t> moved(n, 0);
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint32_t o = earlier.origin[i];
    moved[i] = o == Families::none || old.is_lattice[o] != is_lattice[i];
    if (o != Families::none) plan.new_of_old[o] = static_cast<std::uint32_t>(i);
  }
  plan.build = changed_rows(now, earlier);
  std::vector<std::uint8_t> moved_before(n, 0);  // moved, not a child
  bool any_moved_before = false;
  for (std::uint32_t i = 0; i < n; ++i) {
    if (!moved[i]) continue;
    plan.build[i] = 1;
    now.for_each_bond(i, [&](const BondRef& b) { plan.build[b.neighbor] = 1; });
    if (earlier.origin[i] != Families::none) moved_before[i] = any_moved_before = true;
  }
  // A general row holding a bond into a moved particle (its family holds
  // it): a family holding a child was built again (already built), so only
  // the moved particles that were there before are looked for, in the
  // families of the particles within a bond's length of them.
  if (any_moved_before)
    for (const std::uint32_t i : particles_near(p, moved_before, earlier.longest_bond)) {
      if (plan.build[i] || is_lattice[i]) continue;
      now.for_each_bond(i, [&](const BondRef& b) {
        if (moved[b.neighbor]) plan.build[i] = 1;
      });
    }
  // A row to copy must name particles that are still there (a split parent
  // is not). An entry of a row with j is mirrored by an entry of j's row with
  // the row's particle (an own entry by a dual or a combined one): the rows
  // that name a particle gone are those its own row names.
  std::vector<std::uint8_t> names_gone(old_n, 0);
  for (std::size_t o = 0; o < old_n; ++o)
    if (plan.new_of_old[o] == Families::none)
      for (auto k = old_table.offsets[o]; k < old_table.offsets[o + 1]; ++k) names_gone[old_table.neighbor[k]] = 1;
  for (std::size_t i = 0; i < n; ++i)
    if (!plan.build[i] && names_gone[earlier.same_row[i]]) plan.build[i] = 1;
  // The owners: the general particles whose row is built, and those with a
  // bond into a built general row. Such an owner whose row is copied has its
  // earlier particle's family (with the new indices), and the row built is
  // of a particle that neither is a child nor moved (else the owner's family
  // held a child or a moved particle: built): the earlier row of that
  // particle names the owner, by a dual entry or by a combined one (the
  // reverse of its own bond).
  std::vector<std::uint8_t> owner(n, 0);
  for (std::uint32_t j = 0; j < n; ++j) {
    if (!plan.build[j] || is_lattice[j]) continue;
    owner[j] = 1;
    const std::uint32_t o = earlier.origin[j];
    if (moved[j]) continue;  // (a child too)
    for (auto e = old_table.offsets[o]; e < old_table.offsets[o + 1]; ++e) {
      if (e < old_table.dual_begin[o] && old_table.entry_halves[e] != 2) continue;  // j's own bond only
      const std::uint32_t i = plan.new_of_old[old_table.neighbor[e]];
      if (i != Families::none && !is_lattice[i]) owner[i] = 1;
    }
  }
  for (std::uint32_t i = 0; i < n; ++i)
    if (owner[i]) plan.owners.push_back(i);
  return plan;
}

BondTable general_rows_with_copies(const ParticleSet& p, const std::vector<OwnedBond>& bonds,
                                   const GeneralRowsPlan& plan, const EarlierRowStiffness& earlier,
                                   const std::vector<std::uint8_t>& is_lattice, bool with_damage,
                                   std::vector<std::uint8_t>* intact, std::size_t* copied) {
  const KeptGeneralRows& old = *earlier.general_rows;
  const BondTable& before = *earlier.general_table;
  const std::size_t n = plan.build.size();
  // A built row as variable_horizon_rows makes it: its own bonds (each
  // owner's contiguous in `bonds`) with the reverses they hold, then the
  // bonds into it that no own entry holds, in owner order. Listed per row
  // here, so that every row is written in its place in one pass: no table
  // of the built rows to copy from.
  const std::vector<std::uint64_t> reverse = mergeable_reverses(bonds, n);
  std::vector<std::uint64_t> own_first(n + 1, 0), dual_first(n + 1, 0);
  for (std::size_t k = 0; k < bonds.size(); ++k) {
    ++own_first[bonds[k].owner + 1];
    if (reverse[k] == none && plan.build[bonds[k].neighbor]) ++dual_first[bonds[k].neighbor + 1];
  }
  for (std::size_t i = 0; i < n; ++i) {
    own_first[i + 1] += own_first[i];
    dual_first[i + 1] += dual_first[i];
  }
  std::vector<std::uint64_t> dual_bonds(dual_first[n]);
  {
    std::vector<std::uint64_t> next(dual_first.begin(), dual_first.end() - 1);
    for (std::size_t k = 0; k < bonds.size(); ++k)
      if (reverse[k] == none && plan.build[bonds[k].neighbor]) dual_bonds[next[bonds[k].neighbor]++] = k;
  }
  BondTable t;
  t.particle_count = n;
  t.offsets.assign(n + 1, 0);
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint64_t length =
        plan.build[i] ? (own_first[i + 1] - own_first[i]) + (dual_first[i + 1] - dual_first[i])
                      : before.offsets[earlier.same_row[i] + 1] - before.offsets[earlier.same_row[i]];
    t.offsets[i + 1] = t.offsets[i] + length;
  }
  // The entries are appended row by row (no zeroing of the whole table first).
  const std::size_t total = t.offsets[n];
  for_each_row_entry_array(t, with_damage, true, [total](auto& v) { v.reserve(total); });
  t.dual_begin.resize(n);
  std::vector<std::uint8_t> states;
  states.reserve(total);
  // A built row's stretch of every array is added at once (zeroed while
  // it is in cache) and its entries written by index: no capacity check
  // per entry and field.
  const auto extend_to = [&](std::size_t size) {
    resize_entries(t, size, with_damage, true);
    states.resize(size);
  };
  const auto put = [&](std::uint64_t e, const RowEntry& v) { put_entry(t, states, e, v, with_damage, true); };
  std::size_t rows_copied = 0;
  for (std::size_t i = 0; i < n;) {
    if (plan.build[i]) {
      t.dual_begin[i] = t.offsets[i] + (own_first[i + 1] - own_first[i]);
      extend_to(t.offsets[i + 1]);
      std::uint64_t e = t.offsets[i];
      for (auto k = own_first[i]; k < own_first[i + 1]; ++k) put(e++, own_entry(p, bonds, reverse, k));
      for (auto d = dual_first[i]; d < dual_first[i + 1]; ++d) put(e++, dual_entry(p, bonds[dual_bonds[d]]));
      ++i;
      continue;
    }
    // Runs of copied rows that follow each other in the earlier table (most
    // do: the particles that did not split keep their order) in one copy each.
    const std::size_t r = earlier.same_row[i];
    std::size_t end = i + 1;
    while (end < n && !plan.build[end] && earlier.same_row[end] == r + (end - i)) ++end;
    const std::size_t rows = end - i;
    for (std::size_t q = 0; q < rows; ++q) {
      t.dual_begin[i + q] = t.offsets[i + q] + (before.dual_begin[r + q] - before.offsets[r + q]);
      if (!is_lattice[i + q]) ++rows_copied;
    }
    const auto first = before.offsets[r], count = before.offsets[r + rows] - first;
    const auto copy = [&](const auto& a, auto& b) {
      b.insert(b.end(), a.begin() + static_cast<std::ptrdiff_t>(first),
               a.begin() + static_cast<std::ptrdiff_t>(first + count));
    };
    // Every array the earlier rows hold (those the rows are built with:
    // the same scene), the neighbours as they were, then renumbered in one pass.
    const std::size_t renumber_from = t.neighbor.size();
    BondTable::for_each_entry_array([&](const char*, auto member) {
      if (!(before.*member).empty()) copy(before.*member, t.*member);
    });
    copy(old.intact, states);
    std::uint32_t* const renumbered = t.neighbor.data();
    const std::uint32_t* const new_of_old = plan.new_of_old.data();
    for (std::size_t k = renumber_from; k < renumber_from + count; ++k) renumbered[k] = new_of_old[renumbered[k]];
    i = end;
  }
  if (with_damage) {  // as variable_horizon_rows sums it: over the row in its order
    t.family_area.assign(n, 0.0);
    for (std::size_t i = 0; i < n; ++i)
      for (auto e = t.offsets[i]; e < t.offsets[i + 1]; ++e) t.family_area[i] += t.damage_weight[e];
  }
  if (intact) *intact = std::move(states);
  if (copied) *copied = rows_copied;
  return t;
}

void set_entry_states_from_families(const BondTable& table, const std::vector<std::uint8_t>* family_states,
                                    std::vector<std::uint8_t>& intact) {
  const std::size_t n = table.particle_count;
  if (intact.size() != table.size())
    throw Error("the bond states do not fit the rows (" + std::to_string(intact.size()) + " for " +
                std::to_string(table.size()) + " entries)");
  if (family_states) {
    std::uint64_t own = 0;
    for (std::size_t i = 0; i < n; ++i) own += table.own_end(i) - table.offsets[i];
    if (family_states->size() != own)
      throw Error("the saved bond states do not fit the particle set's families (" +
                  std::to_string(family_states->size()) + " for " + std::to_string(own) + ")");
    auto next = family_states->begin();
    for (std::size_t i = 0; i < n; ++i)
      for (auto e = table.offsets[i]; e < table.own_end(i); ++e) intact[e] = *next++;
  }
  if (table.dual_begin.empty()) return;
  for (std::uint32_t i = 0; i < n; ++i)
    for (auto e = table.dual_begin[i]; e < table.offsets[i + 1]; ++e) {
      const std::uint32_t owner = table.neighbor[e];
      auto b = table.offsets[owner];
      while (b < table.own_end(owner) && table.neighbor[b] != i) ++b;
      if (b == table.own_end(owner))
        throw Error("a dual entry of particle " + std::to_string(i) + " has no bond of its owner " +
                    std::to_string(owner));
      intact[e] = intact[b];
    }
}

double row_stable_time_step(const BondTable& t, double density) {
  std::vector<double> row_stiffness(t.particle_count, 0.0);
  for (std::size_t i = 0; i < t.particle_count; ++i)
    for (auto e = t.offsets[i]; e < t.offsets[i + 1]; ++e) row_stiffness[i] += t.stiffness[e];
  return row_stable_time_step(row_stiffness, density);
}

double row_stable_time_step(const std::vector<double>& row_stiffness, double density) {
  double smallest = INFINITY;
  for (double k : row_stiffness)
    if (k > 0) smallest = std::min(smallest, std::sqrt(2.0 * density / k));
  return smallest;
}

}  // namespace pd::solver
