#include "precrack.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "error.hpp"

namespace pd::solver {
namespace {
// Particles within this fraction of the bond length of the crack's line lie on
// it; crossings within it of an end point are at that end point (precrack.hpp).
constexpr double touch_tolerance = 1e-6;
}  // namespace

bool bond_crosses_crack(Vec2 pi, Vec2 pj, const PrecrackSpec& crack, CrackEnds ends) {
  // The same arithmetic for both directions of the pair: order its end points.
  const bool in_order = pi.x < pj.x || (pi.x == pj.x && pi.y <= pj.y);
  const Vec2 p = in_order ? pi : pj, q = in_order ? pj : pi;
  const Vec2 bond = q - p;
  const double tolerance = touch_tolerance * std::sqrt(dot(bond, bond));
  const Vec2 along = crack.to - crack.from;
  const double crack_length = std::sqrt(dot(along, along));
  const Vec2 direction = (1.0 / crack_length) * along;
  // Signed distances from the crack's line, positive on its left; on the line counts as left.
  const double hp = cross(direction, p - crack.from), hq = cross(direction, q - crack.from);
  if ((hp >= -tolerance) == (hq >= -tolerance)) return false;
  // Where the bond meets the line, as a distance from `from` along the crack:
  // at a particle lying on the line, else where the signed distance is zero.
  double meets;
  if (std::fabs(hp) <= tolerance) meets = dot(direction, p - crack.from);
  else if (std::fabs(hq) <= tolerance) meets = dot(direction, q - crack.from);
  else meets = dot(direction, p - crack.from) + hp / (hp - hq) * dot(direction, bond);
  // The open crack (from, to), with the ends it includes.
  const bool after_from = ends.from ? meets >= -tolerance : meets > tolerance;
  const bool before_to = ends.to ? meets <= crack_length + tolerance : meets < crack_length - tolerance;
  return after_from && before_to;
}

std::vector<CrackEnds> included_ends(const std::vector<PrecrackSpec>& cracks) {
  const auto same_point = [](Vec2 a, Vec2 b, double scale) {
    const Vec2 d = a - b;
    return std::sqrt(dot(d, d)) <= 1e-9 * scale;
  };
  const auto length = [](const PrecrackSpec& c) {
    const Vec2 d = c.to - c.from;
    return std::sqrt(dot(d, d));
  };
  // An end is included when another crack ends there and no earlier one does.
  const auto included = [&](std::size_t k, Vec2 end) {
    bool shared = false;
    for (std::size_t j = 0; j < cracks.size(); ++j) {
      if (j == k) continue;
      const double scale = std::max(length(cracks[k]), length(cracks[j]));
      if (!same_point(end, cracks[j].from, scale) && !same_point(end, cracks[j].to, scale)) continue;
      if (j < k) return false;
      shared = true;
    }
    return shared;
  };
  std::vector<CrackEnds> ends(cracks.size());
  for (std::size_t k = 0; k < cracks.size(); ++k) ends[k] = {included(k, cracks[k].from), included(k, cracks[k].to)};
  return ends;
}

double longest_listed_bond(const ParticleSet& p, const Families& f, const std::vector<std::uint8_t>* only) {
  // The listed bonds' squared lengths and one square root (a hypot per bond
  // was most of the cost of the pre-cracks' set-up).
  double longest_squared = 0;
  for (std::uint32_t i = 0; i < p.size(); ++i) {
    if (only && !(*only)[i]) continue;
    for (auto b = f.offsets[i]; b < f.offsets[i + 1]; ++b) {
      const auto j = f.neighbors[b];
      const double dx = p.x[j] - p.x[i], dy = p.y[j] - p.y[i];
      longest_squared = std::max(longest_squared, dx * dx + dy * dy);
    }
  }
  return std::sqrt(longest_squared);
}

double longest_bond(const ParticleSet& p, const Families& f) {
  return std::max(f.longest_stencil_bond(), longest_listed_bond(p, f, nullptr));
}

namespace {
// Calls cut(k, i, bond) for every bond crossing crack k (only particles within
// a bond length of a crack are looked at). `longest`: a bound of the bonds'
// lengths (longest_bond), 0 to find it here.
template <class Cut>
void for_each_cut_bond(const ParticleSet& p, const Families& f, const std::vector<PrecrackSpec>& cracks,
                       double longest, Cut cut) {
  if (cracks.empty()) return;
  // Widened by 1e-9 against the rounding of either way of taking the length.
  const double reach = (longest > 0 ? longest : longest_bond(p, f)) * (1 + 1e-9);
  const std::vector<CrackEnds> ends = included_ends(cracks);
  for (std::size_t k = 0; k < cracks.size(); ++k) {
    const PrecrackSpec& crack = cracks[k];
    const double xmin = std::min(crack.from.x, crack.to.x) - reach, xmax = std::max(crack.from.x, crack.to.x) + reach;
    const double ymin = std::min(crack.from.y, crack.to.y) - reach, ymax = std::max(crack.from.y, crack.to.y) + reach;
    for (std::uint32_t i = 0; i < p.size(); ++i) {
      if (p.x[i] < xmin || p.x[i] > xmax || p.y[i] < ymin || p.y[i] > ymax) continue;  // too far to be cut
      f.for_each_bond(i, [&](const BondRef& b) {
        const auto j = b.neighbor;
        if (bond_crosses_crack({p.x[i], p.y[i]}, {p.x[j], p.y[j]}, crack, ends[k])) cut(k, i, b);
      });
    }
  }
}
}  // namespace

void require_precrack_cuts(const std::vector<std::uint64_t>& bonds_cut, const ParticleSet& p,
                           const std::vector<PrecrackSpec>& cracks, const std::string& scene_path) {
  // A crack that cuts nothing is a mistake the run would not show.
  for (std::size_t k = 0; k < cracks.size(); ++k)
    if (bonds_cut[k] == 0) {
      std::ostringstream m;
      m << scene_path << ": precracks[" << k << "] from [" << cracks[k].from.x << ", " << cracks[k].from.y
        << "] to [" << cracks[k].to.x << ", " << cracks[k].to.y
        << "] m cuts no bond: it lies outside the plate (x in [" << p.xmin << ", " << p.xmax << "], y in ["
        << p.ymin << ", " << p.ymax << "] m) or inside a hole, or its coordinates are not in metres";
      throw Error(m.str());
    }
}

std::vector<std::uint32_t> particles_cut_by(const ParticleSet& p, const Families& f,
                                            const std::vector<PrecrackSpec>& cracks, const std::string& scene_path,
                                            std::vector<std::uint64_t>* bonds_cut_out, double longest) {
  std::vector<std::uint32_t> touched;
  std::vector<std::uint64_t> bonds_cut(cracks.size(), 0);
  for_each_cut_bond(p, f, cracks, longest, [&](std::size_t k, std::uint32_t i, const BondRef& b) {
    ++bonds_cut[k];
    touched.push_back(i);
    touched.push_back(b.neighbor);
  });
  if (bonds_cut_out)
    *bonds_cut_out = std::move(bonds_cut);
  else
    require_precrack_cuts(bonds_cut, p, cracks, scene_path);
  std::sort(touched.begin(), touched.end());
  touched.erase(std::unique(touched.begin(), touched.end()), touched.end());
  return touched;
}

std::size_t apply_precracks(const ParticleSet& p, const Families& f, const std::vector<PrecrackSpec>& cracks,
                            std::vector<std::uint8_t>& listed_intact, double longest) {
  std::size_t cut = 0;
  for_each_cut_bond(p, f, cracks, longest, [&](std::size_t, std::uint32_t i, const BondRef& b) {
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
