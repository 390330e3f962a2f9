#pragma once
// The surface correction of the ordinary state-based model (theory.md
// Sec. 5.7): two factors, one for each part of
//   W_i = a theta_i^2 + 1/4 sum_j c_d G_i(n_ij) s_ij^2 E_ij,
//   theta_i = (2 / m_i) sum_j D_ij Lambda_ij s_ij V_ij,   m_i = sum_j D_ij V_ij.
// Under a homogeneous strain the stretch of a bond with direction
// n = (cos t, sin t) is s(t) = tau + p cos 2t + q sin 2t (tau the mean
// normal strain, p and q the deviatoric components), so
//  - theta_i is exact (2 tau) for every homogeneous strain iff the family's
//    D V-weighted moments of cos 2t and sin 2t vanish, and
//  - the bond sum is the continuum's iff the G_i E-weighted moments of all five
//    harmonics h(n) (surface_correction.hpp) are those of the full disk.
// Isotropic expansion (tau only) calibrates the zeroth moments, simple shear
// in three orientations (0, 22.5 and 45 degrees: p only, p = q, q only) the
// fourth-order ones; the second-order ones make uniaxial states exact too.
//
// Distortion: each listed particle has its own factor G_i(n) = c_i . h(n)
// on its bonds to listed particles and c_i0 on its bonds to stencil
// particles, solved from its own family alone (a 5 x 5 system):
//   sum_j G_i(n_ij) E_ij h(n_ij) = T.
// W_i holds its own end's share of each bond's energy, with G_i (Osb::
// energy_at_own_end), and is then the classical value under every
// homogeneous strain. The force uses the mean g_ij = (G_i + G_j) / 2, so it
// is equal and opposite on the pair and the derivative of sum_i A_i W_i
// (where A_i E_ij = A_j E_ji, as every force of theory.md Sec. 5.2 assumes).
// Stencil particles (whole families) keep a scalar lambda_i, 1 to round-off,
// and the bonds with a stencil end carry scalars only, which is all the
// lattice kernel can hold.
//
// Dilatation: the bond factor D_ij = D_ji is the mean of the two ends' factors
// (forces of Sec. 5.2 unchanged, with D_ij V_ij for V_ij):
//   D_ij = 1 + (d_i + d_j) . h(n) / 2   (bonds between two listed particles)
//   D_ij = 1                            (a stencil particle at either end)
// with d_i on (cos 2t, sin 2t), and the d_i of all listed particles solve the
// equations sum_j D_ij V_ij (cos 2t, sin 2t) = 0 of every listed particle
// together (damped block Jacobi).
//
// A listed particle whose bonds to listed particles cannot carry the
// harmonics independently, or whose own G_i falls below lowest_shape at one
// of its bonds, keeps fewer harmonics: (1, cos 4t, sin 4t), then a scalar.
// One whose D_ij would fall below 0 at one of its bonds keeps D = 1 (d_i = 0).
//
// In the form the bond set-up reads (surface_correction.hpp):
// lambda_i = c_i0, shapes S_i = 1 + (0, c_i1, ..., c_i4) / c_i0 for every
// listed particle (so that own_correction gives G_i and bond_correction
// g_ij), and `dilatation` the d_i of every listed particle.
#include <cstdint>
#include <vector>

#include "surface_correction.hpp"

namespace pd::solver {

// The OSB factors on weights that already carry the angular factor kappa
// (part 1 of surface_correction.hpp). Bonds that carry force: all stencil
// bonds, and the listed bonds with listed_intact[b.index] != 0. The iteration
// stops when no factor changes by more than `tolerance`. Without
// `dilatation_factors` the d_i are left at 0 (every listed particle keeps its
// row) for a distributed run to iterate on its slabs
// (iterate_dilatation_factors); the distortion factors, each from its own
// family, are made either way.
SurfaceCorrectionResult compute_state_surface_correction(const ParticleSet& particles, const Families& families,
                                                         const PerBond<double>& energy_weights,
                                                         const std::vector<std::uint8_t>& listed_intact,
                                                         double horizon, double tolerance = 1e-7,
                                                         bool dilatation_factors = true);

// The dilatation factors alone, from the rows and values in `dilatation`
// (those of compute_state_surface_correction without its dilatation factors),
// by the same damped block Jacobi and the same rounds. With `exchange` on a
// process's local particles (owned ones with their whole families, then
// ghosts with none; a particle is listed where it has a row) each process
// updates its owned particles' factors, the owners send the ghosts' (both
// components), and the stopping test and the rounds' drops are the
// processes', so every factor equals a one-process run's bit for bit, as
// iterate_scalar_factors does for the bond-based factors. Returns the
// iterations; pd::Error when they do not converge.
int iterate_dilatation_factors(const ParticleSet& particles, const Families& families,
                               const PerBond<double>& energy_weights, const std::vector<std::uint8_t>& listed_intact,
                               double tolerance, DirectionalShapes& dilatation,
                               const ScalarFactorExchange* exchange = nullptr);

}  // namespace pd::solver
