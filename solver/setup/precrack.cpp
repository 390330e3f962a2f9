#include "precrack.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <iomanip>
#include <limits>
#include <sstream>

#include "error.hpp"
#include "plate_pieces.hpp"

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

namespace {
// The squared length of the longest listed bond of the particles with
// only[i] != 0 (all when null) [m^2]: one square root for all (a hypot per
// bond was most of the cost of the pre-cracks' set-up).
double longest_listed_squared(const ParticleSet& p, const std::vector<std::uint64_t>& offsets,
                              const std::vector<std::uint32_t>& neighbors, const std::vector<std::uint8_t>* only) {
  double longest_squared = 0;
  for (std::uint32_t i = 0; i < p.size(); ++i) {
    if (only && !(*only)[i]) continue;
    for (auto b = offsets[i]; b < offsets[i + 1]; ++b) {
      const auto j = neighbors[b];
      const double dx = p.x[j] - p.x[i], dy = p.y[j] - p.y[i];
      longest_squared = std::max(longest_squared, dx * dx + dy * dy);
    }
  }
  return longest_squared;
}

// Calls cut(k, i, place, j) for every bond i -> j at `place` in i's family
// crossing crack k, of the particles with only[i] != 0 (all when null)
// within `reach` (a bound of the bonds' lengths) of the crack.
// `family(i, f)` calls f(place, j) for every bond of i.
template <class Family, class Cut>
void for_each_cut_bond(const ParticleSet& p, const std::vector<PrecrackSpec>& cracks, double reach_bound,
                       const std::vector<std::uint8_t>* only, Family family, Cut cut) {
  // Widened by 1e-9 against the rounding of either way of taking the length.
  const double reach = reach_bound * (1 + 1e-9);
  const std::vector<CrackEnds> ends = included_ends(cracks);
  for (std::size_t k = 0; k < cracks.size(); ++k) {
    const PrecrackSpec& crack = cracks[k];
    const double xmin = std::min(crack.from.x, crack.to.x) - reach, xmax = std::max(crack.from.x, crack.to.x) + reach;
    const double ymin = std::min(crack.from.y, crack.to.y) - reach, ymax = std::max(crack.from.y, crack.to.y) + reach;
    for (std::uint32_t i = 0; i < p.size(); ++i) {
      if (only && !(*only)[i]) continue;
      if (p.x[i] < xmin || p.x[i] > xmax || p.y[i] < ymin || p.y[i] > ymax) continue;  // too far to be cut
      family(i, [&](std::uint32_t place, std::uint32_t j) {
        if (bond_crosses_crack({p.x[i], p.y[i]}, {p.x[j], p.y[j]}, crack, ends[k]))
          cut(static_cast<std::uint32_t>(k), i, place, j);
      });
    }
  }
}

// Lists the particles marked at_an_end (of a cut bond) and counts each crack's cuts.
std::vector<std::uint64_t> finish_cuts(PrecrackCuts& cuts, std::size_t crack_count,
                                       const std::vector<std::uint8_t>& at_an_end) {
  std::vector<std::uint64_t> per_crack(crack_count, 0);
  for (const CutBond& c : cuts.bonds) ++per_crack[c.crack];
  for (std::uint32_t i = 0; i < at_an_end.size(); ++i)
    if (at_an_end[i]) cuts.particles.push_back(i);
  return per_crack;
}
}  // namespace

double longest_bond(const ParticleSet& p, const Families& f) {
  return std::max(f.longest_stencil_bond(), std::sqrt(longest_listed_squared(p, f.offsets, f.neighbors, nullptr)));
}

void require_precrack_cuts(const std::vector<std::uint64_t>& bonds_cut, const ParticleSet& p,
                           const std::vector<PrecrackSpec>& cracks, const std::string& scene_path) {
  // An end farther beyond the plate than the plate is wide is a unit slip
  // (mm read as m: [0.75, 0.0125] for 0.75 mm), not a crack meant to cut
  // through: such a crack cuts the plate from edge to edge, and the run would
  // fail, if at all, at some later check that does not name the crack.
  const double plate_size = std::max(p.xmax - p.xmin, p.ymax - p.ymin);
  for (std::size_t k = 0; k < cracks.size(); ++k)
    for (const bool is_to : {false, true}) {
      const Vec2 end = is_to ? cracks[k].to : cracks[k].from;
      const double beyond = std::max({p.xmin - end.x, end.x - p.xmax, p.ymin - end.y, end.y - p.ymax});
      if (!(beyond > plate_size)) continue;
      const std::string& where = is_to ? cracks[k].where_to : cracks[k].where_from;
      std::ostringstream m;
      m << (where.empty() ? scene_path : where) << ": key 'precracks[" << k << "]." << (is_to ? "to" : "from")
        << "' = [" << end.x << ", " << end.y << "]: this end lies " << beyond
        << " m beyond the plate (x in [" << p.xmin << ", " << p.xmax << "], y in [" << p.ymin << ", " << p.ymax
        << "] m), farther than the plate's size: coordinates are in metres (is it in mm?); a crack meant "
           "to cut through the plate ends at its edge";
      throw Error(m.str());
    }
  // A crack that cuts nothing is a mistake the run would not show.
  for (std::size_t k = 0; k < cracks.size(); ++k)
    if (bonds_cut[k] == 0) {
      const PrecrackSpec& c = cracks[k];
      std::ostringstream m;
      // Ends to 12 digits: two ends that differ in the 9th (a crack of 1e-11
      // m) printed alike at the stream's 6. The other end's source too where
      // --set gave that end alone.
      m.precision(12);
      const auto by_set = [](const std::string& where) { return where.find("--set") != std::string::npos; };
      m << (c.where_from.empty() ? scene_path : c.where_from)
        << (by_set(c.where_to) && !by_set(c.where_from) ? " and " + c.where_to : std::string()) << ": precracks["
        << k << "] from [" << c.from.x << ", " << c.from.y << "] to [" << c.to.x << ", " << c.to.y
        << "] m cuts no bond: ";
      const auto inside = [&](Vec2 q) { return q.x > p.xmin && q.x < p.xmax && q.y > p.ymin && q.y < p.ymax; };
      const double length = std::hypot(c.to.x - c.from.x, c.to.y - c.from.y);
      const auto on_one_side = [&](double Vec2::*axis, double side) { return c.from.*axis == side && c.to.*axis == side; };
      if (length < 0.5 * p.spacing)
        // (Before 7 December 2026 such a crack on the plate's edge was said to lie outside the plate.)
        m << "it is " << std::setprecision(3) << length << std::setprecision(12)
          << " m long, shorter than half the spacing (" << p.spacing
          << " m): a crack must cross the line between two particles to cut their bond";
      else if (on_one_side(&Vec2::x, p.xmin) || on_one_side(&Vec2::x, p.xmax) || on_one_side(&Vec2::y, p.ymin) ||
               on_one_side(&Vec2::y, p.ymax))
        m << "it runs along an edge of the plate (x in [" << p.xmin << ", " << p.xmax << "], y in [" << p.ymin << ", "
          << p.ymax << "] m), where no bond crosses it; a crack into the plate has an end inside it";
      else if (inside(c.from) || inside(c.to))
        // Particles on the crack's line count as lying on its left (docs/scenes.md): a crack along the
        // outermost row of centres has no particle on its right.
        m << "it lies inside the plate's box (x in [" << p.xmin << ", " << p.xmax << "], y in [" << p.ymin << ", "
          << p.ymax << "] m) but no bond crosses it: inside a hole, or along the outermost row of particle centres "
             "(particles on the line count as lying on its left, from -> to); move it half a spacing, or check "
             "that its coordinates are in metres";
      else
        m << "it lies outside the plate (x in [" << p.xmin << ", " << p.xmax << "], y in [" << p.ymin << ", "
          << p.ymax << "] m) or inside a hole, or its coordinates are not in metres";
      throw Error(m.str());
    }
}

PrecrackCuts precrack_cuts(const ParticleSet& p, const Families& f, const std::vector<PrecrackSpec>& cracks,
                           const std::string& scene_path, std::vector<std::uint64_t>* bonds_cut_out) {
  PrecrackCuts cuts;
  cuts.particle_count = p.size();
  if (cracks.empty()) return cuts;
  cuts.reach = longest_bond(p, f);
  const auto family = [&](std::uint32_t i, auto&& bond) {
    const std::uint64_t first = f.on_stencil[i] ? 0 : f.offsets[i];
    f.for_each_bond(i, [&](const BondRef& b) {
      ++cuts.bonds_tested;
      bond(static_cast<std::uint32_t>(b.index - first), b.neighbor);
    });
  };
  std::vector<std::uint8_t> at_an_end(p.size(), 0);
  for_each_cut_bond(p, cracks, cuts.reach, nullptr, family,
                    [&](std::uint32_t k, std::uint32_t i, std::uint32_t place, std::uint32_t j) {
                      cuts.bonds.push_back({k, i, place});
                      at_an_end[i] = at_an_end[j] = 1;
                    });
  std::sort(cuts.bonds.begin(), cuts.bonds.end());
  std::vector<std::uint64_t> bonds_cut = finish_cuts(cuts, cracks.size(), at_an_end);
  if (bonds_cut_out)
    *bonds_cut_out = std::move(bonds_cut);
  else
    require_precrack_cuts(bonds_cut, p, cracks, scene_path);
  return cuts;
}

PrecrackCuts precrack_cuts_after_event(const ParticleSet& p, const std::vector<PrecrackSpec>& cracks,
                                       const std::string& scene_path, const PrecrackCuts& before,
                                       const std::vector<std::uint32_t>& same_family) {
  const std::size_t n = p.size();
  if (same_family.size() != n || p.family_offsets.size() != n + 1)
    throw Error("precrack_cuts_after_event: the families are given for another particle count");
  PrecrackCuts cuts;
  cuts.particle_count = n;
  if (cracks.empty()) return cuts;
  std::vector<std::uint8_t> built(n, 0);
  std::vector<std::uint32_t> now_of(before.particle_count, Families::none);
  for (std::uint32_t i = 0; i < n; ++i) {
    if (same_family[i] == Families::none)
      built[i] = 1;
    else
      now_of[same_family[i]] = i;
  }
  // Every bond is a copied family's (within the earlier set's bound) or a built one's.
  cuts.reach =
      std::max(before.reach, std::sqrt(longest_listed_squared(p, p.family_offsets, p.neighbors, &built)));
  // The copied families' cut bonds, in order (the particles that did not
  // split keep their order), then the built ones'.
  std::vector<std::uint8_t> at_an_end(n, 0);
  cuts.bonds.reserve(before.bonds.size());
  for (const CutBond& c : before.bonds) {
    const std::uint32_t i = now_of[c.owner];
    if (i == Families::none) continue;
    cuts.bonds.push_back({c.crack, i, c.place});
    at_an_end[i] = at_an_end[p.neighbors[p.family_offsets[i] + c.place]] = 1;
  }
  const auto copied = static_cast<std::ptrdiff_t>(cuts.bonds.size());
  const auto family = [&](std::uint32_t i, auto&& bond) {
    const std::uint64_t first = p.family_offsets[i];
    for (auto b = first; b < p.family_offsets[i + 1]; ++b) {
      ++cuts.bonds_tested;
      bond(static_cast<std::uint32_t>(b - first), p.neighbors[b]);
    }
  };
  for_each_cut_bond(p, cracks, cuts.reach, &built, family,
                    [&](std::uint32_t k, std::uint32_t i, std::uint32_t place, std::uint32_t j) {
                      cuts.bonds.push_back({k, i, place});
                      at_an_end[i] = at_an_end[j] = 1;
                    });
  std::sort(cuts.bonds.begin() + copied, cuts.bonds.end());
  std::inplace_merge(cuts.bonds.begin(), cuts.bonds.begin() + copied, cuts.bonds.end());
  require_precrack_cuts(finish_cuts(cuts, cracks.size(), at_an_end), p, cracks, scene_path);
  return cuts;
}

std::size_t apply_precrack_cuts(const Families& f, const PrecrackCuts& cuts, std::vector<std::uint8_t>& listed_intact) {
  std::size_t cut = 0;
  for (const CutBond& c : cuts.bonds) {
    if (f.on_stencil[c.owner])
      throw Error("pre-crack: particle " + std::to_string(c.owner) + " has a cut bond but a stencil family");
    const std::uint64_t b = f.offsets[c.owner] + c.place;
    if (listed_intact[b]) {
      listed_intact[b] = 0;
      ++cut;
    }
  }
  return cut;
}

namespace {

// Each particle's piece over every intact bond, once at set-up.
std::vector<std::uint32_t> piece_roots(const Families& f, const std::vector<std::uint8_t>& listed_intact) {
  return pd::piece_roots(f.particle_count, [&](std::uint32_t i, auto&& join) {
    f.for_each_bond(i, [&](const BondRef& b) {
      if (b.neighbor != Families::none && (b.on_stencil || listed_intact[b.index])) join(b.neighbor);
    });
  });
}

// Count and the three largest sizes of the pieces named by `piece` (one
// entry per particle, each below `names`).
PlatePieces pieces_of(const std::vector<std::uint32_t>& piece, std::size_t names) {
  std::vector<std::size_t> size(names, 0);
  for (const std::uint32_t p : piece) ++size[p];
  PlatePieces pieces;
  for (const std::size_t s : size)
    if (s > 0) ++pieces.count, pieces.largest.push_back(s);
  std::sort(pieces.largest.begin(), pieces.largest.end(), std::greater<>());
  if (pieces.largest.size() > 3) pieces.largest.resize(3);
  return pieces;
}

}  // namespace

PlatePieces plate_pieces(const Families& f, const std::vector<std::uint8_t>& listed_intact) {
  return pieces_of(piece_roots(f, listed_intact), f.particle_count);
}

PlatePieces plate_pieces_on_processes(const Families& f, const std::vector<std::uint8_t>& listed_intact,
                                      const std::vector<std::uint32_t>& global_id, std::size_t owned_count,
                                      const PieceExchange& exchange) {
  // Each particle's label becomes the smallest particle-file index of its
  // piece: the smallest label of its local piece, then the ghosts' labels
  // from their owners, until no process changes one (a piece that crosses k
  // slab borders takes about k rounds). Labels are exact in double (< 2^53).
  const std::vector<std::uint32_t> local_root = piece_roots(f, listed_intact);
  const std::size_t n = local_root.size();
  std::vector<double> label(global_id.begin(), global_id.begin() + n);
  std::vector<double> smallest(n);
  for (;;) {
    std::fill(smallest.begin(), smallest.end(), std::numeric_limits<double>::infinity());
    for (std::size_t i = 0; i < n; ++i) smallest[local_root[i]] = std::min(smallest[local_root[i]], label[i]);
    bool changed = false;
    for (std::size_t i = 0; i < n; ++i)
      if (smallest[local_root[i]] != label[i]) label[i] = smallest[local_root[i]], changed = true;
    exchange.update_ghost_values(label);
    if (!exchange.any(changed)) break;
  }
  std::uint64_t roots = 0;  // the particle that names its piece is owned by one process
  for (std::size_t i = 0; i < owned_count; ++i) roots += label[i] == global_id[i];
  std::vector<double> whole;
  exchange.gather_owned(label.data(), owned_count, whole);
  PlatePieces pieces;
  if (!whole.empty()) pieces = pieces_of(std::vector<std::uint32_t>(whole.begin(), whole.end()), whole.size());
  pieces.count = exchange.sum(roots);
  return pieces;
}

}  // namespace pd::solver
