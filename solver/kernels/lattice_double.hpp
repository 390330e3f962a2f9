#pragma once
// The lattice kernel's forces in double precision (lattice_kernel.hpp,
// compute_in_double): for an energy minimisation near convergence. The float
// sweep rounds the displacements to 24 bits, so a bond's extension carries an
// error of about 6e-8 |u| against e ~ strain |xi|; summed over a plate this
// leaves a residual floor of 1e-5 .. 1e-4 of the reactions at fine grids
// (docs/solver.md, "Fast kernels"), above the minimiser's usual tolerance
// 1e-6. This pass is the sweep's twin in double: the same pairs (each once,
// from the forward half of the stencil), the same pair law
// (Model::force_over_length, deformed_bond.hpp) and the same stiffness
// 0.5 (lambda_i + lambda_j) k_pair, scalar and from the stencil (nothing per
// bond is stored), a few times slower per pair than the float sweep. The
// general particles' bonds among themselves come from their lists, which are
// double already. Bond states are read, never changed (hold_bond_states).
#include <algorithm>
#include <cmath>
#include <cstdint>

#include "deformed_bond.hpp"
#include "effects.hpp"
#include "error.hpp"
#include "lattice_kernel.hpp"
#include "neighbor_kernel.hpp"

namespace pd::solver {

template <class Model>
void LatticeKernel::compute_in_double(Kinematics& k, const std::vector<double>& lambda, std::vector<double>& scratch) {
  static_assert(!Model::has_pre_pass, "bond-based models only");
  if (!held_)
    throw Error("lattice kernel: forces in double need held bond states (hold_bond_states)");
  // General particles: their bonds to general particles (lists, double);
  // lattice particles start from 0. The pairs below add to both. (The lists'
  // damage sums go to `scratch`: the index needs the pairs' share too, which
  // compute() adds; the states do not change here.)
  compute_bond_forces<Model, DamageOn>(general_bonds_, k, general_intact_.empty() ? nullptr : general_intact_.data(),
                                       scratch.data(), general_.data(), static_cast<std::int64_t>(general_.size()));
  for (auto i : particle_) k.fx[i] = k.fy[i] = 0.0;
  const std::size_t half = offset_.size();
  std::vector<double> xi_x(half), xi_y(half), rest(half);
  for (std::size_t h = 0; h < half; ++h) {
    // Forward offsets go up a row or right within one (as strain_energy_density).
    const std::int64_t dj = (offset_[h] + halo_) / row_length_, di = offset_[h] - dj * row_length_;
    xi_x[h] = static_cast<double>(di) * spacing_;
    xi_y[h] = static_cast<double>(dj) * spacing_;
    rest[h] = std::sqrt(xi_x[h] * xi_x[h] + xi_y[h] * xi_y[h]);
  }
  const bool with_states = !state_bits_.empty();
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
        double fx_i = 0, fy_i = 0;
        for (std::size_t h = 0; h < half; ++h) {
          const auto j = particle_at_[static_cast<std::size_t>(c + offset_[h])];
          if (j == Families::none || !(is_lattice_[i] || is_lattice_[j])) continue;  // not a pair of the sweep
          if (with_states && ((states[h] >> lane) & 1u) == 0) continue;               // broken
          const auto bond = deformed_bond(xi_x[h], xi_y[h], rest[h], k.ux[j] - ux_i, k.uy[j] - uy_i);
          const double f = Model::force_over_length(0.5 * (lambda_i + lambda[j]) * pair_stiffness_[h], bond);
          fx_i += f * bond.yx;
          fy_i += f * bond.yy;
          k.fx[j] -= f * bond.yx;
          k.fy[j] -= f * bond.yy;
        }
        k.fx[i] += fx_i;
        k.fy[i] += fy_i;
      }
    }
  };
  // Two colours of row blocks, as the float sweep: a block adds only into
  // itself and the next one, so every particle's sum has a fixed order.
  const std::int64_t blocks = static_cast<std::int64_t>((rows_.size() + block_rows_ - 1) / block_rows_);
  for (std::int64_t colour = 0; colour < 2; ++colour) {
#pragma omp parallel for schedule(dynamic, 1)
    for (std::int64_t b = colour; b < blocks; b += 2)
      sweep_block(static_cast<std::size_t>(b) * block_rows_,
                  std::min(rows_.size(), static_cast<std::size_t>(b + 1) * block_rows_));
  }
}

}  // namespace pd::solver
