#pragma once
// The displacement gradient at a particle, estimated from its family by
// weighted least squares (the peridynamic deformation gradient, docs/theory.md
// Sec. 10.1): the strain a continuum model would see in a PD displacement
// field, e.g. to compare stresses at a hole with an FEM solution.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

#include "particle_file.hpp"

namespace pd {

// d u_a / d x_b (dimensionless); `du_dx[a][b]`, a, b in {0 = x, 1 = y}.
struct DisplacementGradient {
  double du_dx[2][2] = {{0, 0}, {0, 0}};
};

// G_i = (sum_j w_ij (u_j - u_i) (x) xi_ij) K_i^-1,  K_i = sum_j w_ij xi_ij (x) xi_ij,
// w_ij = phi_ij V_j, over the family of i (theory.md Sec. 10.1). Exact for a
// linear displacement field whatever the family's shape, as long as K_i is
// invertible (pd::Error naming the particle if it is not, e.g. all neighbours
// on one line). `ux`, `uy` per particle [m].
DisplacementGradient family_displacement_gradient(const ParticleSet& particles, const std::vector<double>& ux,
                                                  const std::vector<double>& uy, std::size_t i);

// The same over the members of i's family that are not listed in
// [left_out_begin, left_out_end) (sorted particle indices), e.g. the partners
// of i's broken bonds, so that a crack's opening does not enter the gradient;
// none if those members span no area.
std::optional<DisplacementGradient> family_displacement_gradient_without(const ParticleSet& particles,
                                                                         const std::vector<double>& ux,
                                                                         const std::vector<double>& uy,
                                                                         std::size_t i,
                                                                         const std::uint32_t* left_out_begin,
                                                                         const std::uint32_t* left_out_end);

// The same for every particle.
std::vector<DisplacementGradient> family_displacement_gradients(const ParticleSet& particles,
                                                                const std::vector<double>& ux,
                                                                const std::vector<double>& uy);

}  // namespace pd
