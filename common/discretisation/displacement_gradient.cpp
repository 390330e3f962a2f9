#include "displacement_gradient.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "error.hpp"

namespace pd {

namespace {

// G_i over the members j of i's family with counts(j); false (g untouched)
// if those members span no area, `members` then their number.
template <class Counts>
bool gradient_over(const ParticleSet& p, const std::vector<double>& ux, const std::vector<double>& uy, std::size_t i,
                   Counts counts, DisplacementGradient& g, std::size_t& members) {
  // Moment K (symmetric) and the right-hand side B = sum w du (x) xi.
  double kxx = 0, kxy = 0, kyy = 0;
  double b[2][2] = {{0, 0}, {0, 0}};
  members = 0;
  for (auto k = p.family_offsets[i]; k < p.family_offsets[i + 1]; ++k) {
    const auto j = p.neighbors[k];
    if (!counts(j)) continue;
    ++members;
    const double w = p.partial_volume[k] * p.volume[j];
    const double xi_x = p.x[j] - p.x[i], xi_y = p.y[j] - p.y[i];
    const double du[2] = {ux[j] - ux[i], uy[j] - uy[i]};
    kxx += w * xi_x * xi_x;
    kxy += w * xi_x * xi_y;
    kyy += w * xi_y * xi_y;
    for (int a = 0; a < 2; ++a) {
      b[a][0] += w * du[a] * xi_x;
      b[a][1] += w * du[a] * xi_y;
    }
  }
  const double det = kxx * kyy - kxy * kxy;
  // K scales like (family area) delta^2 squared: compare det with that, not with 0.
  if (!(det > 1e-10 * (kxx + kyy) * (kxx + kyy))) return false;
  // K^-1 of the symmetric 2x2 matrix.
  const double inv[2][2] = {{kyy / det, -kxy / det}, {-kxy / det, kxx / det}};
  for (int a = 0; a < 2; ++a)
    for (int c = 0; c < 2; ++c) g.du_dx[a][c] = b[a][0] * inv[0][c] + b[a][1] * inv[1][c];
  return true;
}

}  // namespace

DisplacementGradient family_displacement_gradient(const ParticleSet& p, const std::vector<double>& ux,
                                                  const std::vector<double>& uy, std::size_t i) {
  DisplacementGradient g;
  std::size_t members = 0;
  if (!gradient_over(p, ux, uy, i, [](std::uint32_t) { return true; }, g, members)) {
    std::ostringstream m;
    m << "displacement gradient: the family of particle " << i << " at (" << p.x[i] << ", " << p.y[i]
      << ") m spans no area (" << members << " neighbours)";
    throw Error(m.str());
  }
  return g;
}

std::optional<DisplacementGradient> family_displacement_gradient_without(const ParticleSet& p,
                                                                         const std::vector<double>& ux,
                                                                         const std::vector<double>& uy,
                                                                         std::size_t i,
                                                                         const std::uint32_t* left_out_begin,
                                                                         const std::uint32_t* left_out_end) {
  DisplacementGradient g;
  std::size_t members = 0;
  const auto counts = [&](std::uint32_t j) { return !std::binary_search(left_out_begin, left_out_end, j); };
  if (!gradient_over(p, ux, uy, i, counts, g, members)) return std::nullopt;
  return g;
}

std::vector<DisplacementGradient> family_displacement_gradients(const ParticleSet& p, const std::vector<double>& ux,
                                                                const std::vector<double>& uy) {
  std::vector<DisplacementGradient> out(p.size());
  for (std::size_t i = 0; i < p.size(); ++i) out[i] = family_displacement_gradient(p, ux, uy, i);
  return out;
}

}  // namespace pd
