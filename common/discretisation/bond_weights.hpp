#pragma once
// Quadrature weights of the bond sums (theory.md Sec. 2).
//
// The PMB energy density of particle i is a sum over its family of
// 1/4 c s_ij^2 |xi_ij| phi_ij A_j, the midpoint rule for the integral
// int_{H_i} 1/4 c s^2 |xi| dA over the neighbour cells. Two weightings:
//
//  - partial_volume: E_ij = phi_ij A_j |xi_ij| with phi from the particle file
//    [Peng, Chen, Bobaru 2023, Eq. (11)]. The cell-centre distance |xi_ij| stands
//    for the distance over the whole (partial) cell, which overestimates the
//    bulk energy on a square lattice by 2.2 % (m = 3) and 1.1 % (m = 4)
//    for a uniaxial strain (tests/solver/test_elastic_energy.cpp).
//  - distance_moment (default): E_ij = int_{cell_j ∩ disk(x_i, delta)} |x - x_i| dA,
//    the exact first moment of distance over the part of cell j inside the
//    horizon, from the cell polygons of the particle file (scaled by
//    A_j / polygon area for curved-edge cells). Only the bond direction is
//    sampled at the cell centre; the bulk error under uniaxial strain drops
//    below 0.1 %, and under isotropic expansion to the missing own cell
//    (-0.7 % at m = 3, -0.3 % at m = 4).
//
// The bond stiffness is then k_ij = 0.5 (lambda_i + lambda_j) c E_ij / |xi_ij|^2
// (the solver's bond set-up), so that W_i = 1/4 sum_j k_ij e_ij^2 =
// 1/4 sum_j 0.5 (lambda_i + lambda_j) c s_ij^2 E_ij.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "cell_disk_memo.hpp"
#include "compact_families.hpp"
#include "geometry.hpp"
#include "particle_file.hpp"

namespace pd {

enum class BondWeights { distance_moment, partial_volume };

inline const char* to_string(BondWeights w) {
  return w == BondWeights::distance_moment ? "distance_moment" : "partial_volume";
}

// The weights of an earlier particle set that a later one shares
// (adaptive refinement: the set before a split; theory.md Sec. 8.4).
// `same_family[i]` for particle i of the later set: the particle of the
// earlier set at the same place with the same horizon whose family is the
// same bonds, in the same order, to neighbours with the same cells, or
// Families::none. Such a particle's weights are taken over bond by bond where
// the later families compute them the same way (the same square table, or
// both from the cell polygons), so that the result equals the computation
// from scratch bit for bit; the other bonds are computed.
//
// `origin[i]` (optional; empty: not known) is particle i's particle in the
// earlier set, or Families::none for a particle new in the later one. With
// it, a particle whose family and own route are unchanged, in a set where no
// particle changed its level, takes its whole row over at once instead of
// comparing its bonds' routes one by one (the same weights; theory.md Sec. 8.4).
struct EarlierBondWeights {
  const Families* families = nullptr;
  const PerBond<double>* weights = nullptr;
  std::vector<std::uint32_t> same_family;
  std::vector<std::uint32_t> origin;
  // The earlier set's particles whose families were listed after they were
  // collected (the pre-cracks' cut particles; sorted): whether they matched
  // their stencil is not known (FamilyCollector; null: not known for any).
  const std::vector<std::uint32_t>* listed_before = nullptr;
  // The later set's particles to list whatever their match with the stencil,
  // as Families::make_listed lists them (the pre-cracks' cut particles,
  // found before the families are collected; sorted; null: none).
  const std::vector<std::uint32_t>* listed = nullptr;
};

// E_ij for every bond of `families` [m^3], over each particle's own horizon;
// `particles` provides positions, areas, horizons and cell polygons.
// `earlier` (optional): weights to take over instead of computing them.
// `computed` (optional) receives the listed bonds whose weights were computed.
// `memo` (optional): distance moments of four-vertex cells to look up, and to
// keep those computed here in.
PerBond<double> bond_energy_weights(const ParticleSet& particles, const Families& families, BondWeights weights,
                                    const EarlierBondWeights* earlier = nullptr, std::size_t* computed = nullptr,
                                    CellDiskMemo* memo = nullptr);

// int_{polygon ∩ disk(center, radius)} |x - center| dA for a simple polygon
// (either orientation; the result is >= 0). Exact: a signed sum over the edges
// of closed-form integrals in polar coordinates about the centre.
double polygon_disk_distance_moment(const double* vx, const double* vy, std::size_t n, Vec2 center,
                                    double radius);

}  // namespace pd
