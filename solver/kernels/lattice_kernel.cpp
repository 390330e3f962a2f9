#include "lattice_kernel.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <type_traits>

#include "energy_bonds.hpp"
#include "error.hpp"
#include "variable_horizon_bonds.hpp"

namespace pd::solver {

namespace {
constexpr std::uint32_t none = 0xffffffffu;

bool close(double a, double b, double relative) { return std::fabs(a - b) <= relative * std::fabs(a); }

// Horizons equal as the particle file's check of one horizon takes them (bond_setup.cpp).
bool same_horizon(double horizon, double stencil_horizon) { return close(stencil_horizon, horizon, 1e-9); }

// A general-rows table whose entry row -> neighbor has no mirror entry in the
// neighbour's row (make_dual_horizon_pairs relies on it). Out of line and
// cold: the pairs' loop only tests for it.
[[noreturn]] __attribute__((noinline, cold)) void broken_mirror(std::uint32_t row, std::uint32_t neighbor) {
  throw Error("lattice kernel: the general rows hold an entry " + std::to_string(row) + " -> " +
              std::to_string(neighbor) + " without its mirror in row " + std::to_string(neighbor) +
              " (every bond between general particles has an entry in both rows)");
}

// Broken bonds are counted in whole units of 2^-20 of a cell's area (integers:
// the count does not depend on the order in which bonds break or are recounted).
constexpr double damage_units_per_cell = 1 << 20;
}  // namespace

LatticeKernel::LatticeKernel(const ParticleSet& p, const BondSetup& run_bonds, const LatticeModelSetup& model,
                             bool with_damage, const LatticeSubdomain* subdomain)
    : LatticeKernel(p, run_bonds, model, with_damage, subdomain, nullptr) {}

std::vector<std::uint8_t> LatticeKernel::lattice_particles(const ParticleSet& p, const BondSetup& run_bonds,
                                                           const LatticeModelSetup& model) {
  const ChoiceOnly choice_only;
  return LatticeKernel(p, run_bonds, model, false, nullptr, &choice_only).is_lattice_;
}

LatticeKernel::LatticeKernel(const ParticleSet& p, const BondSetup& run_bonds, const LatticeModelSetup& model,
                             bool with_damage, const LatticeSubdomain* subdomain, const ChoiceOnly* choice_only,
                             std::uint8_t swept, const std::vector<std::uint8_t>* earlier_verdict)
    : swept_(swept) {
  const Families& families = run_bonds.families;
  const std::size_t n = p.size();
  owned_count_ = subdomain ? subdomain->owned_count : n;
  // No lattice: an empty kernel, or (if the caller asks) one whose general
  // particles' lists hold every bond.
  const bool finer_level = swept > 0;  // a finer level's sweep alone: no general table
  const auto without_lattice = [&] {
    if (!choice_only && !finer_level && model.general_lists_without_lattice)
      take_every_particle_as_general(p, run_bonds, model, with_damage);
  };
  // Level 0's kernel sweeps the first resolution level (the particle
  // file's spacing) and makes the sweeps of the finer levels (at_level_horizon);
  // squares of other levels go through the neighbour lists.
  if (families.levels.size() <= swept) {
    without_lattice();
    return;
  }
  const StencilLevel& level = families.levels[swept];
  const double dx = level.spacing;
  const std::size_t s = level.size();
  // (A finer level's children have listed families: family_is_stencil.)
  const bool any_lattice =
      subdomain ? std::count(subdomain->is_lattice.begin(), subdomain->is_lattice.end(), 1) > 0
                : finer_level || families.stencil_particle_count(swept) > 0;
  if (s == 0 || !any_lattice) {  // no lattice: the neighbour lists do all
    without_lattice();
    return;
  }
  const long nx = level.nx;
  const auto col = [&](std::size_t i) { return static_cast<long>(families.cell[i] % nx); };
  const auto row = [&](std::size_t i) { return static_cast<long>(families.cell[i] / nx); };
  const auto on_level = [&](std::size_t i) { return families.level[i] == swept && families.cell[i] >= 0; };
  stencil_di_ = level.di;
  stencil_dj_ = level.dj;
  // Stencil bond constants without the surface-correction factors (bond_setup.hpp).
  std::vector<double> stiffness_ref(s), rest(s);
  for (std::size_t o = 0; o < s; ++o) {
    rest[o] = std::hypot(stencil_di_[o] * dx, stencil_dj_[o] * dx);
    stiffness_ref[o] = model.stiffness(run_bonds.energy_weight.stencil[swept][o], rest[o]);
  }
  for (std::size_t o = 0; o < s; ++o) halo_ = std::max({halo_, std::labs(stencil_di_[o]), std::labs(stencil_dj_[o])});
  const long width = 2 * halo_ + 1;
  const auto step_index = [&](long di, long dj) { return static_cast<std::size_t>((dj + halo_) * width + (di + halo_)); };

  // Forward half of the stencil (up, or right within the row), in sweep order:
  // column of the stencil first, so that consecutive offsets add into
  // different grid rows (a store followed by an overlapping load of the same
  // row would stall). Each forward offset needs its backward partner.
  std::vector<std::size_t> forward, backward;
  for (std::size_t o = 0; o < s; ++o)
    if (stencil_dj_[o] > 0 || (stencil_dj_[o] == 0 && stencil_di_[o] > 0)) forward.push_back(o);
  std::sort(forward.begin(), forward.end(), [&](std::size_t a, std::size_t b) {
    return std::make_pair(stencil_di_[a], stencil_dj_[a]) < std::make_pair(stencil_di_[b], stencil_dj_[b]);
  });
  for (auto o : forward)
    for (std::size_t q = 0; q < s; ++q)
      if (stencil_di_[q] == -stencil_di_[o] && stencil_dj_[q] == -stencil_dj_[o]) backward.push_back(q);
  const std::size_t half = forward.size();
  if (backward.size() != half || 2 * half != s) {  // not a symmetric stencil: no lattice
    stencil_di_.clear();
    stencil_dj_.clear();
    without_lattice();
    return;
  }
  // The two directions of a pair may differ in the last bits: the pair takes their mean.
  pair_of_step_.assign(static_cast<std::size_t>(width * width), -1);
  for (std::size_t h = 0; h < half; ++h) {
    const auto o = forward[h], m = backward[h];
    pair_of_step_[step_index(stencil_di_[o], stencil_dj_[o])] = static_cast<int>(h);
    pair_of_step_[step_index(stencil_di_[m], stencil_dj_[m])] = static_cast<int>(h + half);
    stiffness_ref[o] = stiffness_ref[m] = 0.5 * (stiffness_ref[o] + stiffness_ref[m]);
  }

  // The grid: the level's cells with `halo` padding cells on every side,
  // cut to a window around the local particles (on a process of a
  // distributed run its slab and ghosts, not the whole plate: the grid's
  // arrays hold about 40 bytes per cell), rows padded to whole SIMD steps.
  // The window keeps the sums of the whole grid bit for bit: it starts at a
  // whole number of column tiles and of pairs of row blocks of the padded
  // grid, so that tiles, blocks and their two colours fall on the same
  // cells (lattice_sweep.hpp), and it leaves enough empty cells around the
  // particles that every read past them (a pair's far end, a SIMD step's
  // spare lanes, the wrap into the next row) lands on an empty cell as in
  // the whole grid.
  spacing_ = dx;
  dilatation_coefficient_ = model.dilatation_coefficient;
  unit_area_ = dx * dx / damage_units_per_cell;
  long first_column = nx, last_column = -1, first_row = level.ny, last_row = -1;  // of the local particles
  for (std::size_t i = 0; i < n; ++i)
    if (on_level(i)) {
      first_column = std::min(first_column, col(i)), last_column = std::max(last_column, col(i));
      first_row = std::min(first_row, row(i)), last_row = std::max(last_row, row(i));
    }
  if (last_column < 0) first_column = last_column = first_row = last_row = 0;
  const long column_margin = 2 * halo_ + lanes, row_margin = halo_ + 1;
  const long column_align = tile_steps * lanes, row_align = 2 * std::max(1L, halo_);
  // In cells of the padded grid (column c of the level is padded column c + halo).
  const long window_column = std::max(0L, first_column + halo_ - column_margin) / column_align * column_align;
  const long window_row = std::max(0L, first_row + halo_ - row_margin) / row_align * row_align;
  row_length_ = (last_column + halo_ + column_margin + 1 - window_column + lanes - 1) / lanes * lanes;
  // Rows of an odd number of 64-byte cache lines (16 floats). A row of a
  // power of two's worth of bytes put the stencil's rows into the same cache
  // sets: 1024 cells (4 kB of floats), as a 50 mm plate at dx = 0.05 mm has,
  // halved the sweep's throughput (docs/performance.md, "Row length").
  constexpr long line_cells = 64 / sizeof(Real);
  static_assert(line_cells % lanes == 0, "a cache line holds whole SIMD steps");
  row_length_ = (row_length_ + line_cells - 1) / line_cells * line_cells;
  if ((row_length_ / line_cells) % 2 == 0) row_length_ += line_cells;
  const long grid_rows = std::min(level.ny + 2 * halo_, last_row + halo_ + row_margin + 1) - window_row;
  if (static_cast<std::int64_t>(grid_rows + 1) * row_length_ >= std::numeric_limits<GridCell>::max())
    throw Error("lattice kernel: a grid of " + std::to_string(grid_rows) + " x " + std::to_string(row_length_) +
                " cells is more than 32-bit cell indices hold (2^31 - 2 cells)");
  const auto grid = [&](long c, long r) {
    return static_cast<GridCell>((r + halo_ - window_row) * row_length_ + (c + halo_ - window_column));
  };
  cell_of_.assign(n, -1);
  for (std::size_t i = 0; i < n; ++i)
    if (on_level(i)) cell_of_[i] = grid(col(i), row(i));

  // Pair constants (single precision for the sweep, double for energies).
  for (std::size_t h = 0; h < half; ++h) {
    const auto o = forward[h];
    offset_.push_back(stencil_dj_[o] * row_length_ + stencil_di_[o]);
    xi_x_.push_back(static_cast<Real>(stencil_di_[o] * dx));
    xi_y_.push_back(static_cast<Real>(stencil_dj_[o] * dx));
    rest_.push_back(static_cast<Real>(rest[o]));
    direction_x_.push_back(static_cast<Real>(stencil_di_[o] * dx / rest[o]));
    direction_y_.push_back(static_cast<Real>(stencil_dj_[o] * dx / rest[o]));
    half_stiffness_.push_back(static_cast<Real>(0.5 * stiffness_ref[o]));
    pair_stiffness_.push_back(stiffness_ref[o]);
    critical_extension_.push_back(static_cast<Real>(model.critical_stretch * rest[o]));
    weight_units_.push_back(static_cast<std::uint32_t>(std::lround(level.phi[o] * damage_units_per_cell)));
    family_units_ += 2 * weight_units_.back();
  }

  // Lattice particles: the squares with stencil families, less those that
  // leave the lattice below.
  // With dual horizons a stencil square at another horizon than the
  // stencil's (a smoothed horizon, theory.md Sec. 7) has other constants:
  // it leaves at once, and its bonds are checked as any general particle's.
  dual_horizon_ = static_cast<bool>(model.dual_horizon_rows);
  entries_per_pair_ = dual_horizon_ ? 2 : 1;
  // On a process of a distributed run they were chosen on the whole plate
  // or the slab's band: the checks need every family, and a ghost's is not
  // local.
  std::vector<std::uint8_t> event_verdicts;  // earlier_verdicts (level 0's kernel at a refinement event)
  if (subdomain) {
    if (subdomain->is_lattice.size() != n)
      throw Error("lattice kernel: the subdomain's lattice particles do not fit its particle set");
    is_lattice_ = subdomain->is_lattice;
    for (std::uint32_t i = 0; i < owned_count_; ++i)
      moved_off_ += families.on_stencil[i] && families.level[i] == swept && !is_lattice_[i] ? 1 : 0;
  } else {
    // At a refinement event, every level's membership of the squares the
    // event left alone comes from the set before it (theory.md Sec. 8.9):
    // level 0's kernel finds it once for all levels.
    if (!finer_level && model.earlier_membership)
      event_verdicts = earlier_verdicts(families, run_bonds.energy_weight, *model.earlier_membership);
    const std::vector<std::uint8_t>* verdict =
        finer_level ? earlier_verdict : event_verdicts.empty() ? nullptr : &event_verdicts;
    // A finer level's square decided again that a particle off the level's
    // grid holds a bond into leaves in the one-way check whatever its family
    // is: no pair of the sweep computes that bond. Its set test is skipped.
    // The check's verdicts are the same (theory.md Sec. 8.9): they are the
    // largest set of the squares put on the sweep that no particle off it
    // takes off, and such a square is in no such set (its holder is never
    // on the sweep), so leaving it off from the start removes nothing else.
    // (Nor is it counted as taken off: its family is not looked at.)
    std::vector<std::uint8_t> held_from_off_grid;
    std::vector<std::uint32_t> near_decided_again;  // particles_near_decided_again's search, found once
    const double longest_bond = model.earlier_membership ? model.earlier_membership->longest_bond : 0.0;
    if (finer_level && verdict)
      held_from_off_grid = squares_held_from_off_grid(families, *verdict, p, longest_bond, near_decided_again);
    is_lattice_.assign(n, 0);
    for (std::uint32_t i = 0; i < n; ++i) {
      is_lattice_[i] = families.on_stencil[i] && families.level[i] == swept;
      if (is_lattice_[i] && dual_horizon_ && !same_horizon(p.horizon[i], model.stencil_horizon))
        is_lattice_[i] = 0, ++moved_off_;
      else if (families.level[i] == swept && cell_of_[i] >= 0 &&
               same_horizon(p.horizon[i], model.stencil_horizon)) {
        // A square the refinement event left alone keeps its membership.
        const auto earlier = verdict ? (*verdict)[i] : decide_again;
        if (!decided_again(earlier)) {
          is_lattice_[i] = earlier;
          ++membership_taken_over_;
        } else if (finer_level && !is_lattice_[i]) {
          is_lattice_[i] = earlier == decide_again_family_fits ||
                           ((held_from_off_grid.empty() || !held_from_off_grid[i]) &&
                            family_is_stencil(i, families, run_bonds.lambda, model, rest, forward, backward));
        }
      }
    }
    leave_lattice_where_pairs_differ(families, run_bonds.lambda, model, rest, forward, backward, p, verdict,
                                     held_from_off_grid.empty() ? nullptr : &near_decided_again);
    if (!finer_level && membership_taken_over_ > 0) taken_over_by_level_ = {membership_taken_over_};
  }
  if (choice_only) return;
  for (std::uint32_t i = 0; i < owned_count_; ++i) owned_lattice_count_ += is_lattice_[i];

  // Border and general particles; the general particles' own table of their
  // bonds to general particles. On one process a particle holding a bond
  // into a lattice particle, or held by one, is a square of this level at
  // a stencil step from it that holds the mirror bond
  // (leave_lattice_where_pairs_differ takes the lattice particle off
  // otherwise): the border particles are among this level's squares, and
  // the sweep reads the lattice and border particles only. A process of a
  // distributed run took its lattice from the whole plate, where a ghost's
  // lattice neighbour may not be local: it looks at every family.
  const bool border_among_squares = !subdomain;
  std::vector<std::uint8_t> read_by_sweep(n, 0);
  for (std::uint32_t i = 0; i < n; ++i) {
    if (!is_lattice_[i]) continue;
    particle_.push_back(i);
    particle_cell_.push_back(cell_of_[i]);
    read_by_sweep[i] = 1;
    if (!border_among_squares) families.for_each_bond(i, [&](const BondRef& b) { read_by_sweep[b.neighbor] = 1; });
  }
  if (particle_.empty()) {  // every square left: the neighbour lists do all
    without_lattice();
    return;
  }
  for (std::uint32_t i = 0; i < n; ++i) {
    if (is_lattice_[i] || (border_among_squares && cell_of_[i] < 0)) continue;
    bool border = false;
    double lattice_area = 0;
    families.for_each_bond(i, [&](const BondRef& b) {
      if (!is_lattice_[b.neighbor]) return;
      border = true;
      // (Its damage weight only: not the whole constants, model.bond_constants.)
      lattice_area += static_cast<double>(bond_damage_weight(p, b));
    });
    if (border) border_.push_back(i), border_cell_.push_back(cell_of_[i]), border_lattice_area_.push_back(lattice_area);
    if (border) read_by_sweep[i] = 1;
  }
  if (!finer_level) {
    // The finer levels' sweeps; the general particles are those of no sweep.
    if (model.at_level_horizon && !subdomain) {
      for (std::size_t l = 1; l < families.levels.size(); ++l) {
        if (!(families.levels[l].horizon > 0) || families.levels[l].size() == 0) continue;
        LatticeModelSetup level_model = model.at_level_horizon(families.levels[l].horizon);
        // The set before the event, for its longest possible bond: the level's
        // one-way check then looks for bonds into its squares decided again
        // only near them (particles_near_decided_again), as level 0's does.
        level_model.earlier_membership = model.earlier_membership;
        LatticeKernel finer(p, run_bonds, level_model, with_damage, nullptr, nullptr, static_cast<std::uint8_t>(l),
                            event_verdicts.empty() ? nullptr : &event_verdicts);
        if (finer.membership_taken_over_ > 0) {
          taken_over_by_level_.resize(l + 1, 0);
          taken_over_by_level_[l] = finer.membership_taken_over_;
        }
        if (!finer.empty()) finer_.push_back(std::move(finer));
      }
    }
    if (!finer_.empty()) {
      sweep_index_.assign(n, no_sweep);
      for (std::uint32_t i = 0; i < n; ++i)
        if (is_lattice_[i]) sweep_index_[i] = 0;
      for (std::size_t l = 0; l < finer_.size(); ++l)
        for (const auto i : finer_[l].particle_) {
          is_lattice_[i] = 1;  // from here on: a particle of any sweep
          sweep_index_[i] = static_cast<std::uint8_t>(l + 1);
        }
    }
    for (std::uint32_t i = 0; i < n; ++i)
      if (!is_lattice_[i]) general_.push_back(i);
    make_general_table(p, run_bonds, model, with_damage);
  }
  for (std::uint32_t i = 0; i < n; ++i)
    if (read_by_sweep[i]) grid_particle_.push_back(i), grid_cell_.push_back(cell_of_[i]);
  // These lists grew by doubling and are kept for the whole run: no spare capacity.
  for (auto* v : {&particle_, &general_, &border_, &grid_particle_}) v->shrink_to_fit();
  for (auto* v : {&particle_cell_, &border_cell_, &grid_cell_}) v->shrink_to_fit();
  border_lattice_area_.shrink_to_fit();

  // Row spans: a row visits its lattice cells and every cell a forward offset
  // links to one (lattice cells of the next `halo` rows, shifted by up to `halo`).
  std::vector<long> first_col(static_cast<std::size_t>(grid_rows), row_length_), last_col(static_cast<std::size_t>(grid_rows), -1);
  for (auto c : particle_cell_) {
    const auto r = static_cast<std::size_t>(c / row_length_);
    const long g = static_cast<long>(c % row_length_);
    first_col[r] = std::min(first_col[r], g);
    last_col[r] = std::max(last_col[r], g);
  }
  rows_.resize(static_cast<std::size_t>(grid_rows));
  std::uint64_t state_bytes = 0;
  for (long r = 0; r < grid_rows; ++r) {
    long lo = row_length_, hi = -1;
    for (long q = r; q <= std::min(grid_rows - 1, r + halo_); ++q)
      if (last_col[static_cast<std::size_t>(q)] >= 0)
        lo = std::min(lo, first_col[static_cast<std::size_t>(q)] - halo_),
        hi = std::max(hi, last_col[static_cast<std::size_t>(q)] + halo_);
    auto& span = rows_[static_cast<std::size_t>(r)];
    span.first_state = state_bytes;
    if (hi < 0) continue;
    lo = lo / lanes * lanes;
    span.first_cell = r * row_length_ + lo;
    span.steps = (hi + 1 - lo + lanes - 1) / lanes;
    state_bytes += static_cast<std::uint64_t>(span.steps) * half * lanes;
  }
  block_rows_ = static_cast<std::size_t>(std::max(1L, halo_));
  if (with_damage) state_bits_.assign(state_bytes / lanes, std::uint8_t{0xff});

  // One extra row: forward offsets of the last rows read past the grid's end.
  const std::size_t cells = static_cast<std::size_t>(row_length_ * (grid_rows + 1));
  ux_.assign(cells, Real(0));
  uy_.assign(cells, Real(0));
  lambda_.assign(cells, Real(0));
  lattice_mask_.assign(cells, Real(0));
  for (auto c : particle_cell_) lattice_mask_[static_cast<std::size_t>(c)] = Real(1);
  allocate_step_sums();
  if (with_damage) broken_units_.assign(cells, 0);
  particle_at_.assign(cells, Families::none);
  owned_grid_entries_ = 0;
  for (std::size_t g = 0; g < grid_particle_.size(); ++g) {
    lambda_[static_cast<std::size_t>(grid_cell_[g])] = static_cast<Real>(run_bonds.lambda[grid_particle_[g]]);
    particle_at_[static_cast<std::size_t>(grid_cell_[g])] = grid_particle_[g];
    if (grid_particle_[g] < owned_count_) ++owned_grid_entries_;
  }
}

void LatticeKernel::make_general_table(const ParticleSet& p, const BondSetup& run_bonds,
                                       const LatticeModelSetup& model, bool with_damage) {
  const auto both_general = [&](std::uint32_t i, std::uint32_t j) { return !is_lattice_[i] && !is_lattice_[j]; };
  general_bonds_ = dual_horizon_ ? model.dual_horizon_rows(is_lattice_, &general_intact_)
                                 : bond_table(p, run_bonds, model.bond_constants, model.critical_stretch, with_damage,
                                              &general_intact_, both_general);
  if (!with_damage) general_intact_.clear();
  // Dual horizons: a bond-based model's rows (a state-based model's carry
  // dilatation weights, and its pre-pass reads them row by row).
  if (model.general_pairs_in_float) {
    if (!dual_horizon_)
      make_general_pairs(with_damage);
    else if (general_bonds_.volume_over_length.empty())
      make_dual_horizon_pairs(with_damage);
  }
  // Dual-horizon rows cover the general particles' bonds among themselves:
  // a border particle's family area also holds its pairs with lattice
  // particles, each a bond and its dual bond (two entries of a whole row).
  if (dual_horizon_ && with_damage) {
    for (std::size_t q = 0; q < border_.size(); ++q)
      general_bonds_.family_area[border_[q]] += entries_per_pair_ * border_lattice_area_[q];
    for (const auto& finer : finer_)
      for (std::size_t q = 0; q < finer.border_.size(); ++q)
        general_bonds_.family_area[finer.border_[q]] += entries_per_pair_ * finer.border_lattice_area_[q];
  }
}

void LatticeKernel::take_every_particle_as_general(const ParticleSet& p, const BondSetup& run_bonds,
                                                   const LatticeModelSetup& model, bool with_damage) {
  // Whatever the set-up had chosen goes: no lattice particle, no cell read
  // by a sweep (rows_ stays empty, so every sweep and pass over the grid
  // is a loop of no steps), every bond in the general particles' table.
  const std::size_t n = p.size();
  dual_horizon_ = static_cast<bool>(model.dual_horizon_rows);
  entries_per_pair_ = dual_horizon_ ? 2 : 1;
  is_lattice_.assign(n, 0);
  cell_of_.assign(n, -1);
  particle_.clear();
  particle_cell_.clear();
  border_.clear();
  border_cell_.clear();
  border_lattice_area_.clear();
  grid_particle_.clear();
  grid_cell_.clear();
  rows_.clear();
  state_bits_.clear();
  for (auto* v : {&xi_x_, &xi_y_, &rest_, &half_stiffness_, &critical_extension_, &direction_x_, &direction_y_})
    v->clear();
  offset_.clear();
  pair_stiffness_.clear();
  weight_units_.clear();
  family_units_ = 0;
  owned_lattice_count_ = 0;
  general_.resize(n);
  for (std::uint32_t i = 0; i < n; ++i) general_[i] = i;
  make_general_table(p, run_bonds, model, with_damage);
}

void LatticeKernel::make_general_pairs(bool with_damage) {
  // Each bond i -> j of the table is a pair's first direction unless the
  // pair was made from j's row already (its bond j -> i came first). The
  // reverse bond, if any, is looked up in j's row (a family, tens of bonds).
  const BondTable& t = general_bonds_;
  auto& g = general_pairs_;
  g = GeneralPairs();
  if (t.size() == 0) return;
  if (t.size() >= 0x7fffffffu) return;  // slots are 32-bit: such a table stays on the double lists
  g.slot.assign(t.size(), none);
  // The pairs counted first, so that their arrays are allocated once at their size (peak memory).
  std::size_t pair_count = 0;
  for (const auto i : general_)
    for (auto b = t.offsets[i]; b < t.offsets[i + 1]; ++b) {
      if (g.slot[b] != none) continue;
      ++pair_count;
      const auto j = t.neighbor[b];
      for (auto c = t.offsets[j]; c < t.offsets[j + 1]; ++c)
        if (t.neighbor[c] == i) {
          g.slot[c] = 0;  // a mark: the reverse direction of a counted pair
          break;
        }
    }
  std::fill(g.slot.begin(), g.slot.end(), none);
  const std::size_t padded = (pair_count + 7) / 8 * 8;
  for (auto* v : {&g.first, &g.second}) v->reserve(padded);
  for (auto* v : {&g.xi_x, &g.xi_y, &g.rest}) v->reserve(padded);
  for (auto* v : {&g.stiffness_first, &g.stiffness_second}) v->reserve(padded);
  // The pairs of two owned particles first, then those with a ghost end (a
  // distributed run evaluates the first while the ghosts' values travel).
  // Each pair keeps the orientation and constants it has on one process, and
  // the ends' sums read their slots in row order, so the order of the pairs
  // changes no number. One process: the second pass finds nothing.
  std::size_t owned_pairs = 0;
  for (const bool owned_ends : {true, false}) {
  for (const auto i : general_) {
    for (auto b = t.offsets[i]; b < t.offsets[i + 1]; ++b) {
      if (g.slot[b] != none) continue;
      const auto j = t.neighbor[b];
      if ((i < owned_count_ && j < owned_count_) != owned_ends) continue;
      std::uint64_t reverse = none;
      for (auto c = t.offsets[j]; c < t.offsets[j + 1]; ++c)
        if (t.neighbor[c] == i) {
          reverse = c;
          break;
        }
      g.first.push_back(i);
      g.second.push_back(j);
      g.xi_x.push_back(t.xi_x[b]);
      g.xi_y.push_back(t.xi_y[b]);
      g.rest.push_back(static_cast<Real>(t.rest_length[b]));
      g.stiffness_first.push_back(static_cast<Real>(t.stiffness[b]));
      g.stiffness_second.push_back(reverse != none ? static_cast<Real>(t.stiffness[reverse]) : Real(0));
      // The ends' slots, numbered as if unpadded for now (renumbered below).
      g.slot[b] = 2 * static_cast<std::uint32_t>(g.first.size() - 1);
      if (reverse != none) g.slot[reverse] = g.slot[b] + 1;
    }
  }
  if (owned_ends) owned_pairs = g.first.size();
  }
  g.pairs = g.first.size();
  pad_general_pairs();
  g.owned_groups = static_cast<std::int64_t>(owned_pairs == g.pairs ? g.padded / 8 : owned_pairs / 8);
  g.critical_stretch = static_cast<Real>(t.critical_stretch);
  allocate_step_sums();  // (the pairs' values)
  if (with_damage) {
    g.damage.assign(general_.size(), 0.0);
    g.row_changed.assign(is_lattice_.size(), 0);
    take_general_pair_states();
  }
}

namespace {
// make_dual_horizon_pairs' mark of an entry that reads no value (before the slots are numbered).
constexpr std::uint32_t reads_zero = none - 1;
}  // namespace

void LatticeKernel::pad_general_pairs() {
  // Padding to whole groups of 8: pairs of a particle with itself along a
  // unit rest vector with zero constants (finite, no force, never intact).
  auto& g = general_pairs_;
  g.padded = (g.pairs + 7) / 8 * 8;
  const std::uint32_t pad_particle = general_.front();
  const bool dual = !g.reaction_first.empty() || !g.entry_direction.empty();
  for (std::size_t p = g.pairs; p < g.padded; ++p) {
    g.first.push_back(pad_particle);
    g.second.push_back(pad_particle);
    g.xi_x.push_back(Real(1));
    g.xi_y.push_back(Real(0));
    g.rest.push_back(Real(1));
    g.stiffness_first.push_back(Real(0));
    g.stiffness_second.push_back(Real(0));
    if (!dual) continue;
    for (auto* v : {&g.reaction_first, &g.reaction_second, &g.critical_extension_forward,
                    &g.critical_extension_backward})
      v->push_back(Real(0));
  }
  // The ends' slots were numbered 2 p (first end) and 2 p + 1 (second end).
  for (auto& s : g.slot)
    if (s == reads_zero)
      s = g.zero_slot();
    else if (s != none)
      s = (s % 2 == 0) ? s / 2 : static_cast<std::uint32_t>(g.padded) + s / 2;
}

void LatticeKernel::make_dual_horizon_pairs(bool with_damage) {
  // The entries of a pair {i, j} (i < j): in i's row the own entry of
  // i -> j and the dual entry of j -> i, in j's row the own entry of j -> i
  // and the dual entry of i -> j, each present where its bond is (or one
  // combined entry per row): both rows hold an entry of the pair. Rows
  // visited in ascending order make each pair from i's row, so that the
  // pairs follow i's row and i's entries come before j's, and j's row finds
  // it in the list of the pairs made towards j, without a search.
  const BondTable& t = general_bonds_;
  auto& g = general_pairs_;
  g = GeneralPairs();
  const std::size_t n = t.particle_count;
  if (t.size() == 0 || general_.empty()) return;
  if (t.size() >= 0x7fffffffu) return;  // slots are 32-bit: such a table stays on the rows
  // On a process of a distributed run the rows are the owned particles'
  // (a ghost's row is empty): a pair with a ghost end is made from its
  // owned end's row, which holds all that end receives (its own bond's
  // stiffness, the reaction of the ghost's bond, both critical extensions);
  // the ghost's end gets nothing, as its results are discarded. A table
  // whose ghost rows hold entries stays on the rows.
  for (std::size_t i = owned_count_; i < n; ++i)
    if (t.offsets[i + 1] != t.offsets[i]) return;
  const std::uint32_t owned_count = static_cast<std::uint32_t>(owned_count_);
  // Every pair has an entry in each row, but for a ghost's: at most half as
  // many pairs as entries, and one more per entry towards a ghost (the
  // arrays are cut to the pairs made below).
  std::size_t towards_ghosts = 0;
  for (std::size_t e = 0; e < t.size(); ++e) towards_ghosts += t.neighbor[e] >= owned_count ? 1 : 0;
  const std::size_t most = (t.size() + towards_ghosts) / 2 + 8;
  // The ends and the geometry are written when a pair is made (not zeroed
  // first); the stiffnesses are sums over entries and an absent direction's
  // critical extension stays 0.
  for (auto* v : {&g.first, &g.second}) v->resize(most);
  for (auto* v : {&g.xi_x, &g.xi_y, &g.rest}) v->resize(most);
  for (auto* v : {&g.stiffness_first, &g.stiffness_second, &g.reaction_first, &g.reaction_second,
                  &g.critical_extension_forward, &g.critical_extension_backward})
    v->assign(most, Real(0));
  // Where an entry's stiffness goes, by its end: an own entry carries its
  // row's bond, a dual entry the neighbour's (the row's end's reaction).
  Real* const own_stiffness[2] = {g.stiffness_first.data(), g.stiffness_second.data()};
  Real* const dual_stiffness[2] = {g.reaction_first.data(), g.reaction_second.data()};
  Real* const critical[2] = {g.critical_extension_forward.data(), g.critical_extension_backward.data()};
  g.slot.assign(t.size(), none);
  g.entry_direction.assign(t.size(), 0);
  std::vector<std::uint8_t> ends_read(most, 0);  // per pair: bit e set once end e's first entry took the value
  // The pairs made towards j by smaller ends, at most one per entry of j's
  // row: kept at j's offsets.
  UninitialisedVector<std::uint32_t> made_towards(t.size());  // (each read after it is written)
  std::vector<std::uint32_t> made_towards_count(n, 0);
  // pair_with[j] while row i is visited: for j < i the pair of j and i; for
  // j > i the pair made in i's row, numbered from first_of_row on (a smaller
  // number is an earlier row's: no pair of i and j yet).
  std::vector<std::uint32_t> pair_with(n, none);
  std::uint32_t pairs = 0;
  // By local pointers: the loop's byte stores (ends_read) may alias any
  // member's address, which it would otherwise load again after every store.
  const std::uint64_t* const offsets = t.offsets.data();
  const std::uint64_t* const dual_begin = t.dual_begin.data();
  const std::uint32_t* const neighbor = t.neighbor.data();
  const double* const entry_stiffness = t.stiffness.data();
  const double* const entry_critical_extension = t.critical_extension.data();
  const float* const entry_xi_x = t.xi_x.data();
  const float* const entry_xi_y = t.xi_y.data();
  const double* const entry_rest = t.rest_length.data();
  const std::uint8_t* const halves = t.entry_halves.empty() ? nullptr : t.entry_halves.data();
  std::uint32_t* const first = g.first.data();
  std::uint32_t* const second = g.second.data();
  Real* const xi_x = g.xi_x.data();
  Real* const xi_y = g.xi_y.data();
  Real* const rest = g.rest.data();
  std::uint32_t* const slot = g.slot.data();
  std::uint32_t* const entry_direction = g.entry_direction.data();
  std::uint8_t* const ends_read_bits = ends_read.data();
  std::uint32_t* const towards_list = made_towards.data();
  std::uint32_t* const towards_count = made_towards_count.data();
  std::uint32_t* const pair_with_particle = pair_with.data();
  for (const auto i : general_) {
    const std::uint32_t first_of_row = pairs;
    const std::uint32_t* const towards = towards_list + offsets[i];
    for (std::uint32_t k = 0; k < towards_count[i]; ++k) pair_with_particle[first[towards[k]]] = towards[k];
    // The entries [from, to) of i's row; `own`: they carry i's bonds (backward at the second end).
    const auto take_entries = [&](std::uint64_t from, std::uint64_t to, bool own) {
      Real* const* const stiffness = own ? own_stiffness : dual_stiffness;
      for (auto b = from; b < to; ++b) {
        const std::uint32_t j = neighbor[b];
        const unsigned end = j < i ? 1u : 0u;  // which end of the pair the row is
        std::uint32_t p = pair_with_particle[j];
        if (end == 0 && (p == none || p < first_of_row)) {
          // j's row holds an entry of each pair made towards it, so its
          // list fits there (and the pairs fit `most`); a table without
          // that mirror would overrun it: refused, not written past. A
          // ghost's empty row reads no list (a ghost comes after every
          // owned particle: j > i).
          const bool ghost = j >= owned_count;
          if (!ghost && towards_count[j] == offsets[j + 1] - offsets[j]) broken_mirror(i, j);
          p = pair_with_particle[j] = pairs++;
          first[p] = i;
          second[p] = j;
          xi_x[p] = entry_xi_x[b];
          xi_y[p] = entry_xi_y[b];
          rest[p] = static_cast<Real>(entry_rest[b]);
          if (!ghost) towards_list[offsets[j] + towards_count[j]++] = p;
        }
        if (end == 1 && p == none) broken_mirror(i, j);
        const unsigned backward = own ? end : 1u - end;
        stiffness[end][p] += static_cast<Real>(entry_stiffness[b]);
        const auto extension = static_cast<Real>(entry_critical_extension[b]);
        critical[backward][p] = extension;
        // A combined entry also holds the reverse bond (the same critical extension).
        if (halves && halves[b] == 2) critical[1u - backward][p] = extension;
        entry_direction[b] = 2 * p + backward;
        // The first of the row's entries of a pair reads the end's value.
        const auto bit = static_cast<std::uint8_t>(1u << end);
        slot[b] = (ends_read_bits[p] & bit) == 0 ? 2 * p + end : reads_zero;
        ends_read_bits[p] = static_cast<std::uint8_t>(ends_read_bits[p] | bit);
      }
    };
    take_entries(offsets[i], dual_begin[i], true);
    take_entries(dual_begin[i], offsets[i + 1], false);
  }
  // Both rows of every pair read it, but for a ghost's (checked once here, not per entry).
  std::uint32_t owned_pairs = 0;
  for (std::uint32_t p = 0; p < pairs; ++p) {
    const bool ghost_end = g.second[p] >= owned_count;
    if (ends_read[p] != (ghost_end ? 1 : 3)) broken_mirror(g.first[p], g.second[p]);
    owned_pairs += ghost_end ? 0 : 1;
  }
  for (auto* v : {&g.first, &g.second}) v->resize(pairs);
  for (auto* v : {&g.xi_x, &g.xi_y, &g.rest}) v->resize(pairs);
  for (auto* v : {&g.stiffness_first, &g.stiffness_second, &g.reaction_first, &g.reaction_second,
                  &g.critical_extension_forward, &g.critical_extension_backward})
    v->resize(pairs);
  // The pairs of two owned particles first, then those with a ghost end (a
  // distributed run evaluates the first while the ghosts' values travel),
  // each in the order made. The ends' sums read their slots in row order,
  // so the order of the pairs changes no number. One process: all owned.
  if (owned_pairs < pairs) {
    std::vector<std::uint32_t> moved_to(pairs);
    std::uint32_t next_owned = 0, next_ghost = owned_pairs;
    for (std::uint32_t p = 0; p < pairs; ++p) moved_to[p] = g.second[p] < owned_count ? next_owned++ : next_ghost++;
    const auto move = [&](auto& v) {
      std::vector<std::decay_t<decltype(v[0])>> was(v.begin(), v.end());
      for (std::uint32_t p = 0; p < pairs; ++p) v[moved_to[p]] = was[p];
    };
    move(g.first), move(g.second), move(g.xi_x), move(g.xi_y), move(g.rest);
    for (auto* v : {&g.stiffness_first, &g.stiffness_second, &g.reaction_first, &g.reaction_second,
                    &g.critical_extension_forward, &g.critical_extension_backward})
      move(*v);
    // Slots 2 p + end and directions 2 p + backward follow their pairs.
    for (auto& s : g.slot)
      if (s != none && s != reads_zero) s = 2 * moved_to[s / 2] + s % 2;
    for (auto& d : g.entry_direction) d = 2 * moved_to[d / 2] + d % 2;
  }
  g.pairs = pairs;
  pad_general_pairs();
  g.owned_groups = static_cast<std::int64_t>(owned_pairs == pairs ? g.padded / 8 : owned_pairs / 8);
  allocate_step_sums();  // (the pairs' values)
  if (with_damage) {
    g.damage.assign(general_.size(), 0.0);
    g.row_changed.assign(n, 0);
    take_general_pair_states();
  }
}

void LatticeKernel::release_general_pairs() { general_pairs_ = GeneralPairs(); }

void LatticeKernel::take_general_pair_states() {
  // A pair is intact when every direction of it in the table is (a bond cut
  // by a pre-crack is cut both ways; a pair broken in the run, both ways).
  auto& g = general_pairs_;
  if (g.padded == 0 || general_intact_.empty()) return;
  if (g.entry_direction.empty()) {
    std::vector<std::uint8_t> intact(g.padded, 0);
    std::fill(intact.begin(), intact.begin() + static_cast<std::ptrdiff_t>(g.pairs), std::uint8_t(1));
    for (std::size_t b = 0; b < g.slot.size(); ++b)
      if (g.slot[b] != none) intact[g.pair_of(g.slot[b])] &= general_intact_[b];
    g.intact_bits.assign(g.padded / 8, 0);
    for (std::size_t p = 0; p < g.padded; ++p)
      g.intact_bits[p / 8] |= static_cast<std::uint8_t>(intact[p] << (p % 8));
  } else {
    // Dual horizons: each direction on its own, intact while every entry
    // carrying it is (its own entry and its dual entry break together; a
    // combined entry carries both directions). An absent direction stays 0.
    // Per direction 2 p + backward: bit 0 an entry carries it, bit 1 one of them is broken.
    std::vector<std::uint8_t> seen_vector(2 * g.padded, 0);
    const BondTable& t = general_bonds_;
    // By local pointers: a byte store may alias any member's address, which
    // the loops would otherwise load again after every store.
    std::uint8_t* const seen = seen_vector.data();
    const std::uint32_t* const direction = g.entry_direction.data();
    const std::uint8_t* const intact = general_intact_.data();
    const std::uint8_t* const halves = t.entry_halves.empty() ? nullptr : t.entry_halves.data();
    const std::size_t entries = g.entry_direction.size();
    for (std::size_t b = 0; b < entries; ++b) {
      const std::uint32_t d = direction[b];
      const auto entry = static_cast<std::uint8_t>(intact[b] ? 1u : 3u);
      seen[d] |= entry;
      if (halves && halves[b] == 2) seen[d ^ 1u] |= entry;
    }
    // Each group's two bytes made whole, then stored (every byte written).
    const std::size_t groups = g.padded / 8;
    g.intact_bits.resize(groups);
    g.backward_intact_bits.resize(groups);
    std::uint8_t* const forward_bits = g.intact_bits.data();
    std::uint8_t* const backward_bits = g.backward_intact_bits.data();
    for (std::size_t q = 0; q < groups; ++q) {
      const std::uint8_t* const group = seen + 16 * q;
      unsigned forward = 0, backward = 0;
      for (unsigned k = 0; k < 8; ++k) {
        forward |= (group[2 * k] == 1 ? 1u : 0u) << k;
        backward |= (group[2 * k + 1] == 1 ? 1u : 0u) << k;
      }
      forward_bits[q] = static_cast<std::uint8_t>(forward);
      backward_bits[q] = static_cast<std::uint8_t>(backward);
    }
  }
  g.states_changed = 1;  // the next gather copies the states and the damage from them
}

std::vector<std::uint8_t> LatticeKernel::earlier_verdicts(const Families& families,
                                                          const PerBond<double>& energy_weight,
                                                          const EarlierLatticeMembership& earlier) {
  // A square of any level keeps the earlier set's verdict when the event
  // changed nothing it depends on (theory.md Sec. 8.9): its own family (the
  // split copied it: the same members in the same cells with the same
  // partial volumes, weights and horizons), the bonds into it (every
  // particle holding one kept its family, and no parent held one), the
  // squares at its stencil steps (no child is new there, no parent left
  // there), and its level's stencil with its weights. Decided again: the
  // children, every member of a family the split built, of a parent's
  // family and the squares around a child or a parent.
  const std::size_t n = families.particle_count;
  const Families& before = *earlier.families;
  const auto& origin = *earlier.origin;
  const auto& same_family = *earlier.same_family;
  if (origin.size() != n || same_family.size() != n || earlier.is_lattice->size() != before.particle_count)
    return {};
  std::vector<std::uint8_t> verdict(n, decide_again);
  // The levels whose lattice, stencil and stencil weights are the earlier set's.
  std::vector<std::uint8_t> same_level(families.levels.size(), 0);
  for (std::size_t l = 0; l < families.levels.size() && l < before.levels.size(); ++l) {
    const StencilLevel &a = families.levels[l], &b = before.levels[l];
    same_level[l] = families.xmin == before.xmin && families.ymin == before.ymin && a.spacing == b.spacing &&
                    a.horizon == b.horizon && a.nx == b.nx && a.ny == b.ny && a.di == b.di && a.dj == b.dj &&
                    a.phi == b.phi && l < energy_weight.stencil.size() &&
                    l < earlier.energy_weight->stencil.size() &&
                    energy_weight.stencil[l] == earlier.energy_weight->stencil[l];
  }
  for (std::uint32_t i = 0; i < n; ++i) {
    const auto l = families.level[i];
    if (l != Families::no_level && l < same_level.size() && same_level[l] && origin[i] != Families::none &&
        same_family[i] != Families::none)
      verdict[i] = (*earlier.is_lattice)[origin[i]];
  }
  // The squares at the stencil steps of a square at `cell` of level l (the
  // stencil is symmetric: those whose stencil holds it), of this set.
  const auto decide_around = [&](std::uint8_t l, std::int64_t cell) {
    if (l == Families::no_level || l >= families.levels.size() || cell < 0) return;
    const StencilLevel& level = families.levels[l];
    const long ci = static_cast<long>(cell % level.nx), ri = static_cast<long>(cell / level.nx);
    for (std::size_t o = 0; o < level.size(); ++o) {
      const long c = ci + level.di[o], r = ri + level.dj[o];
      if (c < 0 || c >= level.nx || r < 0 || r >= level.ny) continue;
      const auto j = level.at_cell[static_cast<std::size_t>(r * level.nx + c)];
      if (j != Families::none) verdict[j] = decide_again;
    }
  };
  std::vector<std::uint32_t> now_of(before.particle_count, Families::none);  // the earlier set's particle now
  for (std::uint32_t i = 0; i < n; ++i)
    if (origin[i] != Families::none) now_of[origin[i]] = i;
  for (std::uint32_t i = 0; i < n; ++i) {
    if (origin[i] != Families::none && same_family[i] != Families::none) continue;
    verdict[i] = decide_again;
    families.for_each_bond(i, [&](const BondRef& b) { verdict[b.neighbor] = decide_again; });
    if (origin[i] == Families::none) decide_around(families.level[i], families.cell[i]);  // a child
  }
  for (std::uint32_t o = 0; o < before.particle_count; ++o) {  // the parents: their families and cells
    if (now_of[o] != Families::none) continue;
    before.for_each_bond(o, [&](const BondRef& b) {
      if (now_of[b.neighbor] != Families::none) verdict[now_of[b.neighbor]] = decide_again;
    });
    // (A level whose lattice differs from the earlier set's takes no verdict over.)
    const auto l = before.level[o];
    if (l != Families::no_level && l < same_level.size() && same_level[l]) decide_around(l, before.cell[o]);
  }
  // A square decided again for its neighbourhood's sake whose own family the
  // split copied from a particle on a sweep: that family passed the set test
  // before with the same constants (by induction over the events: a verdict
  // is taken over only with the family), so only the one-way check is left.
  for (std::uint32_t i = 0; i < n; ++i) {
    const auto l = families.level[i];
    if (verdict[i] == decide_again && l != Families::no_level && l < same_level.size() && same_level[l] &&
        origin[i] != Families::none && same_family[i] != Families::none && (*earlier.is_lattice)[origin[i]])
      verdict[i] = decide_again_family_fits;
  }
  return verdict;
}

void LatticeKernel::leave_lattice_where_pairs_differ(const Families& families, const std::vector<double>& lambda,
                                                     const LatticeModelSetup& model, const std::vector<double>& rest,
                                                     const std::vector<std::size_t>& forward,
                                                     const std::vector<std::size_t>& backward,
                                                     const ParticleSet& particles,
                                                     const std::vector<std::uint8_t>* earlier_verdict,
                                                     const std::vector<std::uint32_t>* near_decided_again) {
  // The sweep computes a pair with a lattice end once, with the stencil's
  // constants, and gives its two ends equal and opposite forces. That is the
  // model only where both directions exist with those constants. A general
  // particle i and a lattice particle j fit the sweep when i is a square of
  // the lattice, j sits at a stencil step from it, the bond i -> j has the
  // pair's rest length, stiffness (surface correction included), partial
  // volume and is not cut by a pre-crack, and i holds a bond to every
  // lattice particle whose stencil holds i. Where they do not, j leaves the
  // lattice, and the neighbour lists compute each direction of each of its
  // bonds on its own (theory.md Sec. 1.6). With dual horizons i must also
  // have the stencil's horizon: then its bond to j and j's bond to i are one
  // pair of constant-horizon PD (theory.md Sec. 6.7); a particle with a
  // smaller horizon whose disk reaches j holds a one-way bond, and j leaves.
  //
  // NB-NUG grids at half-integer horizon factors need this (docs/robustness.md):
  // a free cell whose centroid lies a little inside its box holds the square
  // beyond the box edge, whose horizon only touches the cell (a one-way bond,
  // exact geometry). A square that leaves has its own bonds checked in turn;
  // they are stencil bonds and fit, so on a real grid one round settles it,
  // and the worklist visits each particle once whatever the input.
  //
  // With `earlier_verdict` (a refinement event, theory.md Sec. 8.9) the
  // squares that kept the earlier set's membership are not checked: every
  // bond into them and every square around them is as it was. A square
  // qualifies by its whole family (a finer level's by the set test, level
  // 0's by the compact families' stencil match), whose bonds all fit and
  // hold the squares around it, so one that leaves takes no other off: the
  // squares decided again are checked against the others' bonds.
  const StencilLevel& level = families.levels[swept_];
  const auto checked = [&](std::uint32_t j) {
    return !earlier_verdict || decided_again((*earlier_verdict)[j]);
  };
  const std::size_t n = families.particle_count;
  const long nx = level.nx, ny = level.ny;
  const auto col = [&](std::uint32_t i) { return static_cast<long>(families.cell[i] % nx); };
  const auto row = [&](std::uint32_t i) { return static_cast<long>(families.cell[i] / nx); };
  const auto fits = [&](std::uint32_t i, long ci, long ri, const BondRef& b) {
    return fitting_stencil_bond(families, lambda, model, rest, forward, backward, i, ci, ri, b) >= 0;
  };
  // (The squares that leave are checked in turn whatever the start: the
  // result is the same from any start that holds every particle able to
  // take a square off.)
  std::vector<std::uint32_t> unchecked, holder(n, Families::none);  // holder[j]: the last i with a bond i -> j
  if (earlier_verdict) {
    const double longest_bond = model.earlier_membership ? model.earlier_membership->longest_bond : 0.0;
    unchecked = particles_near_decided_again(families, *earlier_verdict, particles, longest_bond, near_decided_again);
  } else {
    for (std::uint32_t i = 0; i < n; ++i)
      if (!is_lattice_[i]) unchecked.push_back(i);
  }
  const auto leave = [&](std::uint32_t j) {
    is_lattice_[j] = 0;
    ++moved_off_;
    unchecked.push_back(j);
  };
  while (!unchecked.empty()) {
    const auto i = unchecked.back();
    unchecked.pop_back();
    // Whether i can be a pair's end at all (a free cell, a square of another
    // size or another horizon cannot), and its cell: once for all its bonds.
    const bool on_cell = cell_of_[i] >= 0;
    const bool may_fit = on_cell && !(dual_horizon_ && !same_horizon(particles.horizon[i], model.stencil_horizon));
    const long ci = on_cell ? col(i) : 0, ri = on_cell ? row(i) : 0;
    families.for_each_bond(i, [&](const BondRef& b) {
      if (!is_lattice_[b.neighbor] || !checked(b.neighbor)) return;
      holder[b.neighbor] = i;
      if (!may_fit || !fits(i, ci, ri, b)) leave(b.neighbor);
    });
    if (!on_cell) continue;  // off the lattice: no stencil holds it
    for (std::size_t o = 0; o < level.size(); ++o) {  // the stencil is symmetric: these hold i
      const long c = ci + level.di[o], r = ri + level.dj[o];
      if (c < 0 || c >= nx || r < 0 || r >= ny) continue;
      const auto j = level.at_cell[static_cast<std::size_t>(r * nx + c)];
      if (j != Families::none && is_lattice_[j] && holder[j] != i && checked(j)) leave(j);
    }
  }
}

std::vector<std::uint32_t> LatticeKernel::particles_near_decided_again(
    const Families& families, const std::vector<std::uint8_t>& earlier_verdict, const ParticleSet& particles,
    double longest_bond, const std::vector<std::uint32_t>* near) const {
  // A particle off the sweep takes a square j off only through a bond into
  // j or by sitting at one of j's stencil steps, and only a square decided
  // again can leave (theory.md Sec. 8.9). Those are: the squares at the
  // stencil steps of each such j (the stencil is symmetric: a square of this
  // level whose stencil holds j is at one of j's steps, and so is a square
  // of this level on its stencil that holds j), and the listed families
  // holding a bond into one. A family on the stencil of another level holds
  // only that level's squares (a lattice's cells hold squares of its level
  // alone), never one of this level.
  const StencilLevel& level = families.levels[swept_];
  const std::size_t n = families.particle_count;
  const long nx = level.nx, ny = level.ny;
  std::vector<std::uint8_t> target(n, 0), started(n, 0);
  std::vector<std::uint32_t> start;
  const auto add = [&](std::uint32_t i) {
    if (is_lattice_[i] || started[i]) return;
    started[i] = 1;
    start.push_back(i);
  };
  bool any_target = false;
  for (std::uint32_t j = 0; j < n; ++j) {
    if (!is_lattice_[j] || !decided_again(earlier_verdict[j])) continue;
    target[j] = 1;
    any_target = true;
    if (families.cell[j] < 0) continue;
    const long cj = static_cast<long>(families.cell[j] % nx), rj = static_cast<long>(families.cell[j] / nx);
    for (std::size_t o = 0; o < level.size(); ++o) {
      const long c = cj + level.di[o], r = rj + level.dj[o];
      if (c < 0 || c >= nx || r < 0 || r >= ny) continue;
      const auto i = level.at_cell[static_cast<std::size_t>(r * nx + c)];
      if (i != Families::none) add(i);
    }
  }
  if (!any_target) return start;
  // A bond into a target is at most the longest possible bond long: only the
  // particles that near one can hold it (in ascending order, as all are).
  const auto holds_bond_into_target = [&](std::uint32_t i) {
    if (is_lattice_[i] || started[i] || families.on_stencil[i]) return;
    for (auto b = families.offsets[i]; b < families.offsets[i + 1]; ++b)
      if (target[families.neighbors[b]]) {
        add(i);
        break;
      }
  };
  if (longest_bond > 0) {
    // (`near`: those of a superset of the targets, in the same order.)
    for (const auto i : near ? *near : particles_near(particles, target, longest_bond)) holds_bond_into_target(i);
  } else {
    for (std::uint32_t i = 0; i < n; ++i) holds_bond_into_target(i);
  }
  return start;
}

std::vector<std::uint8_t> LatticeKernel::squares_held_from_off_grid(const Families& families,
                                                                  const std::vector<std::uint8_t>& earlier_verdict,
                                                                  const ParticleSet& particles, double longest_bond,
                                                                  std::vector<std::uint32_t>& near) const {
  // The holders are listed families (a family on another level's stencil
  // holds squares of that level only: particles_near_decided_again) within
  // the longest possible bond of a square of this level decided again.
  const std::size_t n = families.particle_count;
  std::vector<std::uint8_t> held(n, 0), decided(n, 0);
  for (std::uint32_t j = 0; j < n; ++j) decided[j] = cell_of_[j] >= 0 && decided_again(earlier_verdict[j]);
  const auto mark_bonds = [&](std::uint32_t i) {
    if (cell_of_[i] >= 0 || families.on_stencil[i]) return;
    for (auto b = families.offsets[i]; b < families.offsets[i + 1]; ++b) held[families.neighbors[b]] = 1;
  };
  if (longest_bond > 0) {
    near = particles_near(particles, decided, longest_bond);
    for (const auto i : near) mark_bonds(i);
  } else {
    for (std::uint32_t i = 0; i < n; ++i) mark_bonds(i);
  }
  return held;
}

int LatticeKernel::stencil_step(const Families& families, long ci, long ri, std::uint32_t j) const {
  const StencilLevel& level = families.levels[swept_];
  if (cell_of_[j] < 0) return -1;  // not a square of this level
  const long di = static_cast<long>(families.cell[j] % level.nx) - ci;
  const long dj = static_cast<long>(families.cell[j] / level.nx) - ri;
  if (std::labs(di) > halo_ || std::labs(dj) > halo_) return -1;
  return pair_of_step_[static_cast<std::size_t>((dj + halo_) * (2 * halo_ + 1) + (di + halo_))];
}

long LatticeKernel::fitting_stencil_bond(const Families& families, const std::vector<double>& lambda,
                                         const LatticeModelSetup& model, const std::vector<double>& rest,
                                         const std::vector<std::size_t>& forward,
                                         const std::vector<std::size_t>& backward, std::uint32_t i, long ci, long ri,
                                         const BondRef& b) const {
  const int v = stencil_step(families, ci, ri, b.neighbor);
  return v < 0 ? -1 : fitting_stencil_step(families, lambda, model, rest, forward, backward, i, b, v);
}

long LatticeKernel::fitting_stencil_step(const Families& families, const std::vector<double>& lambda,
                                         const LatticeModelSetup& model, const std::vector<double>& rest,
                                         const std::vector<std::size_t>& forward,
                                         const std::vector<std::size_t>& backward, std::uint32_t i, const BondRef& b,
                                         int v) const {
  const StencilLevel& level = families.levels[swept_];
  const std::size_t half = offset_.size();
  const auto j = b.neighbor;
  const std::size_t h = static_cast<std::size_t>(v) % half;
  const std::size_t o = static_cast<std::size_t>(v) < half ? forward[h] : backward[h];  // the stencil bond i -> j
  const auto c = model.bond_constants(i, b);
  const bool fits = c.intact && close(c.stiffness, 0.5 * (lambda[i] + lambda[j]) * pair_stiffness_[h], 1e-6) &&
                    close(c.rest_length, rest[o], 1e-6) && close(b.partial_volume, level.phi[o], 1e-6);
  return fits ? static_cast<long>(o) : -1;
}

bool LatticeKernel::family_is_stencil(std::uint32_t i, const Families& families, const std::vector<double>& lambda,
                                      const LatticeModelSetup& model, const std::vector<double>& rest,
                                      const std::vector<std::size_t>& forward,
                                      const std::vector<std::size_t>& backward) const {
  // Every stencil bond once, each with the pair's constants: the stencil as
  // a set. First the cell steps alone, each marked in a bitmap of the
  // stencil's steps (a family of another shape fails here, before any
  // bond's constants) and kept for the constants of each bond after.
  const StencilLevel& level = families.levels[swept_];
  if (families.family_size(i) != level.size()) return false;
  const long ci = static_cast<long>(families.cell[i] % level.nx), ri = static_cast<long>(families.cell[i] / level.nx);
  std::uint64_t seen[4] = {0, 0, 0, 0};  // per step of pair_of_step_ (at most 256: larger stencils skip the bitmap)
  const bool bitmap = level.size() <= 256;
  std::uint8_t step_of_bond[256];  // the bitmap's steps, in the family's order
  std::size_t k = 0;
  bool stencil = true;
  families.for_each_bond(i, [&](const BondRef& b) {
    if (!stencil || !bitmap) return;
    const int v = stencil_step(families, ci, ri, b.neighbor);
    const std::uint64_t bit = v < 0 ? 0 : std::uint64_t{1} << (v % 64);
    stencil = v >= 0 && !(seen[v / 64] & bit);
    if (stencil) seen[v / 64] |= bit, step_of_bond[k++] = static_cast<std::uint8_t>(v);
  });
  if (!stencil) return false;
  std::vector<std::uint8_t> seen_bond(bitmap ? 0 : level.size(), 0);
  k = 0;
  families.for_each_bond(i, [&](const BondRef& b) {
    if (!stencil) return;
    const long o =
        bitmap ? fitting_stencil_step(families, lambda, model, rest, forward, backward, i, b, step_of_bond[k++])
               : fitting_stencil_bond(families, lambda, model, rest, forward, backward, i, ci, ri, b);
    stencil = o >= 0 && (bitmap || !seen_bond[static_cast<std::size_t>(o)]);
    if (stencil && !bitmap) seen_bond[static_cast<std::size_t>(o)] = 1;
  });
  return stencil;
}

void LatticeKernel::add_dilatation_weights(const ParticleSet& p, const BondSetup& setup) {
  // V_ij = phi_ij V_j D_ij, 0 across a pre-crack, and m_i = sum_j V_ij over
  // the whole family (dilatation_volume): as bond_setup.cpp's
  // add_dilatation_weights for the neighbour lists, so that both paths have
  // the same theta (theory.md Sec. 5). D_ij is 1 on every pair of the sweep
  // (a lattice particle is a stencil particle, Sec. 5.7).
  const Families& families = setup.families;
  const std::size_t n = p.size(), half = offset_.size();
  weighted_volume_.assign(n, 0.0);
  pair_volume_over_length_.assign(half, -1.0);
  // The general particles' weights in their table's order. Dual-horizon rows
  // carry theirs already (own and dual entries, variable_horizon_rows): the
  // families' bonds between general particles are only counted against the
  // rows' own entries; m_i is the whole family's here in both cases.
  auto& general_weights = general_bonds_.volume_over_length;
  std::uint64_t general_family_bonds = 0;
  if (!dual_horizon_) {
    general_weights.clear();
    general_weights.reserve(general_bonds_.size());
  }
  for (std::uint32_t i = 0; i < n; ++i)
    families.for_each_bond(i, [&](const BondRef& b) {
      const auto j = b.neighbor;
      const double volume = dilatation_volume(p, setup, i, b);
      const double rest = std::hypot(p.x[j] - p.x[i], p.y[j] - p.y[i]);
      weighted_volume_[i] += volume;
      if (!is_lattice_[i] && !is_lattice_[j]) {  // the general particles' table, in its order
        if (!dual_horizon_) general_weights.push_back(volume / rest);
        ++general_family_bonds;
        return;
      }
      // A pair of the sweep: one V/|xi| per offset for both directions (the
      // sweep adds the pair's term to both ends), as its stiffness.
      const auto step = cell_of_[j] - cell_of_[i];
      const long dj = static_cast<long>((step + halo_ + row_length_ * (halo_ + 1)) / row_length_) - (halo_ + 1);
      const long di = static_cast<long>(step - dj * row_length_);
      const int v = std::labs(di) <= halo_ && std::labs(dj) <= halo_
                        ? pair_of_step_[static_cast<std::size_t>((dj + halo_) * (2 * halo_ + 1) + (di + halo_))]
                        : -1;
      double& pair = pair_volume_over_length_[static_cast<std::size_t>(v < 0 ? 0 : v) % half];
      if (v >= 0 && pair < 0) pair = volume / rest;
      if (v < 0 || !close(pair, volume / rest, 1e-6))
        throw Error("lattice kernel: the dilatation weight of the bond " + std::to_string(i) + " -> " +
                    std::to_string(j) + " differs from its lattice partner's");
    });
  std::uint64_t general_own_entries = 0;
  for (std::size_t i = 0; i < n; ++i)
    general_own_entries += general_bonds_.own_end(i) - general_bonds_.offsets[i];
  if (general_weights.size() != general_bonds_.size() || general_own_entries != general_family_bonds)
    throw Error("lattice kernel: the general particles' table does not hold their families' bonds");
  // The general pairs' directions, and each end its own V/|xi| (they differ between free cells).
  auto& g = general_pairs_;
  g.volume_first.assign(g.padded, Real(0));
  g.volume_second.assign(g.padded, Real(0));
  for (std::size_t b = 0; b < g.slot.size(); ++b) {
    if (g.slot[b] == none) continue;
    const std::size_t pair = g.pair_of(g.slot[b]);
    (g.slot[b] >= g.padded ? g.volume_second : g.volume_first)[pair] = static_cast<Real>(general_weights[b]);
  }
  volume_over_length_.assign(half, Real(0));
  for (std::size_t h = 0; h < half; ++h)
    volume_over_length_[h] = static_cast<Real>(std::max(0.0, pair_volume_over_length_[h]));
  theta_sum_.assign(n, 0.0);
  theta_.assign(n, 0.0);
  pressure_.assign(n, 0.0);
  own_theta_.assign(ux_.size(), Real(0));
  far_theta_.assign(ux_.size(), Real(0));
  pressure_grid_.assign(ux_.size(), Real(0));
}

void LatticeKernel::refresh_pair_constants() {
  pair_constants_.resize(offset_.size());
  for (std::size_t h = 0; h < offset_.size(); ++h)
    pair_constants_[h] = {offset_[h],       xi_x_[h],           xi_y_[h],
                          rest_[h],         direction_x_[h],    direction_y_[h],
                          half_stiffness_[h], critical_extension_[h],
                          volume_over_length_.empty() ? Real(0) : volume_over_length_[h]};
}

void LatticeKernel::scatter_displacements_in_team(const Kinematics& k, std::int64_t first_entry,
                                                  std::int64_t last_entry) {
#pragma omp for schedule(static) nowait
  for (std::int64_t g = first_entry; g < last_entry; ++g) {
    const auto i = grid_particle_[g];
    ux_[static_cast<std::size_t>(grid_cell_[g])] = static_cast<Real>(k.ux[i]);
    uy_[static_cast<std::size_t>(grid_cell_[g])] = static_cast<Real>(k.uy[i]);
  }
}

void LatticeKernel::hold_bond_states(bool hold) {
  if (dual_horizon_) throw Error("lattice kernel: held bond states are not available with dual horizons");
  // An infinite critical extension: Model::holds is true for every bond, so
  // the sweeps and the lists keep the states as they are.
  if (hold == held_) return;
  held_ = hold;
  // The energy minimisation evaluates the general particles' bonds on the
  // double lists (their states are general_intact_, up to date).
  release_general_pairs();
  if (hold) {
    released_critical_extension_ = critical_extension_;
    released_critical_stretch_ = general_bonds_.critical_stretch;
    std::fill(critical_extension_.begin(), critical_extension_.end(), INFINITY);
    general_bonds_.critical_stretch = INFINITY;
  } else {
    critical_extension_ = released_critical_extension_;
    released_critical_extension_.clear();
    general_bonds_.critical_stretch = released_critical_stretch_;
  }
}

void LatticeKernel::symmetrise_general_bonds(const ParticleSet& p) {
  if (dual_horizon_) throw Error("lattice kernel: the energy-symmetric table is not available with dual horizons");
  if (general_intact_.empty() && general_bonds_.size() > 0)
    throw Error("lattice kernel: the energy-symmetric table needs the bond states (damage on)");
  release_general_pairs();  // the energy-symmetric lists have other constants
  general_bonds_ = energy_bond_table(std::move(general_bonds_), p.x, p.y, p.volume);
  // A pre-cut pair has stiffness 0 in both directions: broken, as in the quasi-static problem.
  general_intact_.resize(general_bonds_.size());
  for (std::size_t b = 0; b < general_bonds_.size(); ++b) general_intact_[b] = general_bonds_.stiffness[b] != 0 ? 1 : 0;
}

std::uint64_t LatticeKernel::state_index(std::int64_t cell, long di, long dj) const {
  return state_index(cell, cell / row_length_, di, dj);
}

std::uint64_t LatticeKernel::pair_state_index(std::uint32_t i, std::uint32_t j) const {
  // Cell step from i to j: row step dj and column step di with |di| <= halo (the offset
  // by halo + 1 rows keeps the integer division away from negative numbers).
  const auto step = cell_of_[j] - cell_of_[i];
  const long dj = static_cast<long>((step + halo_ + row_length_ * (halo_ + 1)) / row_length_) - (halo_ + 1);
  return state_index(cell_of_[i], static_cast<long>(step - dj * row_length_), dj);
}

std::size_t LatticeKernel::particle_count() const {
  std::size_t count = owned_lattice_count_;
  for (const auto& finer : finer_) count += finer.owned_lattice_count_;
  return count;
}

std::size_t LatticeKernel::grid_cell_count() const {
  std::size_t count = ux_.size();
  for (const auto& finer : finer_) count += finer.ux_.size();
  return count;
}

std::size_t LatticeKernel::moved_off_count() const {
  std::size_t count = moved_off_;
  for (const auto& finer : finer_) count += finer.moved_off_;
  return count;
}

std::size_t LatticeKernel::bond_state_count() const {
  std::size_t count = state_bits_.size() + general_intact_.size();
  for (const auto& finer : finer_) count += finer.state_bits_.size();
  return count;
}

bool LatticeKernel::has_bond_states() const { return !(state_bits_.empty() && general_intact_.empty()); }

void LatticeKernel::bond_states(std::vector<std::uint8_t>& out) const {
  // The state bytes as they are (also the bits of slots that are no bond,
  // which the sweep flips freely and never counts): a restored kernel is
  // this one bit for bit. Level 0's sweep, the finer ones, the general table.
  out.resize(bond_state_count());
  auto next = std::copy(state_bits_.begin(), state_bits_.end(), out.begin());
  for (const auto& finer : finer_) next = std::copy(finer.state_bits_.begin(), finer.state_bits_.end(), next);
  std::copy(general_intact_.begin(), general_intact_.end(), next);
}

void LatticeKernel::set_bond_states(const std::vector<std::uint8_t>& states) {
  if (states.size() != bond_state_count())
    throw Error("the saved bond states do not fit the lattice kernel (" + std::to_string(states.size()) + " for " +
                std::to_string(bond_state_count()) + ")");
  auto next = states.begin();
  const auto take = [&](std::vector<std::uint8_t>& to) {
    std::copy(next, next + static_cast<std::ptrdiff_t>(to.size()), to.begin());
    next += static_cast<std::ptrdiff_t>(to.size());
  };
  take(state_bits_);
  for (auto& finer : finer_) take(finer.state_bits_);
  take(general_intact_);
  take_general_pair_states();
  recount_broken_units();
}

void LatticeKernel::family_bond_states(const Families& families, std::vector<std::uint8_t>& out) const {
  // Bond by bond in the families' order: a pair of the sweep from its bit,
  // a bond between general particles from their table (whose rows keep the
  // families' order, bond_table).
  out.clear();
  if (!has_bond_states()) return;  // no damage
  for (std::uint32_t i = 0; i < owned_count_; ++i) append_family_bond_states(families, i, out);
}

void LatticeKernel::append_family_bond_states(const Families& families, std::uint32_t i,
                                              std::vector<std::uint8_t>& out) const {
  if (!has_bond_states()) return;  // no damage
  for_each_family_bond(families, i, [&](const BondRef&, const auto& intact) { out.push_back(intact() ? 1 : 0); });
}

void LatticeKernel::broken_pairs(const std::vector<std::uint8_t>& states,
                                 std::vector<std::pair<std::uint32_t, std::uint32_t>>& out) const {
  if (!has_bond_states()) return;  // no damage
  if (states.size() != bond_state_count())
    throw Error("lattice kernel: bond states of another layout (" + std::to_string(states.size()) + " for " +
                std::to_string(bond_state_count()) + ")");
  append_broken_pairs(states.data(), states.data() + (states.size() - general_intact_.size()), out);
}

void LatticeKernel::broken_pairs(std::vector<std::pair<std::uint32_t, std::uint32_t>>& out) const {
  if (!has_bond_states()) return;  // no damage
  append_sweep_broken_pairs(state_bits_.data(), out);
  for (const auto& finer : finer_) finer.append_sweep_broken_pairs(finer.state_bits_.data(), out);
  append_broken_pairs(nullptr, general_intact_.data(), out);
}

void LatticeKernel::append_broken_pairs(const std::uint8_t* state_bytes, const std::uint8_t* general_intact,
                                        std::vector<std::pair<std::uint32_t, std::uint32_t>>& out) const {
  const auto owned = [&](std::uint32_t i) { return i < owned_count_; };
  // (No state bytes: the sweeps' pairs are listed already.)
  if (state_bytes) {
    append_sweep_broken_pairs(state_bytes, out);
    state_bytes += state_bits_.size();
    for (const auto& finer : finer_) {
      finer.append_sweep_broken_pairs(state_bytes, out);
      state_bytes += finer.state_bits_.size();
    }
  }
  // The general particles' bonds among themselves: a row's own entries (a
  // dual entry repeats its owner's bond).
  for (const auto i : general_) {
    if (!owned(i)) continue;
    for (auto b = general_bonds_.offsets[i]; b < general_bonds_.own_end(i); ++b) {
      const auto j = general_bonds_.neighbor[b];
      if (!general_intact[b]) out.emplace_back(std::min(i, j), std::max(i, j));
    }
  }
}

void LatticeKernel::append_sweep_broken_pairs(const std::uint8_t* state_bytes,
                                              std::vector<std::pair<std::uint32_t, std::uint32_t>>& out) const {
  const auto owned = [&](std::uint32_t i) { return i < owned_count_; };
  // The sweep: each pair has one slot, at its forward end (state_index). A
  // zero bit whose cells do not hold a pair with a lattice end is no bond
  // (the sweep flips those freely).
  const std::size_t half = offset_.size();
  for (const RowSpan& span : rows_) {
    const std::uint64_t first_byte = span.first_state / lanes;
    const std::uint64_t bytes = static_cast<std::uint64_t>(span.steps) * half;
    for (std::uint64_t q = 0; q < bytes; ++q) {
      const unsigned broken = static_cast<std::uint8_t>(~state_bytes[first_byte + q]);
      if (broken == 0) continue;  // 8 intact slots: the common case
      const std::uint64_t step = q / half, v = q % half;
      for (unsigned bits = broken; bits != 0; bits &= bits - 1) {
        const auto cell = span.first_cell + static_cast<std::int64_t>(step * lanes) + __builtin_ctz(bits);
        const auto i = particle_at_[static_cast<std::size_t>(cell)];
        const auto j = particle_at_[static_cast<std::size_t>(cell + offset_[v])];
        if (i == Families::none || j == Families::none || !(is_lattice_[i] || is_lattice_[j])) continue;
        if (owned(i) || owned(j)) out.emplace_back(std::min(i, j), std::max(i, j));
      }
    }
  }
}

void LatticeKernel::set_family_bond_states(const Families& families, const std::vector<std::uint8_t>& states) {
  if (!has_bond_states()) return;  // no damage
  std::uint64_t expected = 0;
  for (std::uint32_t i = 0; i < owned_count_; ++i) expected += families.family_size(i);
  if (states.size() != expected)
    throw Error("the saved bond states do not fit this process's families (" + std::to_string(states.size()) +
                " for " + std::to_string(expected) + ")");
  // Every pair intact, then the broken ones cleared from their owned ends (a
  // pair between two owned particles twice, with the same state).
  std::fill(state_bits_.begin(), state_bits_.end(), std::uint8_t{0xff});
  for (auto& finer : finer_) std::fill(finer.state_bits_.begin(), finer.state_bits_.end(), std::uint8_t{0xff});
  std::size_t next = 0;
  for (std::uint32_t i = 0; i < owned_count_; ++i) {
    auto general = general_bonds_.offsets[i];
    families.for_each_bond(i, [&](const BondRef& b) {
      const auto j = b.neighbor;
      const std::uint8_t intact = states[next++];
      if (!(is_lattice_[i] || is_lattice_[j])) {
        general_intact_[general++] = intact;
      } else if (!intact) {
        LatticeKernel& sweep = sweep_of(i, j);
        const auto slot = sweep.pair_state_index(i, j);
        auto& byte = sweep.state_bits_[slot / lanes];
        byte = static_cast<std::uint8_t>(byte & ~(1u << (slot % lanes)));
      }
    });
  }
  take_general_pair_states();
  recount_broken_units();
}

void LatticeKernel::set_general_entry_states(const std::vector<std::uint8_t>& states) {
  if (!has_bond_states()) return;  // no damage
  if (states.size() != general_intact_.size())
    throw Error("the saved bond states do not fit this process's general rows (" + std::to_string(states.size()) +
                " for " + std::to_string(general_intact_.size()) + ")");
  general_intact_ = states;
  take_general_pair_states();
}

void LatticeKernel::count_breaks(unsigned before, unsigned after, std::int64_t cell, std::size_t h) {
  for (unsigned broke = before & ~after; broke != 0; broke &= broke - 1) {
    const int t = __builtin_ctz(broke);
    const auto c = static_cast<std::size_t>(cell + t), far = static_cast<std::size_t>(cell + t + offset_[h]);
    if (lattice_mask_[c] == Real(0) && lattice_mask_[far] == Real(0)) continue;  // not a bond of the sweep
    broken_units_[c] += weight_units_[h];
    broken_units_[far] += weight_units_[h];
    const std::uint64_t directed = owned_ends(c, far);  // 2 on one process
#pragma omp atomic
    broken_directed_ += directed;
  }
}

void LatticeKernel::recount_broken_units() {
  for (auto& finer : finer_) finer.recount_broken_units();
  if (broken_units_.empty()) return;
  std::fill(broken_units_.begin(), broken_units_.end(), 0u);
  // Each direction i -> j adds to i: every cell gets its broken pairs once,
  // and the directed bonds of owned particles count.
  const std::int64_t count = static_cast<std::int64_t>(grid_particle_.size());
  std::uint64_t directed = 0;
#pragma omp parallel for schedule(static) reduction(+ : directed)
  for (std::int64_t g = 0; g < count; ++g)
    for_each_pair_of(static_cast<std::size_t>(g), [&](std::uint32_t i, std::uint32_t, std::size_t h, long, long, std::uint64_t slot) {
      if (pair_intact(slot)) return;
      broken_units_[static_cast<std::size_t>(grid_cell_[g])] += weight_units_[h];
      directed += i < owned_count_ ? 1 : 0;
    });
  broken_directed_ = directed;
}

void LatticeKernel::intact_stiffness_blocks(std::vector<double>& xx, std::vector<double>& xy,
                                            std::vector<double>& yy) const {
  const std::size_t n = cell_of_.size();
  xx.assign(n, 0.0);
  xy.assign(n, 0.0);
  yy.assign(n, 0.0);
  // k n n^T of bond i -> j added to i (the sign of n does not matter).
  const auto add = [&](std::uint32_t i, std::uint32_t, double k, double n_x, double n_y) {
    xx[i] += k * n_x * n_x;
    xy[i] += k * n_x * n_y;
    yy[i] += k * n_y * n_y;
  };
  for_each_intact_general_bond(add);
  // Every bond i -> j with a lattice end adds to i: each grid particle its own block.
  const std::int64_t count = static_cast<std::int64_t>(grid_particle_.size());
#pragma omp parallel for schedule(static)
  for (std::int64_t g = 0; g < count; ++g) for_each_intact_pair_of(static_cast<std::size_t>(g), add);
}

std::size_t LatticeKernel::broken_bond_count() const {
  if (!has_bond_states()) return 0;  // no damage
  std::uint64_t swept = broken_directed_;
  for (const auto& finer : finer_) swept += finer.broken_directed_;
  // On a process of a distributed run a dual-horizon row's dual entries are
  // the bonds of other rows, which may be another process's: the owned
  // rows' own entries (a ghost's row is empty), each bond once over the processes.
  const bool distributed = owned_count_ < is_lattice_.size();
  return swept + static_cast<std::size_t>(dual_horizon_ && distributed
                                              ? broken_own_entries(general_bonds_, general_intact_)
                                              : broken_directed_bonds(general_bonds_, general_intact_));
}

bool LatticeKernel::break_pair(std::uint32_t i, std::uint32_t j) {
  if (is_lattice_[i] || is_lattice_[j]) return sweep_of(i, j).break_sweep_pair(i, j);
  bool found = false;
  for (auto [from, to] : {std::pair{i, j}, std::pair{j, i}})
    for (auto b = general_bonds_.offsets[from]; b < general_bonds_.offsets[from + 1]; ++b)
      if (general_bonds_.neighbor[b] == to) {
        found = true;
        break_general_entry(b, from, to);
      }
  return found;
}

void LatticeKernel::break_general_entry(std::uint64_t b, std::uint32_t from, std::uint32_t to) {
  if (general_intact_.empty()) return;
  general_intact_[b] = 0;
  // The pair's states at once (an event breaks many pairs: no pass over the whole table each).
  auto& g = general_pairs_;
  if (g.intact_bits.empty()) return;
  const std::size_t pair = g.entry_direction.empty() ? g.pair_of(g.slot[b]) : g.entry_direction[b] / 2;
  const auto cleared = static_cast<std::uint8_t>(~(1u << (pair % 8)));
  g.intact_bits[pair / 8] &= cleared;
  if (!g.backward_intact_bits.empty()) g.backward_intact_bits[pair / 8] &= cleared;
  g.row_changed[from] = g.row_changed[to] = 1;  // the next gather copies their rows' states and damage
}

void LatticeKernel::break_pairs(const std::vector<std::pair<std::uint32_t, std::uint32_t>>& pairs) {
  // A pair with a lattice end: its sweep's slot. The pairs of two general
  // particles: each end's broken partners listed, then each such end's row
  // read once, its entries to those partners broken (break_pair reads both
  // rows for every pair; a refinement event breaks every inherited pair).
  const std::size_t n = is_lattice_.size();
  std::vector<std::uint64_t> first(n + 1, 0);
  std::size_t general_pair_count = 0;
  for (const auto& [i, j] : pairs) {
    if (is_lattice_[i] || is_lattice_[j]) {
      sweep_of(i, j).break_sweep_pair(i, j);
      continue;
    }
    ++first[i + 1], ++first[j + 1];
    ++general_pair_count;
  }
  if (general_pair_count == 0 || general_intact_.empty()) return;
  for (std::size_t i = 0; i < n; ++i) first[i + 1] += first[i];
  std::vector<std::uint32_t> partner(first[n]);
  std::vector<std::uint64_t> next(first.begin(), first.end() - 1);
  for (const auto& [i, j] : pairs)
    if (!(is_lattice_[i] || is_lattice_[j])) partner[next[i]++] = j, partner[next[j]++] = i;
  std::vector<std::uint8_t> is_partner(n, 0);
  for (std::uint32_t from = 0; from < n; ++from) {
    if (first[from] == first[from + 1]) continue;
    for (auto k = first[from]; k < first[from + 1]; ++k) is_partner[partner[k]] = 1;
    for (auto b = general_bonds_.offsets[from]; b < general_bonds_.offsets[from + 1]; ++b) {
      const auto to = general_bonds_.neighbor[b];
      if (is_partner[to]) break_general_entry(b, from, to);
    }
    for (auto k = first[from]; k < first[from + 1]; ++k) is_partner[partner[k]] = 0;
  }
}

bool LatticeKernel::break_sweep_pair(std::uint32_t i, std::uint32_t j) {
  if (cell_of_[i] < 0 || cell_of_[j] < 0) return false;
  const auto step = cell_of_[j] - cell_of_[i];
  const long dj = static_cast<long>((step + halo_ + row_length_ * (halo_ + 1)) / row_length_) - (halo_ + 1);
  const long di = static_cast<long>(step - dj * row_length_);
  if (std::labs(di) > halo_ || std::labs(dj) > halo_ ||
      pair_of_step_[static_cast<std::size_t>((dj + halo_) * (2 * halo_ + 1) + (di + halo_))] < 0)
    return false;
  if (!state_bits_.empty() && pair_intact(pair_state_index(i, j))) {
    const auto slot = pair_state_index(i, j);
    state_bits_[slot / lanes] = static_cast<std::uint8_t>(state_bits_[slot / lanes] & ~(1u << (slot % lanes)));
    const int v = pair_of_step_[static_cast<std::size_t>((dj + halo_) * (2 * halo_ + 1) + (di + halo_))];
    const auto units = weight_units_[static_cast<std::size_t>(v) % offset_.size()];
    broken_units_[static_cast<std::size_t>(cell_of_[i])] += units;
    broken_units_[static_cast<std::size_t>(cell_of_[j])] += units;
    broken_directed_ += 2;
  }
  return true;
}

void LatticeKernel::allocate_step_sums() {
  for (auto& finer : finer_) finer.allocate_step_sums();
  if (own_fx_.size() != ux_.size())
    for (auto* sums : {&own_fx_, &own_fy_, &far_fx_, &far_fy_}) sums->assign(ux_.size(), Real(0));
  auto& g = general_pairs_;
  if (g.value_x.size() != g.value_count())
    for (auto* values : {&g.value_x, &g.value_y}) {
      // Not zeroed: each pass over the pairs writes every end (all padded
      // groups) before the gather reads it; the zero slot is never written.
      values->clear();
      values->resize(g.value_count());
      if (!values->empty()) (*values)[g.zero_slot()] = Real(0);
    }
}

void LatticeKernel::release_step_sums() {
  // The far sums of the cells the gather reads are 0 now; the others are
  // never read, so zeroed new ones give the same forces. The pairs' values
  // are written whole by each evaluation before they are read.
  for (auto& finer : finer_) finer.release_step_sums();
  for (auto* sums : {&own_fx_, &own_fy_, &far_fx_, &far_fy_, &energy_}) std::vector<Real>().swap(*sums);
  for (auto* values : {&general_pairs_.value_x, &general_pairs_.value_y}) UninitialisedVector<Real>().swap(*values);
}

}  // namespace pd::solver
