#pragma once
// The bond table of the total strain energy, for energy minimisation.
//
// The dynamic kernel sums, for particle i, f_i = sum_j k_ij e_ij y_ij/|y_ij|
// (bonds.hpp). It is minus the gradient of the total strain energy
//   Pi = h sum_i A_i W_i,  W_i = 1/4 sum_j k_ij e_ij^2      (theory.md Sec. 1)
// divided by A_i h only when A_i k_ij = A_j k_ji for every pair. That holds on
// uniform grids, but not on non-uniform ones: the partial-volume factor of j in
// i's horizon differs from that of i in j's, and j may even lie in i's family
// without i lying in j's. A minimiser needs the exact gradient of the energy it
// minimises, so the quasi-static solver uses this table instead: the union of
// both directions of every pair with
//   k^E_ij = (A_i k_ij + A_j k_ji) / (2 A_i)     (k = 0 for a missing direction),
// for which A_i k^E_ij is symmetric, h sum_i A_i 1/4 sum_j k^E_ij e_ij^2 = Pi
// (the same energy), and A_i h times the kernel's force density with this table
// is exactly -dPi/dx_i. On uniform grids k^E = k.
//
// The energy's stiffness is W_i's own (BondTable::energy_stiffness_of, i's
// own surface-correction factor where a model splits it, theory.md Sec. 5.7).
// A table with dilatation weights (the state-based model, theory.md Sec. 5.6)
// keeps in addition, per bond of the union, W_i's own constants: the
// energy_stiffness k^W_ij and the dilatation weight w_ij = V_ij/|xi_ij| (both
// 0 for a direction that exists only as the partner of another), the
// partner's weight A_j w_ji / A_i (partner_volume_over_length), and m_i
// (weighted_volume). W_i computed on this table is the dynamic model's.
#include <vector>

#include "bond_table.hpp"

namespace pd::solver {

// `bonds` must carry damage weights (built with damage on); in the result a
// direction that exists only as the partner of another carries damage weight
// 0 (it is not part of its particle's family for the damage index), and
// family_area is that of `bonds`. Rest lengths are recomputed from the
// positions so that both directions of a pair are equal bit for bit.
// `bonds` is taken (moved in) and released before the result is built: the
// set-up's memory peak is this function's.
BondTable energy_bond_table(BondTable bonds, const std::vector<double>& x, const std::vector<double>& y,
                            const std::vector<double>& area);

// Largest relative asymmetry |A_i k_ij - A_j k_ji| / max(A_i k_ij, A_j k_ji)
// over the pairs of `bonds` (0 on uniform grids): how far the dynamic kernel's
// forces are from an energy gradient.
double largest_stiffness_asymmetry(const BondTable& bonds, const std::vector<double>& area);

}  // namespace pd::solver
