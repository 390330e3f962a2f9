#include "precrack.hpp"

#include <algorithm>
#include <cmath>

#include "error.hpp"

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

namespace {
// Calls cut(i, bond) for every bond crossing a crack (only particles within a
// bond length of a crack are looked at).
template <class Cut>
void for_each_cut_bond(const ParticleSet& p, const Families& f, const std::vector<PrecrackSpec>& cracks, Cut cut) {
  if (cracks.empty()) return;
  double reach = f.longest_stencil_bond();
  for (std::uint32_t i = 0; i < p.size(); ++i)
    for (auto b = f.offsets[i]; b < f.offsets[i + 1]; ++b) {
      const auto j = f.neighbors[b];
      reach = std::max(reach, std::hypot(p.x[j] - p.x[i], p.y[j] - p.y[i]));
    }
  for (const auto& crack : cracks) {
    const double xmin = std::min(crack.from.x, crack.to.x) - reach, xmax = std::max(crack.from.x, crack.to.x) + reach;
    const double ymin = std::min(crack.from.y, crack.to.y) - reach, ymax = std::max(crack.from.y, crack.to.y) + reach;
    for (std::uint32_t i = 0; i < p.size(); ++i) {
      if (p.x[i] < xmin || p.x[i] > xmax || p.y[i] < ymin || p.y[i] > ymax) continue;  // too far to be cut
      f.for_each_bond(i, [&](const BondRef& b) {
        const auto j = b.neighbor;
        if (bond_crosses_crack({p.x[i], p.y[i]}, {p.x[j], p.y[j]}, crack)) cut(i, b);
      });
    }
  }
}
}  // namespace

std::vector<std::uint32_t> particles_cut_by(const ParticleSet& p, const Families& f,
                                            const std::vector<PrecrackSpec>& cracks) {
  std::vector<std::uint32_t> touched;
  for_each_cut_bond(p, f, cracks, [&](std::uint32_t i, const BondRef& b) {
    touched.push_back(i);
    touched.push_back(b.neighbor);
  });
  std::sort(touched.begin(), touched.end());
  touched.erase(std::unique(touched.begin(), touched.end()), touched.end());
  return touched;
}

std::size_t apply_precracks(const ParticleSet& p, const Families& f, const std::vector<PrecrackSpec>& cracks,
                            std::vector<std::uint8_t>& listed_intact) {
  std::size_t cut = 0;
  for_each_cut_bond(p, f, cracks, [&](std::uint32_t i, const BondRef& b) {
    if (b.on_stencil)
      throw Error("pre-crack: particle " + std::to_string(i) + " has a cut bond but a stencil family");
    if (listed_intact[b.index]) {
      listed_intact[b.index] = 0;
      ++cut;
    }
  });
  return cut;
}

}  // namespace pd::solver
