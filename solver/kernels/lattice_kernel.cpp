#include "lattice_kernel.hpp"

#include <algorithm>
#include <cmath>
#include <type_traits>

#if defined(__AVX2__) && !defined(PD_PORTABLE_SWEEP)
#include <immintrin.h>
#endif

#include "error.hpp"

namespace pd::solver {

namespace {
constexpr std::uint32_t none = 0xffffffffu;

bool close(double a, double b, double relative) { return std::fabs(a - b) <= relative * std::fabs(a); }

// Broken bonds are counted in whole units of 2^-20 of a cell's area (integers:
// the count does not depend on the order in which bonds break or are recounted).
constexpr double damage_units_per_cell = 1 << 20;
}  // namespace

LatticeKernel::LatticeKernel(const ParticleSet& p, const BondSetup& run_bonds, const Pmb::Constants& model,
                             bool with_damage) {
  const Families& families = run_bonds.families;
  const std::size_t n = p.size();
  const double dx = families.spacing;
  const std::size_t s = families.stencil_size();
  if (s == 0 || families.stencil_particle_count() == 0) return;  // no lattice: the neighbour lists do all
  const long nx = families.nx;
  const auto col = [&](std::size_t i) { return static_cast<long>(families.cell[i] % nx); };
  const auto row = [&](std::size_t i) { return static_cast<long>(families.cell[i] / nx); };
  stencil_di_ = families.stencil_di;
  stencil_dj_ = families.stencil_dj;
  // Stencil bond constants without the surface-correction factors (run_bonds.hpp).
  std::vector<double> stiffness_ref(s), rest(s);
  for (std::size_t o = 0; o < s; ++o) {
    rest[o] = std::hypot(stencil_di_[o] * dx, stencil_dj_[o] * dx);
    stiffness_ref[o] = Pmb::bond_stiffness(model, 1.0, run_bonds.energy_weight.stencil[o], rest[o]);
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

  // The grid: halo cells on every side, rows padded to whole SIMD steps.
  spacing_ = dx;
  unit_area_ = dx * dx / damage_units_per_cell;
  row_length_ = (nx + 2 * halo_ + lanes - 1) / lanes * lanes;
  const long grid_rows = families.ny + 2 * halo_;
  const auto grid = [&](long c, long r) { return static_cast<std::int64_t>((r + halo_) * row_length_ + (c + halo_)); };
  cell_of_.assign(n, -1);
  for (std::size_t i = 0; i < n; ++i)
    if (families.cell[i] >= 0) cell_of_[i] = grid(col(i), row(i));

  // Pair constants (single precision for the sweep, double for energies).
  for (std::size_t h = 0; h < half; ++h) {
    const auto o = forward[h];
    offset_.push_back(stencil_dj_[o] * row_length_ + stencil_di_[o]);
    xi_x_.push_back(static_cast<Real>(stencil_di_[o] * dx));
    xi_y_.push_back(static_cast<Real>(stencil_dj_[o] * dx));
    rest_.push_back(static_cast<Real>(rest[o]));
    half_stiffness_.push_back(static_cast<Real>(0.5 * stiffness_ref[o]));
    pair_stiffness_.push_back(stiffness_ref[o]);
    critical_extension_.push_back(static_cast<Real>(model.critical_stretch * rest[o]));
    weight_units_.push_back(static_cast<std::uint32_t>(std::lround(families.stencil_phi[o] * damage_units_per_cell)));
    family_units_ += 2 * weight_units_.back();
  }

  // Lattice particles (stencil families), border and general particles; the
  // general particles' own table of their bonds to general particles.
  is_lattice_.assign(n, 0);
  std::vector<bool> read_by_sweep(n, false);
  for (std::uint32_t i = 0; i < n; ++i) {
    if (!families.on_stencil[i]) continue;
    is_lattice_[i] = 1;
    particle_.push_back(i);
    particle_cell_.push_back(cell_of_[i]);
    read_by_sweep[i] = true;
    families.for_each_bond(i, [&](const BondRef& b) { read_by_sweep[b.neighbor] = true; });
  }
  for (std::uint32_t i = 0; i < n; ++i) {
    if (is_lattice_[i]) continue;
    general_.push_back(i);
    bool border = false;
    double lattice_area = 0;
    families.for_each_bond(i, [&](const BondRef& b) {
      const auto j = b.neighbor;
      if (!is_lattice_[j]) return;
      // The sweep computes this bond with the pair's constants: they must be this bond's.
      const long di = cell_of_[i] < 0 ? halo_ + 1 : col(j) - col(i), dj = cell_of_[i] < 0 ? 0 : row(j) - row(i);
      const int v = std::labs(di) <= halo_ && std::labs(dj) <= halo_ ? pair_of_step_[step_index(di, dj)] : -1;
      const std::size_t h = v < 0 ? 0 : static_cast<std::size_t>(v) % half;
      const auto c = bond_constants<Pmb>(p, run_bonds, model, i, b);
      const double k_pair = 0.5 * (run_bonds.lambda[i] + run_bonds.lambda[j]) * pair_stiffness_[h];
      if (v < 0 || !c.intact || !close(c.stiffness, k_pair, 1e-6) || !close(c.rest_length, rest[forward[h]], 1e-6))
        throw Error("lattice kernel: the bond " + std::to_string(i) + " -> " + std::to_string(j) +
                    " does not match its lattice partner's (families not symmetric?)");
      border = true;
      lattice_area += static_cast<double>(c.damage_weight);
    });
    if (border) border_.push_back(i), border_cell_.push_back(cell_of_[i]), border_lattice_area_.push_back(lattice_area);
  }
  general_bonds_ = bond_table<Pmb>(p, run_bonds, model, with_damage, &general_intact_,
                              [&](std::uint32_t i, std::uint32_t j) { return !is_lattice_[i] && !is_lattice_[j]; });
  if (!with_damage) general_intact_.clear();
  for (std::uint32_t i = 0; i < n; ++i)
    if (read_by_sweep[i]) grid_particle_.push_back(i), grid_cell_.push_back(cell_of_[i]);

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
  own_fx_.assign(cells, 0.0);
  own_fy_.assign(cells, 0.0);
  far_fx_.assign(cells, 0.0);
  far_fy_.assign(cells, 0.0);
  if (with_damage) broken_units_.assign(cells, 0);
  particle_at_.assign(cells, Families::none);
  for (std::size_t g = 0; g < grid_particle_.size(); ++g) {
    lambda_[static_cast<std::size_t>(grid_cell_[g])] = static_cast<Real>(run_bonds.lambda[grid_particle_[g]]);
    particle_at_[static_cast<std::size_t>(grid_cell_[g])] = grid_particle_[g];
  }
}

std::uint64_t LatticeKernel::state_index(std::int64_t cell, long di, long dj) const {
  return state_index(cell, cell / row_length_, di, dj);
}

std::uint64_t LatticeKernel::state_index(std::int64_t cell, std::int64_t row, long di, long dj) const {
  const long width = 2 * halo_ + 1;
  int v = pair_of_step_[static_cast<std::size_t>((dj + halo_) * width + (di + halo_))];
  const int half = static_cast<int>(offset_.size());
  if (v >= half) {  // backward: the pair is stored at the other end
    v -= half;
    cell += dj * row_length_ + di;
    row += dj;
  }
  const auto& span = rows_[static_cast<std::size_t>(row)];
  const auto index = static_cast<std::uint64_t>(cell - span.first_cell);
  return span.first_state + (index / lanes * offset_.size() + static_cast<std::uint64_t>(v)) * lanes + index % lanes;
}

std::uint64_t LatticeKernel::pair_state_index(std::uint32_t i, std::uint32_t j) const {
  // Cell step from i to j: row step dj and column step di with |di| <= halo (the offset
  // by halo + 1 rows keeps the integer division away from negative numbers).
  const auto step = cell_of_[j] - cell_of_[i];
  const long dj = static_cast<long>((step + halo_ + row_length_ * (halo_ + 1)) / row_length_) - (halo_ + 1);
  return state_index(cell_of_[i], static_cast<long>(step - dj * row_length_), dj);
}

template <class F>
void LatticeKernel::for_each_pair_of(std::size_t g, F&& f) const {
  // Every stencil step from particle grid_particle_[g]: the pairs with a lattice end.
  const auto i = grid_particle_[g];
  const auto cell = grid_cell_[g];
  const std::int64_t row = cell / row_length_;  // (once per particle: a division is slow)
  const std::size_t half = offset_.size();
  for (std::size_t o = 0; o < stencil_di_.size(); ++o) {
    const long di = stencil_di_[o], dj = stencil_dj_[o];
    const auto j = particle_at_[static_cast<std::size_t>(cell + dj * row_length_ + di)];
    if (j == Families::none || !(is_lattice_[i] || is_lattice_[j])) continue;
    const int v = pair_of_step_[static_cast<std::size_t>((dj + halo_) * (2 * halo_ + 1) + (di + halo_))];
    f(i, j, static_cast<std::size_t>(v) % half, di, dj, state_index(cell, row, di, dj));
  }
}

void LatticeKernel::bond_states(std::vector<std::uint8_t>& out) const {
  // The state bytes as they are (also the bits of slots that are no bond,
  // which the sweep flips freely and never counts): a restored kernel is
  // this one bit for bit.
  out.resize(bond_state_count());
  std::copy(state_bits_.begin(), state_bits_.end(), out.begin());
  std::copy(general_intact_.begin(), general_intact_.end(), out.begin() + static_cast<std::ptrdiff_t>(state_bits_.size()));
}

void LatticeKernel::set_bond_states(const std::vector<std::uint8_t>& states) {
  if (states.size() != bond_state_count())
    throw Error("the saved bond states do not fit the lattice kernel (" + std::to_string(states.size()) + " for " +
                std::to_string(bond_state_count()) + ")");
  std::copy(states.begin(), states.begin() + static_cast<std::ptrdiff_t>(state_bits_.size()), state_bits_.begin());
  std::copy(states.begin() + static_cast<std::ptrdiff_t>(state_bits_.size()), states.end(), general_intact_.begin());
  recount_broken_units();
}

void LatticeKernel::record_breaks(std::uint8_t& state, unsigned before, unsigned after, std::int64_t cell,
                                  std::size_t h) {
  state = static_cast<std::uint8_t>(after);
  for (unsigned broke = before & ~after; broke != 0; broke &= broke - 1) {
    const int t = __builtin_ctz(broke);
    const auto c = static_cast<std::size_t>(cell + t), far = static_cast<std::size_t>(cell + t + offset_[h]);
    if (lattice_mask_[c] == Real(0) && lattice_mask_[far] == Real(0)) continue;  // not a bond of the sweep
    broken_units_[c] += weight_units_[h];
    broken_units_[far] += weight_units_[h];
#pragma omp atomic
    broken_directed_ += 2;
  }
}

void LatticeKernel::recount_broken_units() {
  if (broken_units_.empty()) return;
  std::fill(broken_units_.begin(), broken_units_.end(), 0u);
  // Each direction i -> j adds to i: every cell gets its broken pairs once.
  const std::int64_t count = static_cast<std::int64_t>(grid_particle_.size());
  std::uint64_t directed = 0;
#pragma omp parallel for schedule(static) reduction(+ : directed)
  for (std::int64_t g = 0; g < count; ++g)
    for_each_pair_of(static_cast<std::size_t>(g), [&](std::uint32_t, std::uint32_t, std::size_t h, long, long, std::uint64_t slot) {
      if (pair_intact(slot)) return;
      broken_units_[static_cast<std::size_t>(grid_cell_[g])] += weight_units_[h];
      ++directed;
    });
  broken_directed_ = directed;
}

std::size_t LatticeKernel::broken_bond_count() const {
  if (state_bits_.empty()) return 0;
  return broken_directed_ + static_cast<std::size_t>(std::count(general_intact_.begin(), general_intact_.end(), 0));
}

bool LatticeKernel::break_pair(std::uint32_t i, std::uint32_t j) {
  if (cell_of_[i] >= 0 && cell_of_[j] >= 0 && (is_lattice_[i] || is_lattice_[j])) {
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
  bool found = false;
  for (auto [from, to] : {std::pair{i, j}, std::pair{j, i}})
    for (auto b = general_bonds_.offsets[from]; b < general_bonds_.offsets[from + 1]; ++b)
      if (general_bonds_.neighbor[b] == to) {
        if (!general_intact_.empty()) general_intact_[b] = 0;
        found = true;
      }
  return found;
}

void LatticeKernel::strain_energy_density(const Kinematics& k, const std::vector<double>& ref_x,
                                          const std::vector<double>& ref_y, const std::vector<double>& lambda,
                                          std::vector<double>& energy_density) const {
  compute_strain_energy_density(general_bonds_, k, general_intact_.empty() ? nullptr : general_intact_.data(),
                                energy_density);
  const std::int64_t count = static_cast<std::int64_t>(grid_particle_.size());
  const double spacing = spacing_;
#pragma omp parallel for schedule(static)
  for (std::int64_t g = 0; g < count; ++g) {
    double w = 0;
    for_each_pair_of(static_cast<std::size_t>(g), [&](std::uint32_t i, std::uint32_t j, std::size_t h, long di, long dj,
                                                      std::uint64_t index) {
      if (!state_bits_.empty() && !pair_intact(index)) return;
      // Extension from the displacement difference, free of cancellation (as in the sweep), in double.
      const double xx = di * spacing, xy = dj * spacing, rest = std::sqrt(xx * xx + xy * xy);
      const double dux = (k.x[j] - ref_x[j]) - (k.x[i] - ref_x[i]), duy = (k.y[j] - ref_y[j]) - (k.y[i] - ref_y[i]);
      const double yx = xx + dux, yy = xy + duy;
      const double extension = (2 * (xx * dux + xy * duy) + dux * dux + duy * duy) / (std::sqrt(yx * yx + yy * yy) + rest);
      w += 0.5 * (lambda[i] + lambda[j]) * pair_stiffness_[h] * extension * extension;
    });
    energy_density[grid_particle_[g]] += 0.25 * w;
  }
}

template <class DamageMode>
void LatticeKernel::sweep_rows(std::size_t first_row, std::size_t last_row) {
  constexpr bool with_damage = std::is_same_v<DamageMode, DamageOn>;
  const std::size_t half = offset_.size();
  // Column tiles: the rows a tile reads and adds into stay in the L1 cache
  // while the tile moves up the block.
  constexpr std::int64_t tile_steps = 16;
  std::int64_t first_step = INT64_MAX, last_step = 0;  // in SIMD steps from the row start
  for (std::size_t r = first_row; r < last_row; ++r) {
    const RowSpan span = rows_[r];
    if (span.steps == 0) continue;
    const std::int64_t start = (span.first_cell - static_cast<std::int64_t>(r) * row_length_) / lanes;
    first_step = std::min(first_step, start);
    last_step = std::max(last_step, start + span.steps);
  }
  for (std::int64_t tile = first_step; tile < last_step; tile += tile_steps)
  for (std::size_t r = first_row; r < last_row; ++r) {
    const RowSpan span = rows_[r];
    const std::int64_t start = (span.first_cell - static_cast<std::int64_t>(r) * row_length_) / lanes;
    const std::int64_t from = std::max<std::int64_t>(0, tile - start);
    const std::int64_t to = std::min(span.steps, tile + tile_steps - start);
    for (std::int64_t step = from; step < to; ++step) {
      const std::int64_t cell = span.first_cell + step * lanes;
      const Real* ux0 = ux_.data() + cell;
      const Real* uy0 = uy_.data() + cell;
      const Real* lambda0 = lambda_.data() + cell;
      const Real* lattice0 = lattice_mask_.data() + cell;
      // One byte of pair states per offset: bit t for lane t.
      std::uint8_t* states =
          with_damage ? state_bits_.data() + span.first_state / lanes + static_cast<std::uint64_t>(step) * half : nullptr;
      Real ax[lanes] = {}, ay[lanes] = {};
#if defined(__AVX2__) && !defined(PD_PORTABLE_SWEEP)
      const __m256 ux0_v = _mm256_loadu_ps(ux0), uy0_v = _mm256_loadu_ps(uy0);
      const __m256 lambda0_v = _mm256_loadu_ps(lambda0), lattice0_v = _mm256_loadu_ps(lattice0);
      __m256 ax_v = _mm256_setzero_ps(), ay_v = _mm256_setzero_ps();
#endif
      for (std::size_t h = 0; h < half; ++h) {
        const std::int64_t o = offset_[h];
        const Real* uxj = ux0 + o;
        const Real* uyj = uy0 + o;
        const Real* lambdaj = lambda0 + o;
        const Real* latticej = lattice0 + o;
        Real* fxj = far_fx_.data() + cell + o;
        Real* fyj = far_fy_.data() + cell + o;
        const Real xx = xi_x_[h], xy = xi_y_[h], rest = rest_[h], half_k = half_stiffness_[h];
        const Real limit = critical_extension_[h];
#if defined(__AVX2__) && !defined(PD_PORTABLE_SWEEP)
        // The 8 lanes in one AVX2 register each; the pair states as a bit mask
        // (movemask), which the portable loop below cannot express.
        const __m256 dux = _mm256_sub_ps(_mm256_loadu_ps(uxj), ux0_v);
        const __m256 duy = _mm256_sub_ps(_mm256_loadu_ps(uyj), uy0_v);
        const __m256 xx_v = _mm256_set1_ps(xx), xy_v = _mm256_set1_ps(xy);
        const __m256 yx = _mm256_add_ps(xx_v, dux), yy = _mm256_add_ps(xy_v, duy);
        const __m256 length = _mm256_sqrt_ps(_mm256_fmadd_ps(yx, yx, _mm256_mul_ps(yy, yy)));
        // |y| - |xi| = (|y|^2 - |xi|^2) / (|y| + |xi|), with |y|^2 - |xi|^2 formed from
        // the displacement difference: no cancellation, and one division per pair.
        const __m256 excess = _mm256_fmadd_ps(
            _mm256_set1_ps(Real(2)), _mm256_fmadd_ps(xx_v, dux, _mm256_mul_ps(xy_v, duy)),
            _mm256_fmadd_ps(dux, dux, _mm256_mul_ps(duy, duy)));
        const __m256 sum = _mm256_add_ps(length, _mm256_set1_ps(rest));
        // Only pairs with a lattice end count: the others are the neighbour lists' (or no bond).
        __m256 counts = _mm256_max_ps(lattice0_v, _mm256_loadu_ps(latticej));
        if constexpr (with_damage) {
          const unsigned before = states[h];
          const __m256i lane_bits = _mm256_setr_epi32(1, 2, 4, 8, 16, 32, 64, 128);
          const __m256 was_intact = _mm256_castsi256_ps(_mm256_cmpeq_epi32(
              _mm256_and_si256(_mm256_set1_epi32(static_cast<int>(before)), lane_bits), lane_bits));
          const __m256 holds =
              _mm256_and_ps(was_intact, _mm256_cmp_ps(excess, _mm256_mul_ps(_mm256_set1_ps(limit), sum), _CMP_LE_OQ));
          const auto after = static_cast<unsigned>(_mm256_movemask_ps(holds));
          if (after != before) record_breaks(states[h], before, after, cell, h);  // rare
          counts = _mm256_and_ps(counts, holds);
        }
        const __m256 f = _mm256_div_ps(
            _mm256_mul_ps(_mm256_mul_ps(counts, _mm256_set1_ps(half_k)),
                          _mm256_mul_ps(_mm256_add_ps(lambda0_v, _mm256_loadu_ps(lambdaj)), excess)),
            _mm256_mul_ps(length, sum));
        const __m256 fx = _mm256_mul_ps(f, yx), fy = _mm256_mul_ps(f, yy);
        ax_v = _mm256_add_ps(ax_v, fx);
        ay_v = _mm256_add_ps(ay_v, fy);
        _mm256_storeu_ps(fxj, _mm256_sub_ps(_mm256_loadu_ps(fxj), fx));
        _mm256_storeu_ps(fyj, _mm256_sub_ps(_mm256_loadu_ps(fyj), fy));
#else
        const unsigned was_intact = with_damage ? states[h] : 0u;
        unsigned intact = 0;
#pragma omp simd reduction(| : intact)
        for (int t = 0; t < lanes; ++t) {
          const Real dux = uxj[t] - ux0[t], duy = uyj[t] - uy0[t];
          const Real yx = xx + dux, yy = xy + duy;
          const Real length = std::sqrt(yx * yx + yy * yy);
          // |y| - |xi| = (|y|^2 - |xi|^2) / (|y| + |xi|) (see above).
          const Real excess = Real(2) * (xx * dux + xy * duy) + dux * dux + duy * duy;
          const Real sum = length + rest;
          Real counts = std::max(lattice0[t], latticej[t]);
          if constexpr (with_damage) {
            const bool holds = ((was_intact >> t) & 1u) != 0 && excess <= limit * sum;
            intact |= static_cast<unsigned>(holds) << t;
            counts = holds ? counts : Real(0);
          }
          const Real f = counts * half_k * (lambda0[t] + lambdaj[t]) * excess / (length * sum);
          const Real fx = f * yx, fy = f * yy;
          ax[t] += fx;
          ay[t] += fy;
          fxj[t] -= fx;
          fyj[t] -= fy;
        }
        if constexpr (with_damage)
          if (intact != was_intact) record_breaks(states[h], was_intact, intact, cell, h);  // rare
#endif
      }
#if defined(__AVX2__) && !defined(PD_PORTABLE_SWEEP)
      _mm256_storeu_ps(ax, ax_v);
      _mm256_storeu_ps(ay, ay_v);
#endif
      Real* own_fx = own_fx_.data() + cell;
      Real* own_fy = own_fy_.data() + cell;
      for (int t = 0; t < lanes; ++t) {
        own_fx[t] = ax[t];
        own_fy[t] = ay[t];
      }
    }
  }
}

template <class DamageMode>
void LatticeKernel::compute(Kinematics& k, const std::vector<double>& ref_x, const std::vector<double>& ref_y,
                            std::vector<double>& damage) {
  constexpr bool with_damage = std::is_same_v<DamageMode, DamageOn>;
  // General particles: their bonds to general particles (neighbour lists).
  compute_internal_forces_of<DamageMode>(general_bonds_, k, with_damage ? general_intact_.data() : nullptr,
                                         with_damage ? damage.data() : nullptr, general_.data(),
                                         static_cast<std::int64_t>(general_.size()));

  const std::int64_t scattered = static_cast<std::int64_t>(grid_particle_.size());
#pragma omp parallel for schedule(static)
  for (std::int64_t g = 0; g < scattered; ++g) {
    const auto i = grid_particle_[g];
    ux_[static_cast<std::size_t>(grid_cell_[g])] = static_cast<Real>(k.x[i] - ref_x[i]);
    uy_[static_cast<std::size_t>(grid_cell_[g])] = static_cast<Real>(k.y[i] - ref_y[i]);
  }
  // Two colours of row blocks: a block's far-end forces reach only into the next block.
  const std::int64_t blocks = static_cast<std::int64_t>((rows_.size() + block_rows_ - 1) / block_rows_);
  for (std::int64_t colour = 0; colour < 2; ++colour) {
#pragma omp parallel for schedule(dynamic, 1)
    for (std::int64_t b = colour; b < blocks; b += 2)
      sweep_rows<DamageMode>(static_cast<std::size_t>(b) * block_rows_,
                             std::min(rows_.size(), static_cast<std::size_t>(b + 1) * block_rows_));
  }

  // A cell's sums: its own pairs (forward) plus the far ends of the pairs of
  // the cells behind it. The far sums are cleared once read, ready for the
  // next step (other cells' far sums are never read).
  const auto take_sums = [&](std::size_t cell, double& fx, double& fy) {
    fx = static_cast<double>(own_fx_[cell] + far_fx_[cell]);
    fy = static_cast<double>(own_fy_[cell] + far_fy_[cell]);
    far_fx_[cell] = far_fy_[cell] = Real(0);
  };
  const std::int64_t lattice_count = static_cast<std::int64_t>(particle_.size());
  const double inverse_family_units = family_units_ > 0 ? 1.0 / family_units_ : 0.0;
#pragma omp parallel for schedule(static)
  for (std::int64_t q = 0; q < lattice_count; ++q) {
    const auto i = particle_[q];
    const auto c = static_cast<std::size_t>(particle_cell_[q]);
    take_sums(c, k.fx[i], k.fy[i]);
    // D_i = broken share of the family [004:(10)]: exactly 0 while every bond holds.
    if constexpr (with_damage) damage[i] = broken_units_[c] * inverse_family_units;
  }
  const std::int64_t border_count = static_cast<std::int64_t>(border_.size());
#pragma omp parallel for schedule(static)
  for (std::int64_t q = 0; q < border_count; ++q) {
    const auto i = border_[q];
    const auto c = static_cast<std::size_t>(border_cell_[q]);
    double fx = 0, fy = 0;
    take_sums(c, fx, fy);
    k.fx[i] += fx;
    k.fy[i] += fy;
    if constexpr (with_damage) {
      // The neighbour lists counted the bonds to lattice particles as missing;
      // they are missing only as far as they broke.
      const double intact_lattice_area = border_lattice_area_[q] - broken_units_[c] * unit_area_;
      const double d = damage[i] - intact_lattice_area / general_bonds_.family_area[i];
      damage[i] = d < 1e-9 ? 0.0 : d;  // round-off of the two sums; one bond weighs ~1e-2
    }
  }
}

template void LatticeKernel::compute<DamageOn>(Kinematics&, const std::vector<double>&, const std::vector<double>&,
                                               std::vector<double>&);
template void LatticeKernel::compute<DamageOff>(Kinematics&, const std::vector<double>&, const std::vector<double>&,
                                                std::vector<double>&);

}  // namespace pd::solver
