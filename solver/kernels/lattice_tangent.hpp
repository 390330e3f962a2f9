#pragma once
// The lattice kernel's tangent product (lattice_kernel.hpp, force_change):
// the change of the force densities at the displacements u along a direction
// d, i.e. minus the Hessian of the energy at u times d per unit area, with
// the deformed bond directions and the geometric term (Model::force_change,
// theory.md Secs. 4.8 and 4.12). The quasi-static solver's correction rounds
// use it as their Newton matrix (mixed_precision.cpp).
//
// The sweep's pairs in float, 8 cells at a time, as the force sweep
// (lattice_sweep.hpp): each pair once, its change added to one end and
// subtracted from the other; broken pairs read from the state bits, never
// changed. The bond's deformed direction and e/|y| come from u rounded to
// float (relative errors of about 1e-7 in n and 6e-8 |u| / |e| in e/|y|, which
// only size the minimiser's steps: the residual that decides convergence is
// the double pass). The general particles' bonds among themselves come from
// their lists in double (bond_force_change_in_team).
#include <algorithm>
#include <cstdint>

#include "deformed_bond.hpp"
#include "effects.hpp"
#include "lattice_kernel.hpp"
#include "lattice_sweep.hpp"
#include "neighbor_kernel.hpp"
#include "simd.hpp"

namespace pd::solver {

template <class Model>
void LatticeKernel::tangent_rows(std::size_t first_row, std::size_t last_row) {
  using simd::Float8;
  const simd::FlushSubnormals flush_subnormals;  // see simd.hpp
  const std::size_t half = offset_.size();
  const bool with_states = !state_bits_.empty();
  const Real *const ux = ux_.data(), *const uy = uy_.data(), *const dx = dx_.data(), *const dy = dy_.data();
  const Real *const lambda = lambda_.data(), *const lattice = lattice_mask_.data();
  Real *const own_fx = own_fx_.data(), *const own_fy = own_fy_.data();
  Real *const far_fx = far_fx_.data(), *const far_fy = far_fy_.data();
  lattice_detail::for_each_tile_step(rows_, row_length_, lanes, first_row, last_row,
                                     [&](const RowSpan& span, std::int64_t step, std::int64_t cell) {
    const Real* ux0 = ux + cell;
    const Real* uy0 = uy + cell;
    const Real* dx0 = dx + cell;
    const Real* dy0 = dy + cell;
    const Real* lambda0 = lambda + cell;
    const Real* lattice0 = lattice + cell;
    const std::uint8_t* states =
        with_states ? state_bits_.data() + span.first_state / lanes + static_cast<std::uint64_t>(step) * half : nullptr;
    const Float8 ux_i = simd::load(ux0), uy_i = simd::load(uy0), dx_i = simd::load(dx0), dy_i = simd::load(dy0);
    const Float8 lambda_i = simd::load(lambda0), lattice_i = simd::load(lattice0);
    Float8 ax(0.0f), ay(0.0f);
    for (std::size_t h = 0; h < half; ++h) {
      const std::int64_t o = offset_[h];
      const auto bond = deformed_bond(Float8(xi_x_[h]), Float8(xi_y_[h]), Float8(rest_[h]),
                                      simd::load(ux0 + o) - ux_i, simd::load(uy0 + o) - uy_i);
      // Only pairs with a lattice end, and intact ones, count (as in the force sweep).
      Float8 counts = simd::max(lattice_i, simd::load(lattice0 + o));
      if (with_states) counts = simd::where(simd::mask_of_bits(states[h]), counts);
      const Float8 stiffness = counts * Float8(half_stiffness_[h]) * (lambda_i + simd::load(lambda0 + o));
      Float8 gx, gy;
      Model::force_change(stiffness, bond, simd::load(dx0 + o) - dx_i, simd::load(dy0 + o) - dy_i, gx, gy);
      ax += gx;
      ay += gy;
      Real* gxj = far_fx + cell + o;
      Real* gyj = far_fy + cell + o;
      simd::store(gxj, simd::load(gxj) - gx);
      simd::store(gyj, simd::load(gyj) - gy);
    }
    simd::store(own_fx + cell, ax);
    simd::store(own_fy + cell, ay);
  });
}

template <class Model>
void LatticeKernel::force_change(Kinematics& k, const std::vector<double>& dx, const std::vector<double>& dy) {
  static_assert(!Model::has_pre_pass, "bond-based models only");
  allocate_step_sums();
  if (dx_.size() != ux_.size()) {
    dx_.assign(ux_.size(), Real(0));
    dy_.assign(ux_.size(), Real(0));
  }
  k.fx.resize(k.ux.size());
  k.fy.resize(k.ux.size());
  std::vector<double> no_damage;  // the gather writes no damage (DamageOff)
  const std::int64_t scattered = static_cast<std::int64_t>(grid_particle_.size());
#pragma omp parallel
  {
    // The general particles' bonds among themselves (lists, double; written,
    // so lattice particles get theirs from the gather below), and u and d
    // onto the grid.
    bond_force_change_in_team<Model>(general_bonds_, k.ux.data(), k.uy.data(), dx.data(), dy.data(),
                                     general_intact_.empty() ? nullptr : general_intact_.data(), general_.data(),
                                     static_cast<std::int64_t>(general_.size()), k.fx.data(), k.fy.data());
#pragma omp for schedule(static) nowait
    for (std::int64_t g = 0; g < scattered; ++g) {
      const auto i = grid_particle_[g];
      const auto c = static_cast<std::size_t>(grid_cell_[g]);
      ux_[c] = static_cast<Real>(k.ux[i]);
      uy_[c] = static_cast<Real>(k.uy[i]);
      dx_[c] = static_cast<Real>(dx[i]);
      dy_[c] = static_cast<Real>(dy[i]);
    }
#pragma omp barrier
    two_colour_sweep_in_team([this](std::size_t first, std::size_t last) { tangent_rows<Model>(first, last); });
    gather_forces_in_team<DamageOff, false>(k, no_damage, nullptr, general_bonds_.family_area);
  }
}

}  // namespace pd::solver
