#pragma once
// The lattice kernel's loops (lattice_kernel.hpp), templates over the model
// and the effects: instantiated where the force field chooses them
// (force_field.cpp), so that adding a model needs no change here.
#include <algorithm>
#include <cstdint>

#include "deformed_bond.hpp"
#include "lattice_kernel.hpp"
#include "neighbor_kernel.hpp"
#include "simd.hpp"

namespace pd::solver {

namespace lattice_detail {
// The first column tile of a block of rows: the first SIMD step a row of the
// block visits, rounded down to a whole number of tiles from the row's start.
// Tiles then sit at the same columns whatever part of the grid a run sweeps,
// and so does the order in which a cell receives its far-end sums (a process
// of a distributed run adds them as one process does, bit for bit).
inline std::int64_t tile_start(std::int64_t first_step, std::int64_t tile_steps) {
  return first_step / tile_steps * tile_steps;
}
}  // namespace lattice_detail

template <class Model>
void LatticeKernel::strain_energy_density(const Kinematics& k, const std::vector<double>& lambda,
                                          std::vector<double>& energy_density) const {
  add_bond_energy_density<Model>(general_bonds_, k, general_intact_.empty() ? nullptr : general_intact_.data(),
                                 energy_density);
  // Each pair once, in the sweep's order (rows of cells, forward offsets),
  // its energy 1/4 k e^2 added to both ends (k_ij = k_ji on the lattice). In
  // double, from the double displacements: the same law as the sweep.
  const std::size_t half = offset_.size();
  std::vector<double> xi_x(half), xi_y(half), rest(half);
  for (std::size_t h = 0; h < half; ++h) {
    // Forward offsets go up a row or right within one: dj >= 0, |di| <= halo.
    const std::int64_t dj = (offset_[h] + halo_) / row_length_, di = offset_[h] - dj * row_length_;
    xi_x[h] = static_cast<double>(di) * spacing_;
    xi_y[h] = static_cast<double>(dj) * spacing_;
    rest[h] = std::sqrt(xi_x[h] * xi_x[h] + xi_y[h] * xi_y[h]);
  }
  const bool with_states = !state_bits_.empty();
  std::vector<double> cell_energy(particle_at_.size(), 0.0);  // [J/m^3] per grid cell
  // A state-based model: the pairs' dilatation sums too, per cell (theory.md Sec. 5).
  std::vector<double> cell_theta(Model::has_pre_pass ? particle_at_.size() : 0, 0.0);
  const auto sweep_block = [&](std::size_t first_row, std::size_t last_row) {
    for (std::size_t r = first_row; r < last_row; ++r) {
      const RowSpan span = rows_[r];
      for (std::int64_t s = 0; s < span.steps * lanes; ++s) {
        const std::int64_t c = span.first_cell + s;
        const auto i = particle_at_[static_cast<std::size_t>(c)];
        if (i == Families::none) continue;
        const std::uint8_t* states = with_states ? state_bits_.data() + span.first_state / lanes +
                                                       static_cast<std::uint64_t>(s / lanes) * half
                                                 : nullptr;
        const unsigned lane = static_cast<unsigned>(s % lanes);
        const double ux_i = k.ux[i], uy_i = k.uy[i], lambda_i = lambda[i];
        double w_i = 0, theta_i = 0;
        for (std::size_t h = 0; h < half; ++h) {
          const std::int64_t cj = c + offset_[h];
          const auto j = particle_at_[static_cast<std::size_t>(cj)];
          if (j == Families::none || !(is_lattice_[i] || is_lattice_[j])) continue;  // not a bond of the sweep
          const bool broken = with_states && ((states[h] >> lane) & 1u) == 0;
          const auto bond = deformed_bond(xi_x[h], xi_y[h], rest[h], k.ux[j] - ux_i, k.uy[j] - uy_i);
          if constexpr (Model::has_pre_pass) {
            // A broken pair stays in theta under the variants that keep it (theory.md Sec. 5.8).
            if (!broken || Model::broken_bond_in_dilatation) {
              const double t =
                  Model::dilatation_term(pair_volume_over_length_[h], Model::bond(bond, xi_x[h], xi_y[h], rest[h]));
              theta_i += t;
              cell_theta[static_cast<std::size_t>(cj)] += t;
            }
          }
          if (broken) continue;
          if constexpr (Model::energy_at_own_end) {  // each end its own factor's share (theory.md Sec. 5.7)
            w_i += Model::energy_density(lambda_i * pair_stiffness_[h], bond);
            cell_energy[static_cast<std::size_t>(cj)] += Model::energy_density(lambda[j] * pair_stiffness_[h], bond);
          } else {
            const double e = Model::energy_density(0.5 * (lambda_i + lambda[j]) * pair_stiffness_[h], bond);
            w_i += e;
            cell_energy[static_cast<std::size_t>(cj)] += e;
          }
        }
        cell_energy[static_cast<std::size_t>(c)] += w_i;
        if constexpr (Model::has_pre_pass) cell_theta[static_cast<std::size_t>(c)] += theta_i;
      }
    }
  };
  // Two colours of row blocks, as in the force sweep: a block adds only into
  // itself and the next block.
  const std::int64_t blocks = static_cast<std::int64_t>((rows_.size() + block_rows_ - 1) / block_rows_);
  for (std::int64_t colour = 0; colour < 2; ++colour) {
#pragma omp parallel for schedule(dynamic, 1)
    for (std::int64_t b = colour; b < blocks; b += 2)
      sweep_block(static_cast<std::size_t>(b) * block_rows_,
                  std::min(rows_.size(), static_cast<std::size_t>(b + 1) * block_rows_));
  }
  const std::int64_t count = static_cast<std::int64_t>(grid_particle_.size());
#pragma omp parallel for schedule(static)
  for (std::int64_t g = 0; g < count; ++g)
    energy_density[grid_particle_[g]] += cell_energy[static_cast<std::size_t>(grid_cell_[g])];
  // The finer levels' sweeps (their kernels hold no general bonds).
  for (const auto& finer : finer_) finer.strain_energy_density<Model>(k, lambda, energy_density);
  if constexpr (Model::has_pre_pass) {
    // W_i += a theta_i^2, theta_i from the current displacements in double:
    // the general particles' lists (states as they are: DamageOff breaks
    // nothing and does not write them) and the pairs' sums.
    const std::size_t n = energy_density.size();
    std::vector<double> sum(n, 0.0);
    std::uint8_t* const states = const_cast<std::uint8_t*>(general_intact_.empty() ? nullptr : general_intact_.data());
#pragma omp parallel
    add_general_dilatation_sums_in_team<Model, DamageOff>(k, states, sum.data());
    for (std::int64_t g = 0; g < count; ++g) sum[grid_particle_[g]] += cell_theta[static_cast<std::size_t>(grid_cell_[g])];
    for (std::size_t i = 0; i < n; ++i) {
      const double m = weighted_volume_[i];
      const double theta = m > 0 ? 2.0 * sum[i] / m : 0.0;
      energy_density[i] += dilatation_coefficient_ * theta * theta;
    }
  }
}

template <class Model, class Damage, bool SumEnergy>
void LatticeKernel::sweep_rows(std::size_t first_row, std::size_t last_row) {
  using simd::Float8;
  const simd::FlushSubnormals flush_subnormals;  // see simd.hpp
  constexpr bool with_damage = Damage::enabled;
  const std::size_t half = offset_.size();
  constexpr std::int64_t tile_steps = LatticeKernel::tile_steps;
  std::int64_t first_step = INT64_MAX, last_step = 0;  // in SIMD steps from the row start
  struct StateChange {
    std::uint32_t offset;  // h
    unsigned before;       // the states before the step
  };
  std::vector<StateChange> changed(with_damage ? half : 0);
  for (std::size_t r = first_row; r < last_row; ++r) {
    const RowSpan span = rows_[r];
    if (span.steps == 0) continue;
    const std::int64_t start = (span.first_cell - static_cast<std::int64_t>(r) * row_length_) / lanes;
    first_step = std::min(first_step, start);
    last_step = std::max(last_step, start + span.steps);
  }
  first_step = lattice_detail::tile_start(first_step, tile_steps);
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
            with_damage ? state_bits_.data() + span.first_state / lanes + static_cast<std::uint64_t>(step) * half
                        : nullptr;
        const Float8 ux_i = simd::load(ux0), uy_i = simd::load(uy0);
        const Float8 lambda_i = simd::load(lambda0), lattice_i = simd::load(lattice0);
        Float8 ax(0.0f), ay(0.0f), energy_i(0.0f);
        std::size_t changes = 0;  // offsets whose pair states changed in this step
        for (std::size_t h = 0; h < half; ++h) {
          const std::int64_t o = offset_[h];
          Real* fxj = far_fx_.data() + cell + o;
          Real* fyj = far_fy_.data() + cell + o;
          const auto bond = deformed_bond(Float8(xi_x_[h]), Float8(xi_y_[h]), Float8(rest_[h]),
                                          simd::load(ux0 + o) - ux_i, simd::load(uy0 + o) - uy_i);
          // Only pairs with a lattice end count: the others are the neighbour lists' (or no bond).
          Float8 counts = simd::max(lattice_i, simd::load(lattice0 + o));
          if constexpr (with_damage) {
            const unsigned before = states[h];
            const auto holds = simd::mask_of_bits(before) & Model::holds(Float8(critical_extension_[h]), bond);
            const unsigned after = simd::bits(holds);
            if (after != before) {  // rare: the bonds are counted after the offsets' loop
              states[h] = static_cast<std::uint8_t>(after);
              changed[changes++] = {static_cast<std::uint32_t>(h), before};
            }
            counts = simd::where(holds, counts);
          }
          // k = 0.5 (lambda_i + lambda_j) k_pair, and 0 for no bond or a broken one.
          const Float8 stiffness = counts * Float8(half_stiffness_[h]) * (lambda_i + simd::load(lambda0 + o));
          const Float8 f = Model::force_over_length(stiffness, bond);
          const Float8 fx = f * bond.yx, fy = f * bond.yy;
          ax += fx;
          ay += fy;
          simd::store(fxj, simd::load(fxj) - fx);
          simd::store(fyj, simd::load(fyj) - fy);
          if constexpr (SumEnergy) {
            // 1/4 k e^2 of the pair (0 for no bond or a broken one), the same to both ends (k_ij = k_ji).
            const Float8 w = Model::energy_density(stiffness, bond);
            energy_i += w;
            Real* energy_j = energy_.data() + cell + o;
            simd::store(energy_j, simd::load(energy_j) + w);
          }
        }
        simd::store(own_fx_.data() + cell, ax);
        simd::store(own_fy_.data() + cell, ay);
        if constexpr (SumEnergy) simd::store(energy_.data() + cell, simd::load(energy_.data() + cell) + energy_i);
        // Counted here, outside the loop over offsets: a call inside it would
        // make the compiler keep the accumulators in memory (all vector
        // registers are lost across a call), slowing every pair by ~25 %.
        if constexpr (with_damage)
          for (std::size_t c = 0; c < changes; ++c)
            count_breaks(changed[c].before, states[changed[c].offset], cell, changed[c].offset);
      }
    }
}

// ---- State-based models (Model::has_pre_pass; theory.md Sec. 5). Loops of
// their own, so that the bond-based sweep above stays as it is. Both sweeps
// follow its split of the work: a pair with a lattice end is evaluated once,
// here, and its terms go to both ends; the general particles' bonds among
// themselves come from their neighbour lists (add_dilatation_sums,
// compute_state_forces), or with dual horizons from their dual-horizon rows,
// whose own entries add to their owners' dilatation only (theory.md Sec. 6.8).

namespace lattice_detail {
// Calls step_body(span, step, cell) for every SIMD step of rows
// [first_row, last_row), in column tiles as sweep_rows (the rows a tile reads
// and adds into stay in the L1 cache).
template <class Spans, class Body>
inline void for_each_tile_step(const Spans& rows, std::int64_t row_length, int lanes, std::size_t first_row,
                               std::size_t last_row, Body&& step_body) {
  constexpr std::int64_t tile_steps = LatticeKernel::tile_steps;
  std::int64_t first_step = INT64_MAX, last_step = 0;
  for (std::size_t r = first_row; r < last_row; ++r) {
    const auto& span = rows[r];
    if (span.steps == 0) continue;
    const std::int64_t start = (span.first_cell - static_cast<std::int64_t>(r) * row_length) / lanes;
    first_step = std::min(first_step, start);
    last_step = std::max(last_step, start + span.steps);
  }
  first_step = tile_start(first_step, tile_steps);
  for (std::int64_t tile = first_step; tile < last_step; tile += tile_steps)
    for (std::size_t r = first_row; r < last_row; ++r) {
      const auto& span = rows[r];
      const std::int64_t start = (span.first_cell - static_cast<std::int64_t>(r) * row_length) / lanes;
      const std::int64_t from = std::max<std::int64_t>(0, tile - start);
      const std::int64_t to = std::min(span.steps, tile + tile_steps - start);
      for (std::int64_t step = from; step < to; ++step) step_body(span, step, span.first_cell + step * lanes);
    }
}
}  // namespace lattice_detail

// The dilatation sums of the pairs: Lambda e V/|xi| added to both ends (the
// term is the same seen from either end: e, Lambda and V/|xi| are symmetric).
// Bonds break here, before any of their terms is summed, so that a bond that
// breaks leaves the dilatation and the force of the same step, as
// compute_dilatation on the neighbour lists.
template <class Model, class Damage>
void LatticeKernel::dilatation_rows(std::size_t first_row, std::size_t last_row) {
  using simd::Float8;
  const simd::FlushSubnormals flush_subnormals;  // see simd.hpp
  constexpr bool with_damage = Damage::enabled;
  const std::size_t half = offset_.size();
  struct StateChange {
    std::uint32_t offset;
    unsigned before;
  };
  std::vector<StateChange> changed(with_damage ? half : 0);
  // Addresses in locals, which no store can change (see PairConstants).
  const PairConstants* const pairs = pair_constants_.data();
  const Real *const ux = ux_.data(), *const uy = uy_.data(), *const lattice = lattice_mask_.data();
  Real *const own_theta = own_theta_.data(), *const far_theta = far_theta_.data();
  std::uint8_t* const state_bits = state_bits_.data();
  lattice_detail::for_each_tile_step(rows_, row_length_, lanes, first_row, last_row,
                                     [&](const RowSpan& span, std::int64_t step, std::int64_t cell) {
    const Real* ux0 = ux + cell;
    const Real* uy0 = uy + cell;
    const Real* lattice0 = lattice + cell;
    Real* theta0 = far_theta + cell;
    std::uint8_t* states =
        with_damage ? state_bits + span.first_state / lanes + static_cast<std::uint64_t>(step) * half : nullptr;
    const Float8 ux_i = simd::load(ux0), uy_i = simd::load(uy0), lattice_i = simd::load(lattice0);
    Float8 sum(0.0f);
    std::size_t changes = 0;
    for (std::size_t h = 0; h < half; ++h) {
      const PairConstants& pair = pairs[h];
      const std::int64_t o = pair.offset;
      const auto bond = deformed_bond(Float8(pair.xi_x), Float8(pair.xi_y), Float8(pair.rest),
                                      simd::load(ux0 + o) - ux_i, simd::load(uy0 + o) - uy_i);
      Float8 counts = simd::max(lattice_i, simd::load(lattice0 + o));  // a lattice end: the sweep's pair
      if constexpr (with_damage) {
        const unsigned before = states[h];
        const auto holds = simd::mask_of_bits(before) & Model::holds(Float8(pair.critical_extension), bond);
        const unsigned after = simd::bits(holds);
        if (after != before) {
          states[h] = static_cast<std::uint8_t>(after);
          changed[changes++] = {static_cast<std::uint32_t>(h), before};
        }
        // Variants (b), (c) keep a broken pair's term (theory.md Sec. 5.8).
        if constexpr (!Model::broken_bond_in_dilatation) counts = simd::where(holds, counts);
      }
      const Float8 term = counts * Model::dilatation_term(Float8(pair.volume_over_length),
                                                          Model::bond(bond, Float8(pair.direction_x),
                                                                      Float8(pair.direction_y)));
      sum += term;
      simd::store(theta0 + o, simd::load(theta0 + o) + term);
    }
    simd::store(own_theta + cell, sum);
    if constexpr (with_damage)  // outside the offsets' loop, as in sweep_rows
      for (std::size_t c = 0; c < changes; ++c)
        count_breaks(changed[c].before, states[changed[c].offset], cell, changed[c].offset);
  });
}

// The forces of the pairs after the dilatation: the bond part and the
// dilatation part of both ends (theory.md Sec. 5), one scalar per pair along
// y, added to one end and subtracted from the other. The states are those the
// dilatation sweep left (read only).
template <class Model, class Damage>
void LatticeKernel::state_force_rows(std::size_t first_row, std::size_t last_row) {
  using simd::Float8;
  const simd::FlushSubnormals flush_subnormals;
  constexpr bool with_damage = Damage::enabled;
  const std::size_t half = offset_.size();
  const Float8 a(static_cast<Real>(dilatation_coefficient_));
  // Addresses in locals, which no store can change (see PairConstants).
  const PairConstants* const pairs = pair_constants_.data();
  const Real *const ux = ux_.data(), *const uy = uy_.data(), *const lambda = lambda_.data();
  const Real *const lattice = lattice_mask_.data(), *const pressure = pressure_grid_.data();
  Real *const own_fx = own_fx_.data(), *const own_fy = own_fy_.data();
  Real *const far_fx = far_fx_.data(), *const far_fy = far_fy_.data();
  const std::uint8_t* const state_bits = state_bits_.data();
  lattice_detail::for_each_tile_step(rows_, row_length_, lanes, first_row, last_row,
                                     [&](const RowSpan& span, std::int64_t step, std::int64_t cell) {
    const Real* ux0 = ux + cell;
    const Real* uy0 = uy + cell;
    const Real* lambda0 = lambda + cell;
    const Real* lattice0 = lattice + cell;
    const Real* pressure0 = pressure + cell;
    Real* fx0 = far_fx + cell;
    Real* fy0 = far_fy + cell;
    const std::uint8_t* states =
        with_damage ? state_bits + span.first_state / lanes + static_cast<std::uint64_t>(step) * half : nullptr;
    const Float8 ux_i = simd::load(ux0), uy_i = simd::load(uy0);
    const Float8 lambda_i = simd::load(lambda0), lattice_i = simd::load(lattice0), pressure_i = simd::load(pressure0);
    Float8 ax(0.0f), ay(0.0f);
    for (std::size_t h = 0; h < half; ++h) {
      const PairConstants& constants = pairs[h];
      const std::int64_t o = constants.offset;
      const auto bond = deformed_bond(Float8(constants.xi_x), Float8(constants.xi_y), Float8(constants.rest),
                                      simd::load(ux0 + o) - ux_i, simd::load(uy0 + o) - uy_i);
      const auto terms = Model::bond(bond, Float8(constants.direction_x), Float8(constants.direction_y));
      const Float8 pair = simd::max(lattice_i, simd::load(lattice0 + o));
      Float8 counts = pair;
      if constexpr (with_damage) counts = simd::where(simd::mask_of_bits(states[h]), counts);
      const Float8 stiffness = Float8(constants.half_stiffness) * (lambda_i + simd::load(lambda0 + o));
      const Float8 bond_part = Model::force_over_length(stiffness, terms);
      const Float8 dilatation_part = Model::dilatation_force_over_length(
          a, Float8(constants.volume_over_length), pressure_i + simd::load(pressure0 + o), terms);
      // Variant (c) keeps a broken pair's dilatation force (theory.md Sec. 5.8).
      Float8 f;
      if constexpr (Model::broken_bond_keeps_dilatation_force)
        f = counts * bond_part + pair * dilatation_part;
      else
        f = counts * (bond_part + dilatation_part);
      const Float8 fx = f * bond.yx, fy = f * bond.yy;
      ax += fx;
      ay += fy;
      simd::store(fx0 + o, simd::load(fx0 + o) - fx);
      simd::store(fy0 + o, simd::load(fy0 + o) - fy);
    }
    simd::store(own_fx + cell, ax);
    simd::store(own_fy + cell, ay);
  });
}

// ---- The general particles' pairs (GeneralPairs, lattice_kernel.hpp): each
// pair once, in float, 8 pairs at a time, its values to both ends through
// the slots. A pass over the pairs, then (after a barrier) a gather per
// particle over its row of the table in the table's order: every sum has a
// fixed order whatever the thread count (and whatever the process count: a
// pair's value seen from either end is the same bit for bit, since y, |y|
// and the extension of the pair formed from j's end are exactly those from
// i's, negated or equal, and each lane computes what a lone pair would).

namespace lattice_detail {
// u_j - u_i (Sum: u_i + u_j) of the 8 pairs (first[t], second[t]), formed in
// double and then rounded: the float pair sees u_j - u_i to 6e-8 of itself.
template <bool Sum>
inline simd::Float8 pair_combination(const double* u, const std::uint32_t* first, const std::uint32_t* second) {
#ifdef PD_SIMD_AVX2
  const auto four = [&](int offset) {
    const __m128i i = _mm_loadu_si128(reinterpret_cast<const __m128i*>(first + offset));
    const __m128i j = _mm_loadu_si128(reinterpret_cast<const __m128i*>(second + offset));
    // The masked form with a zeroed source: the plain one leaves GCC 12 warning about its undefined source.
    const __m256d all = _mm256_castsi256_pd(_mm256_set1_epi64x(-1));
    const __m256d u_i = _mm256_mask_i32gather_pd(_mm256_setzero_pd(), u, i, all, 8);
    const __m256d u_j = _mm256_mask_i32gather_pd(_mm256_setzero_pd(), u, j, all, 8);
    return _mm256_cvtpd_ps(Sum ? _mm256_add_pd(u_i, u_j) : _mm256_sub_pd(u_j, u_i));
  };
  return simd::Float8(_mm256_set_m128(four(4), four(0)));
#else
  simd::Float8 r;
  for (int t = 0; t < simd::lanes; ++t)
    r.v[t] = static_cast<float>(Sum ? u[first[t]] + u[second[t]] : u[second[t]] - u[first[t]]);
  return r;
#endif
}

// What both passes over the general pairs do for the group of 8 pairs q: the
// pairs' deformed bonds (float, from the double displacements), and with
// damage their states, a pair breaking once for both directions at s0 |xi|
// as the sweep's pairs (theory.md Sec. 1.5; with dual horizons each
// direction at its owner's). The ends of a pair whose state changed are
// marked in GeneralPairs::row_changed, for the gather.
template <class Model, bool with_damage>
struct GeneralPairGroups {
  const simd::FlushSubnormals flush_subnormals;  // while the pass runs (see simd.hpp)
  const std::uint32_t *first, *second;
  const LatticeKernel::Real *xi_x, *xi_y, *rest;
  const double *ux, *uy;
  std::uint8_t* intact_bits;
  std::uint8_t* row_changed;
  simd::Float8 critical_stretch;
  std::size_t second_end;  // where the second ends' values start
  std::int64_t groups;     // of 8 pairs

  // The groups [first_group, last_group), seen as groups 0 .. groups - 1 (the
  // pointers start at first_group): the loops keep the form of a pass over
  // all groups, which the compiler turns into the same code.
  template <class Pairs>  // LatticeKernel::GeneralPairs
  GeneralPairGroups(Pairs& g, const Kinematics& k, std::int64_t first_group, std::int64_t last_group)
      : first(g.first.data() + first_group * simd::lanes), second(g.second.data() + first_group * simd::lanes),
        xi_x(g.xi_x.data() + first_group * simd::lanes), xi_y(g.xi_y.data() + first_group * simd::lanes),
        rest(g.rest.data() + first_group * simd::lanes), ux(k.ux.data()), uy(k.uy.data()),
        intact_bits(g.intact_bits.data() + (g.intact_bits.empty() ? 0 : first_group)), row_changed(g.row_changed.data()),
        critical_stretch(g.critical_stretch), second_end(g.padded), groups(last_group - first_group) {}
  auto bond(std::size_t p) const {
    return deformed_bond(simd::load(xi_x + p), simd::load(xi_y + p), simd::load(rest + p),
                         pair_combination<false>(ux, first + p, second + p),
                         pair_combination<false>(uy, first + p, second + p));
  }
  // The pairs of group q that hold after this evaluation.
  template <class Bond>
  auto holds(std::int64_t q, std::size_t p, const Bond& b) {
    return still_holds(intact_bits[q], critical_stretch * simd::load(rest + p), b, p);
  }
  // The bonds of the group of pairs from p whose states are `bits` that hold
  // after this evaluation at the critical extensions s0 |xi| [m]; `bits` updated.
  template <class Bond>
  auto still_holds(std::uint8_t& bits, const simd::Float8& critical_extension, const Bond& b, std::size_t p) {
    const auto h = simd::mask_of_bits(bits) & Model::holds(critical_extension, b);
    const auto after = static_cast<std::uint8_t>(simd::bits(h));
    if (after != bits) mark_rows(static_cast<unsigned>(after ^ bits), p);  // rare
    bits = after;
    return h;
  }
  void mark_rows(unsigned lanes_changed, std::size_t p) {
    for (unsigned m = lanes_changed; m != 0; m &= m - 1) {
      const std::size_t t = p + static_cast<std::size_t>(__builtin_ctz(m));
#pragma omp atomic write
      row_changed[first[t]] = 1;
#pragma omp atomic write
      row_changed[second[t]] = 1;
    }
  }
};
}  // namespace lattice_detail

// The pair law is linear in the stiffness (and a state-based model's
// dilatation force in V/|xi|): it is evaluated once for k = 1 and scaled by
// each end's own constant (theory.md Sec. 1.6, "Each pair once").
template <class Model, class Damage>
void LatticeKernel::general_pair_forces_in_team(const Kinematics& k, std::int64_t first_group,
                                                std::int64_t last_group) {
  using simd::Float8;
  auto& g = general_pairs_;
  if (!g.reaction_first.empty()) {  // dual horizons (the whole team takes the same branch)
    dual_horizon_pair_forces_in_team<Model, Damage>(k, first_group, last_group);
    return;
  }
  lattice_detail::GeneralPairGroups<Model, Damage::enabled> pairs(g, k, first_group, last_group);
  const std::int64_t shift = first_group * simd::lanes;  // (the pointers start at the first group)
  const Real *const k_first = g.stiffness_first.data() + shift, *const k_second = g.stiffness_second.data() + shift;
  Real *const value_x = g.value_x.data() + shift, *const value_y = g.value_y.data() + shift;
  const std::size_t second_end = pairs.second_end;
#pragma omp for schedule(static) nowait
  for (std::int64_t q = 0; q < pairs.groups; ++q) {
    const std::size_t p = static_cast<std::size_t>(q) * simd::lanes;
    const auto bond = pairs.bond(p);
    Float8 f = Model::force_over_length(Float8(1.0f), bond);
    if constexpr (Damage::enabled) f = simd::where(pairs.holds(q, p, bond), f);
    const Float8 fx = f * bond.yx, fy = f * bond.yy;
    const Float8 k_i = simd::load(k_first + p), minus_k_j = Float8(0.0f) - simd::load(k_second + p);
    simd::store(value_x + p, k_i * fx);
    simd::store(value_y + p, k_i * fy);
    simd::store(value_x + second_end + p, minus_k_j * fx);
    simd::store(value_y + second_end + p, minus_k_j * fy);
  }
}

// The same with dual horizons (GeneralPairs): per pair two bonds, each with
// its owner's critical extension and state; each end's stiffness is that of
// its own bond while it holds plus that of the reaction of the other's.
template <class Model, class Damage>
void LatticeKernel::dual_horizon_pair_forces_in_team(const Kinematics& k, std::int64_t first_group,
                                                     std::int64_t last_group) {
  using simd::Float8;
  auto& g = general_pairs_;
  lattice_detail::GeneralPairGroups<Model, Damage::enabled> pairs(g, k, first_group, last_group);
  const std::int64_t shift = first_group * simd::lanes;  // (the pointers start at the first group)
  const Real *const k_first = g.stiffness_first.data() + shift, *const k_second = g.stiffness_second.data() + shift;
  const Real *const r_first = g.reaction_first.data() + shift, *const r_second = g.reaction_second.data() + shift;
  const Real* const forward_critical = g.critical_extension_forward.data() + shift;
  const Real* const backward_critical = g.critical_extension_backward.data() + shift;
  std::uint8_t* const backward_bits = g.backward_intact_bits.data() + (g.backward_intact_bits.empty() ? 0 : first_group);
  Real *const value_x = g.value_x.data() + shift, *const value_y = g.value_y.data() + shift;
  const std::size_t second_end = pairs.second_end;
#pragma omp for schedule(static) nowait
  for (std::int64_t q = 0; q < pairs.groups; ++q) {
    const std::size_t p = static_cast<std::size_t>(q) * simd::lanes;
    const auto bond = pairs.bond(p);
    const Float8 f = Model::force_over_length(Float8(1.0f), bond);
    Float8 own_i = simd::load(k_first + p), reaction_i = simd::load(r_first + p);
    Float8 own_j = simd::load(k_second + p), reaction_j = simd::load(r_second + p);
    if constexpr (Damage::enabled) {  // i -> j: i's own and j's reaction; j -> i: the other two
      const auto forward = pairs.still_holds(pairs.intact_bits[q], simd::load(forward_critical + p), bond, p);
      const auto backward = pairs.still_holds(backward_bits[q], simd::load(backward_critical + p), bond, p);
      own_i = simd::where(forward, own_i), reaction_j = simd::where(forward, reaction_j);
      own_j = simd::where(backward, own_j), reaction_i = simd::where(backward, reaction_i);
    }
    const Float8 on_first = own_i + reaction_i, on_second = own_j + reaction_j;
    const Float8 fx = f * bond.yx, fy = f * bond.yy;
    const Float8 minus_on_second = Float8(0.0f) - on_second;
    simd::store(value_x + p, on_first * fx);
    simd::store(value_y + p, on_first * fy);
    simd::store(value_x + second_end + p, minus_on_second * fx);
    simd::store(value_y + second_end + p, minus_on_second * fy);
  }
}

// Each general particle's force density: the sum of its ends' values in its
// row's order (float, as the sweep's sums), written; with damage also its
// damage index over its bonds among general particles and the pairs' states
// copied into general_intact_ (the gather of the sweep then adds the bonds
// into the lattice, as after the double lists).
template <class Damage>
void LatticeKernel::gather_general_pair_forces_in_team(Kinematics& k, double* damage) {
  const auto& g = general_pairs_;
  const BondTable& t = general_bonds_;
  const std::int64_t count = static_cast<std::int64_t>(general_.size());
  const std::uint32_t* const slot = g.slot.data();
  const Real *const value_x = g.value_x.data(), *const value_y = g.value_y.data();
  std::uint8_t* const intact = general_intact_.data();
  const float* const weight = t.damage_weight.data();
  // Set from outside or by the passes before the barrier (GeneralPairs::states_changed, row_changed).
  const bool states_changed = Damage::enabled && g.states_changed != 0;
  std::uint8_t* const row_changed = general_pairs_.row_changed.data();
  double* const own_damage = general_pairs_.damage.data();
#pragma omp for schedule(static) nowait
  for (std::int64_t q = 0; q < count; ++q) {
    const auto i = general_[static_cast<std::size_t>(q)];
    Real fx = 0, fy = 0;
    if (!Damage::enabled || !(states_changed || row_changed[i])) {
      for (auto b = t.offsets[i]; b < t.offsets[i + 1]; ++b) {
        fx += value_x[slot[b]];
        fy += value_y[slot[b]];
      }
      if constexpr (Damage::enabled) damage[i] = own_damage[q];  // as the last gather found it
    } else {
      double intact_area = 0;
      for (auto b = t.offsets[i]; b < t.offsets[i + 1]; ++b) {
        const std::uint32_t s = slot[b];
        fx += value_x[s];
        fy += value_y[s];
        const std::uint8_t state = g.entry_holds(static_cast<std::size_t>(b)) ? 1 : 0;
        intact[b] = state;
        intact_area += static_cast<double>(state) * static_cast<double>(weight[b]);
      }
      damage[i] = own_damage[q] = damage_index(intact_area, t.family_area[i]);
      row_changed[i] = 0;
    }
    k.fx[i] = static_cast<double>(fx);
    k.fy[i] = static_cast<double>(fy);
  }
}

// A state-based model's dilatation terms Lambda e V/|xi| of the pairs, each
// end with its own V/|xi| (theory.md Sec. 5.2); the pairs break here, as the
// lists' and the sweep's dilatation passes (a broken pair's term stays under
// the variants that keep it, Sec. 5.8).
template <class Model, class Damage>
void LatticeKernel::general_pair_dilatation_in_team(const Kinematics& k, std::int64_t first_group,
                                                    std::int64_t last_group) {
  using simd::Float8;
  auto& g = general_pairs_;
  lattice_detail::GeneralPairGroups<Model, Damage::enabled> pairs(g, k, first_group, last_group);
  const std::int64_t shift = first_group * simd::lanes;  // (the pointers start at the first group)
  const Real *const v_first = g.volume_first.data() + shift, *const v_second = g.volume_second.data() + shift;
  Real* const value_x = g.value_x.data() + shift;
  const std::size_t second_end = pairs.second_end;
#pragma omp for schedule(static) nowait
  for (std::int64_t q = 0; q < pairs.groups; ++q) {
    const std::size_t p = static_cast<std::size_t>(q) * simd::lanes;
    const auto bond = pairs.bond(p);
    Float8 term = Model::dilatation_term(
        Float8(1.0f), Model::bond(bond, simd::load(pairs.xi_x + p), simd::load(pairs.xi_y + p), simd::load(pairs.rest + p)));
    if constexpr (Damage::enabled) {
      const auto holds = pairs.holds(q, p, bond);
      if constexpr (!Model::broken_bond_in_dilatation) term = simd::where(holds, term);
    }
    simd::store(value_x + p, simd::load(v_first + p) * term);
    simd::store(value_x + second_end + p, simd::load(v_second + p) * term);
  }
}

// Adds each general particle's dilatation terms (row order, float) to theta_sum_.
inline void LatticeKernel::gather_general_pair_dilatation_in_team() {
  const auto& g = general_pairs_;
  const BondTable& t = general_bonds_;
  const std::int64_t count = static_cast<std::int64_t>(general_.size());
  const std::uint32_t* const slot = g.slot.data();
  const Real* const value_x = g.value_x.data();
#pragma omp for schedule(static) nowait
  for (std::int64_t q = 0; q < count; ++q) {
    const auto i = general_[static_cast<std::size_t>(q)];
    Real sum = 0;
    for (auto b = t.offsets[i]; b < t.offsets[i + 1]; ++b) sum += value_x[slot[b]];
    theta_sum_[i] += static_cast<double>(sum);
  }
}

// A state-based model's pair forces after the dilatation: on i the bond
// part with k_ij and the dilatation part with V_ij/|xi| and both ends'
// theta/m, on j the same with k_ji and V_ji/|xi| along -y (theory.md
// Sec. 5.2, as compute_state_forces gives each direction); the states are
// those the dilatation pass left.
template <class Model, class Damage>
void LatticeKernel::general_pair_state_forces_in_team(const Kinematics& k, std::int64_t first_group,
                                                      std::int64_t last_group) {
  using simd::Float8;
  const simd::FlushSubnormals flush_subnormals;  // see simd.hpp
  auto& g = general_pairs_;
  // The groups [first_group, last_group) as groups 0 .. groups - 1 (see GeneralPairGroups).
  const std::int64_t groups = last_group - first_group, shift = first_group * simd::lanes;
  const std::uint32_t *const first = g.first.data() + shift, *const second = g.second.data() + shift;
  const Real *const xi_x = g.xi_x.data() + shift, *const xi_y = g.xi_y.data() + shift, *const rest = g.rest.data() + shift;
  const Real *const k_first = g.stiffness_first.data() + shift, *const k_second = g.stiffness_second.data() + shift;
  const Real *const v_first = g.volume_first.data() + shift, *const v_second = g.volume_second.data() + shift;
  const double *const ux = k.ux.data(), *const uy = k.uy.data(), *const pressure = pressure_.data();
  const std::uint8_t* const intact_bits = g.intact_bits.data() + (g.intact_bits.empty() ? 0 : first_group);
  Real *const value_x = g.value_x.data() + shift, *const value_y = g.value_y.data() + shift;
  const std::size_t second_end = g.padded;
  const Float8 a(static_cast<Real>(dilatation_coefficient_));
#pragma omp for schedule(static) nowait
  for (std::int64_t q = 0; q < groups; ++q) {
    const std::size_t p = static_cast<std::size_t>(q) * simd::lanes;
    const Float8 eta_x = lattice_detail::pair_combination<false>(ux, first + p, second + p);
    const Float8 eta_y = lattice_detail::pair_combination<false>(uy, first + p, second + p);
    const Float8 rest_length = simd::load(rest + p), xi_x_p = simd::load(xi_x + p), xi_y_p = simd::load(xi_y + p);
    const auto bond = deformed_bond(xi_x_p, xi_y_p, rest_length, eta_x, eta_y);
    const auto terms = Model::bond(bond, xi_x_p, xi_y_p, rest_length);
    const Float8 bond_part = Model::force_over_length(Float8(1.0f), terms);
    const Float8 pressure_sum = lattice_detail::pair_combination<true>(pressure, first + p, second + p);
    const Float8 dilatation_part = Model::dilatation_force_over_length(a, Float8(1.0f), pressure_sum, terms);
    Float8 k_i = simd::load(k_first + p), k_j = simd::load(k_second + p);
    if constexpr (Damage::enabled && Model::broken_bond_keeps_dilatation_force) {
      // A broken pair loses its bond term and keeps its dilatation term (Sec. 5.8).
      const auto holds = simd::mask_of_bits(intact_bits[q]);
      k_i = simd::where(holds, k_i);
      k_j = simd::where(holds, k_j);
    }
    Float8 f_first = simd::fmadd(k_i, bond_part, simd::load(v_first + p) * dilatation_part);
    Float8 f_second = simd::fmadd(k_j, bond_part, simd::load(v_second + p) * dilatation_part);
    if constexpr (Damage::enabled && !Model::broken_bond_keeps_dilatation_force) {
      // A broken pair loses both terms.
      const auto holds = simd::mask_of_bits(intact_bits[q]);
      f_first = simd::where(holds, f_first);
      f_second = simd::where(holds, f_second);
    }
    const Float8 minus_f_second = Float8(0.0f) - f_second;
    simd::store(value_x + p, f_first * bond.yx);
    simd::store(value_y + p, f_first * bond.yy);
    simd::store(value_x + second_end + p, minus_f_second * bond.yx);
    simd::store(value_y + second_end + p, minus_f_second * bond.yy);
  }
}

template <class Model, class Damage>
void LatticeKernel::add_general_dilatation_sums_in_team(const Kinematics& k, std::uint8_t* intact,
                                                        double* sum) const {
  const std::int64_t count = static_cast<std::int64_t>(general_.size());
  if (!dual_horizon_)
    add_dilatation_sums_in_team<Model, Damage>(general_bonds_, k, intact, general_.data(), count, sum);
  else  // each own entry at its owner's critical extension; the dual entries carry other particles' theta
    add_dilatation_sums_with_in_team<Model, Damage>(general_bonds_, k, intact, general_.data(), count, sum,
                                                    PerBondCriticalExtension{general_bonds_.critical_extension.data()},
                                                    OwnEntries{general_bonds_.dual_begin.data()});
}

template <class PairsInTeam>
void LatticeKernel::finish_with_ghost_displacements_in_team(const Kinematics& k, std::int64_t early_groups,
                                                            std::int64_t groups, std::int64_t early_entries,
                                                            PairsInTeam&& pairs_in_team) {
#pragma omp master
  ghost_exchange_.finish_displacements();
#pragma omp barrier
  pairs_in_team(early_groups, groups);
  scatter_displacements_in_team(k, early_entries, grid_entries());
}

template <class Model, class Damage>
void LatticeKernel::compute_state_based(Kinematics& k, std::vector<double>& damage) {
  constexpr bool with_damage = Damage::enabled;
  const std::int64_t general_count = static_cast<std::int64_t>(general_.size());
  const std::int64_t grid_count = static_cast<std::int64_t>(grid_particle_.size());
  const std::int64_t n = static_cast<std::int64_t>(theta_sum_.size());
  const bool in_pairs = general_pairs_in_float();
  refresh_pair_constants();
  // A distributed run: each exchange runs while the pairs of two owned
  // particles and the owned cells' scatter are done (they read no ghost),
  // then the pairs with a ghost end and the ghosts' cells. The double lists
  // read ghosts from their start: with them, each exchange completes first.
  // (The sweep's own order must not change, see "Time loop" in docs/solver.md.)
  const bool overlap = ghost_exchange_.set() && in_pairs;
  if (!overlap) ghost_exchange_.displacements();
  const std::int64_t groups = general_pair_groups();
  const std::int64_t early_groups = overlap ? general_pairs_.owned_groups : groups;
  const std::int64_t early_entries = overlap ? owned_grid_entries_ : grid_count;
  // One team for the whole evaluation (see compute() below); the barriers
  // are where a loop reads what another wrote.
#pragma omp parallel
  {
    if (overlap) {
#pragma omp master
      ghost_exchange_.start_displacements();
    }
    // 1. The dilatation sums: the general particles' bonds among themselves
    //    (lists) and the sweep's pairs (both break the over-stretched bonds).
#pragma omp for schedule(static)
    for (std::int64_t i = 0; i < n; ++i) theta_sum_[static_cast<std::size_t>(i)] = 0.0;
    if (in_pairs)
      general_pair_dilatation_in_team<Model, Damage>(k, 0, early_groups);
    else
      add_general_dilatation_sums_in_team<Model, Damage>(k, with_damage ? general_intact_.data() : nullptr,
                                                         theta_sum_.data());
    scatter_displacements_in_team(k, 0, early_entries);
    if (overlap)
      finish_with_ghost_displacements_in_team(k, early_groups, groups, early_entries,
                                              [&](std::int64_t first, std::int64_t last) {
                                                general_pair_dilatation_in_team<Model, Damage>(k, first, last);
                                              });
#pragma omp barrier
    if (in_pairs) gather_general_pair_dilatation_in_team();  // before the sweep's barrier, as theta_sum_'s grid part needs
    two_colour_sweep_in_team([this](std::size_t first, std::size_t last) { dilatation_rows<Model, Damage>(first, last); });
#pragma omp for schedule(static)
    for (std::int64_t g = 0; g < grid_count; ++g) {
      const auto c = static_cast<std::size_t>(grid_cell_[g]);
      theta_sum_[grid_particle_[g]] += static_cast<double>(own_theta_[c] + far_theta_[c]);
      far_theta_[c] = Real(0);  // ready for the next step, as the force sums
    }
    // 2. theta_i = 2/m_i sum, and theta_i/m_i, which the forces read at both ends.
#pragma omp for schedule(static)
    for (std::int64_t i = 0; i < n; ++i) {
      const double m = weighted_volume_[i];
      theta_[i] = m > 0 ? 2.0 * theta_sum_[i] / m : 0.0;  // a particle without bonds has no dilatation
      pressure_[i] = m > 0 ? theta_[i] / m : 0.0;
    }
    // On a process of a distributed run a ghost's sums above miss the bonds
    // of its family that are not local: its theta_j / m_j comes from its
    // owner (MPI from the thread that initialised it), before anything reads
    // it; with the pairs, the owned cells' scatter and the pairs of two
    // owned particles run while it travels.
    if (ghost_exchange_.set()) {
#pragma omp master
      {
        ghost_exchange_.start_values(pressure_);
        if (!overlap) ghost_exchange_.finish_values(pressure_);
      }
      if (!overlap) {
#pragma omp barrier
      }
    }
#pragma omp for schedule(static) nowait
    for (std::int64_t g = 0; g < early_entries; ++g)
      pressure_grid_[static_cast<std::size_t>(grid_cell_[g])] = static_cast<Real>(pressure_[grid_particle_[g]]);
    if (in_pairs) general_pair_state_forces_in_team<Model, Damage>(k, 0, early_groups);
    if (overlap) {
#pragma omp master
      ghost_exchange_.finish_values(pressure_);
#pragma omp barrier
#pragma omp for schedule(static) nowait
      for (std::int64_t g = early_entries; g < grid_count; ++g)
        pressure_grid_[static_cast<std::size_t>(grid_cell_[g])] = static_cast<Real>(pressure_[grid_particle_[g]]);
      general_pair_state_forces_in_team<Model, Damage>(k, early_groups, groups);
    }
    // 3. The forces: the general particles' bonds among themselves, and the sweep's pairs.
    if (in_pairs) {
#pragma omp barrier
      gather_general_pair_forces_in_team<Damage>(k, with_damage ? damage.data() : nullptr);
    } else {
      if (!dual_horizon_)
        compute_state_forces_in_team<Model, Damage>(general_bonds_, k, with_damage ? general_intact_.data() : nullptr,
                                                    with_damage ? damage.data() : nullptr, pressure_.data(),
                                                    dilatation_coefficient_, general_.data(), general_count);
      else  // own entries with the particle's theta_i / m_i, dual entries with their owners' (theory.md Sec. 6.8)
        compute_dual_horizon_state_forces_in_team<Model, Damage>(
            general_bonds_, k, with_damage ? general_intact_.data() : nullptr, with_damage ? damage.data() : nullptr,
            pressure_.data(), dilatation_coefficient_, general_.data(), general_count);
#pragma omp barrier
    }
    two_colour_sweep_in_team([this](std::size_t first, std::size_t last) { state_force_rows<Model, Damage>(first, last); });
    gather_forces_in_team<Damage, false>(k, damage, nullptr, general_bonds_.family_area);
  }
}

template <class Rows>
void LatticeKernel::two_colour_sweep_in_team(Rows&& rows) {
  // Two colours of row blocks: a block's far-end sums reach only into the
  // next block. The barrier at the end of each colour's loop is needed.
  const std::int64_t blocks = static_cast<std::int64_t>((rows_.size() + block_rows_ - 1) / block_rows_);
  for (std::int64_t colour = 0; colour < 2; ++colour) {
#pragma omp for schedule(dynamic, 1)
    for (std::int64_t b = colour; b < blocks; b += 2)
      rows(static_cast<std::size_t>(b) * block_rows_,
           std::min(rows_.size(), static_cast<std::size_t>(b + 1) * block_rows_));
  }
}

template <class Model, class Damage>
void LatticeKernel::compute(Kinematics& k, std::vector<double>& damage, std::vector<double>* energy_density) {
  allocate_step_sums();
  compute_in_one_team<Model, Damage>(k, damage, energy_density);
  general_pairs_.states_changed = 0;  // the gathers have copied what changed
}

template <class Model, class Damage>
void LatticeKernel::compute_in_one_team(Kinematics& k, std::vector<double>& damage,
                                        std::vector<double>* energy_density) {
  if constexpr (Model::has_pre_pass) {
    compute_state_based<Model, Damage>(k, damage);
  } else {
    constexpr bool with_damage = Damage::enabled;
    std::uint8_t* const general_intact = with_damage ? general_intact_.data() : nullptr;
    const bool in_pairs = general_pairs_in_float();
    // A distributed run: the ghosts' displacements travel while the pairs of
    // two owned particles and the owned cells' scatter are done (they read no
    // ghost); the lists read ghosts from their start (see compute_state_based).
    const bool overlap = ghost_exchange_.set() && in_pairs;
    if (!overlap) ghost_exchange_.displacements();
    const std::int64_t groups = general_pair_groups(), grid_count = grid_entries();
    const std::int64_t early_groups = overlap ? general_pairs_.owned_groups : groups;
    const std::int64_t early_entries = overlap ? owned_grid_entries_ : grid_count;
    if (energy_density) {
      energy_density->assign(k.ux.size(), 0.0);
      if (energy_.size() != ux_.size()) energy_.assign(ux_.size(), Real(0));
      for (auto& finer : finer_)
        if (finer.energy_.size() != finer.ux_.size()) finer.energy_.assign(finer.ux_.size(), Real(0));
    }
    // One team of threads for the whole evaluation: the loops that do not
    // read each other's results run back to back without a wait between them
    // (the `_in_team` loops end without a barrier). An ordinary step starts
    // one parallel region and waits at 3 barriers and its end, where it
    // started 6 regions, each ending in a wait; on a shared machine a thread
    // taken off its core holds up the others at every such wait.
#pragma omp parallel
    {
      if (overlap) {
#pragma omp master
        ghost_exchange_.start_displacements();
      }
      // General particles: their bonds to general particles (neighbour
      // lists); and the displacements onto the grid, for the sweep.
      if (in_pairs)
        general_pair_forces_in_team<Model, Damage>(k, 0, early_groups);
      else if (!dual_horizon_)
        compute_bond_forces_in_team<Model, Damage>(general_bonds_, k, general_intact,
                                                   with_damage ? damage.data() : nullptr, general_.data(),
                                                   static_cast<std::int64_t>(general_.size()));
      else  // each bond breaks at its owner's critical extension (theory.md Sec. 6.2)
        compute_bond_forces_with_in_team<Model, Damage>(
            general_bonds_, k, general_intact, with_damage ? damage.data() : nullptr, general_.data(),
            static_cast<std::int64_t>(general_.size()),
            PerBondCriticalExtension{general_bonds_.critical_extension.data()});
      scatter_displacements_in_team(k, 0, early_entries);
      for (auto& finer : finer_) finer.scatter_displacements_in_team(k, 0, finer.grid_entries());
      if (overlap)
        finish_with_ghost_displacements_in_team(k, early_groups, groups, early_entries,
                                                [&](std::int64_t first, std::int64_t last) {
                                                  general_pair_forces_in_team<Model, Damage>(k, first, last);
                                                });
#pragma omp barrier
      // The pairs' values into their ends (before the sweep's first barrier,
      // which the gather of its sums waits at).
      if (in_pairs) gather_general_pair_forces_in_team<Damage>(k, with_damage ? damage.data() : nullptr);
      if (!energy_density) {  // an ordinary step: the sweep without any energy arithmetic
        // Level 0's sweep, then each finer level's (theory.md Sec. 8.9): their
        // cells and particles are their own, and a general particle next to
        // a finer sweep borders that one alone.
        for (LatticeKernel* sweep = this; sweep; sweep = next_sweep(sweep)) {
          sweep->two_colour_sweep_in_team(
              [sweep](std::size_t first, std::size_t last) { sweep->sweep_rows<Model, Damage, false>(first, last); });
          sweep->gather_forces_in_team<Damage, false>(k, damage, nullptr, general_bonds_.family_area);
        }
      } else {
        // An energy row: the general particles' bonds among themselves (their
        // states as this step left them), then the sweep's pairs.
        if (in_pairs) {
#pragma omp barrier
        }
        add_bond_energy_density_in_team<Model>(general_bonds_, k, general_intact, *energy_density);
        for (LatticeKernel* sweep = this; sweep; sweep = next_sweep(sweep)) {
          sweep->two_colour_sweep_in_team(
              [sweep](std::size_t first, std::size_t last) { sweep->sweep_rows<Model, Damage, true>(first, last); });
          sweep->gather_forces_in_team<Damage, true>(k, damage, energy_density->data(), general_bonds_.family_area);
        }
      }
    }
  }
}

template <class Damage, bool SumEnergy>
void LatticeKernel::gather_forces_in_team(Kinematics& k, std::vector<double>& damage, double* energy_density,
                                          const std::vector<double>& family_area) {
  constexpr bool with_damage = Damage::enabled;
  // A cell's sums: its own pairs (forward) plus the far ends of the pairs of
  // the cells behind it. The far sums are cleared once read, ready for the
  // next step (other cells' far sums are never read).
  const auto take_sums = [&](std::size_t cell, double& fx, double& fy) {
    fx = static_cast<double>(own_fx_[cell] + far_fx_[cell]);
    fy = static_cast<double>(own_fy_[cell] + far_fy_[cell]);
    far_fx_[cell] = far_fy_[cell] = Real(0);
  };
  // The same for the strain energy density of an energy row.
  const auto take_energy = [&](std::size_t cell, std::uint32_t i) {
    energy_density[i] += static_cast<double>(energy_[cell]);
    energy_[cell] = Real(0);
  };
  const std::int64_t lattice_count = static_cast<std::int64_t>(particle_.size());
  const double inverse_family_units = family_units_ > 0 ? 1.0 / family_units_ : 0.0;
  // Lattice and border particles have cells and force sums of their own: the
  // two loops need no wait between them.
#pragma omp for schedule(static) nowait
  for (std::int64_t q = 0; q < lattice_count; ++q) {
    const auto i = particle_[q];
    const auto c = static_cast<std::size_t>(particle_cell_[q]);
    take_sums(c, k.fx[i], k.fy[i]);
    if constexpr (SumEnergy) take_energy(c, i);
    // D_i = broken share of the family [Peng et al. 2023, Eq. (10)]: exactly 0 while every bond holds.
    if constexpr (with_damage) damage[i] = broken_units_[c] * inverse_family_units;
  }
  const std::int64_t border_count = static_cast<std::int64_t>(border_.size());
#pragma omp for schedule(static) nowait
  for (std::int64_t q = 0; q < border_count; ++q) {
    const auto i = border_[q];
    const auto c = static_cast<std::size_t>(border_cell_[q]);
    double fx = 0, fy = 0;
    take_sums(c, fx, fy);
    if constexpr (SumEnergy) take_energy(c, i);
    k.fx[i] += fx;
    k.fy[i] += fy;
    if constexpr (with_damage) {
      // The neighbour lists counted the bonds to lattice particles as missing;
      // they are missing only as far as they broke. With dual horizons a pair
      // is a bond and its dual bond, both in the row's family area.
      const double intact_lattice_area = (border_lattice_area_[q] - broken_units_[c] * unit_area_) * entries_per_pair_;
      const double d = damage[i] - intact_lattice_area / family_area[i];
      // Round-off of the two sums: below 1e-9 is 0 (one bond weighs ~1e-2), above 1 is 1.
      damage[i] = d < 1e-9 ? 0.0 : std::min(d, 1.0);
    }
  }
}

}  // namespace pd::solver
