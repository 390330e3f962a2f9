#include "precrack.hpp"

#include <algorithm>
#include <cmath>

namespace pd::solver {
namespace {
// +1 if p is on the left of the directed line a->b or on it (within `tolerance`), else -1.
int side_of_line(Vec2 p, Vec2 a, Vec2 b, double tolerance) {
  const Vec2 d = b - a;
  const double signed_distance = cross(d, p - a) / std::sqrt(dot(d, d));
  return signed_distance >= -tolerance ? +1 : -1;
}
}  // namespace

bool bond_crosses_crack(Vec2 pi, Vec2 pj, const PrecrackSpec& crack) {
  const Vec2 bond = pj - pi;
  const double bond_length = std::sqrt(dot(bond, bond));
  const double tolerance = 1e-9 * bond_length;
  // The two particles on different sides of the crack line ...
  if (side_of_line(pi, crack.from, crack.to, tolerance) == side_of_line(pj, crack.from, crack.to, tolerance))
    return false;
  // ... and the crack segment reaching the bond's line (end points included).
  const double a = cross(bond, crack.from - pi) / bond_length;
  const double b = cross(bond, crack.to - pi) / bond_length;
  const double near_a = std::fabs(a) <= tolerance ? 0.0 : a;
  const double near_b = std::fabs(b) <= tolerance ? 0.0 : b;
  return near_a * near_b <= 0;
}

std::size_t apply_precracks(const ParticleSet& p, const BondTable& bonds, const std::vector<PrecrackSpec>& cracks,
                            std::vector<std::uint8_t>& intact) {
  std::size_t cut = 0;
  if (cracks.empty()) return 0;
  for (const auto& crack : cracks) {
    const double reach = bonds.rest_length.empty()
                             ? 0
                             : *std::max_element(bonds.rest_length.begin(), bonds.rest_length.end());
    const double xmin = std::min(crack.from.x, crack.to.x) - reach, xmax = std::max(crack.from.x, crack.to.x) + reach;
    const double ymin = std::min(crack.from.y, crack.to.y) - reach, ymax = std::max(crack.from.y, crack.to.y) + reach;
    for (std::size_t i = 0; i < p.size(); ++i) {
      if (p.x[i] < xmin || p.x[i] > xmax || p.y[i] < ymin || p.y[i] > ymax) continue;  // too far to be cut
      for (auto b = bonds.offsets[i]; b < bonds.offsets[i + 1]; ++b) {
        if (!intact[b]) continue;
        const auto j = bonds.neighbor[b];
        if (bond_crosses_crack({p.x[i], p.y[i]}, {p.x[j], p.y[j]}, crack)) {
          intact[b] = 0;
          ++cut;
        }
      }
    }
  }
  return cut;
}

}  // namespace pd::solver
