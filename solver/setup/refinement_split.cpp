#include "refinement_split.hpp"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <sstream>

#include "displacement_gradient.hpp"
#include "error.hpp"
#include "families.hpp"
#include "particle_pairs.hpp"

namespace pd::solver {
namespace {

// Whether the origins a, b of two particles of the split set were bonded in
// either direction before it (families are sorted by index).
bool bonded_before(const ParticleSet& before, std::uint32_t a, std::uint32_t b) {
  const auto row_has = [&](std::uint32_t i, std::uint32_t j) {
    const auto first = before.neighbors.begin() + static_cast<std::ptrdiff_t>(before.family_offsets[i]);
    const auto last = before.neighbors.begin() + static_cast<std::ptrdiff_t>(before.family_offsets[i + 1]);
    return std::binary_search(first, last, j);
  };
  return row_has(a, b) || row_has(b, a);
}

// Per particle of the set before a split whose row a split builds: itself
// and the particles it was bonded with in either direction, ascending and
// without repeats. These origins are the only ones the bond rule of
// theory.md Sec. 8.3 admits in its row.
struct BondPartners {
  std::vector<std::uint64_t> first, end;  // per particle of the set before the split: its range in `partner`
  std::vector<std::uint32_t> partner;
};

BondPartners bond_partners(const ParticleSet& before, const std::vector<std::uint8_t>& wanted) {
  const std::size_t n = before.size();
  // The bonds i -> a to a wanted a: one pass over all bonds (raw pointers:
  // the appends cannot make the compiler read the families' ends again).
  std::vector<std::pair<std::uint32_t, std::uint32_t>> reverse;
  const std::uint64_t* offsets = before.family_offsets.data();
  const std::uint32_t* neighbors = before.neighbors.data();
  const std::uint8_t* is_wanted = wanted.data();
  for (std::uint32_t i = 0; i < n; ++i) {
    const std::uint64_t end = offsets[i + 1];
    for (auto k = offsets[i]; k < end; ++k)
      if (is_wanted[neighbors[k]]) reverse.emplace_back(neighbors[k], i);
  }
  BondPartners b;
  b.first.assign(n + 1, 0);
  for (std::size_t a = 0; a < n; ++a)
    if (wanted[a]) b.first[a + 1] = 1 + (before.family_offsets[a + 1] - before.family_offsets[a]);
  for (const auto& [a, i] : reverse) ++b.first[a + 1];
  for (std::size_t a = 0; a < n; ++a) b.first[a + 1] += b.first[a];
  b.partner.resize(b.first.back());
  std::vector<std::uint64_t> next(b.first.begin(), b.first.end() - 1);
  for (std::uint32_t a = 0; a < n; ++a) {
    if (!wanted[a]) continue;
    b.partner[next[a]++] = a;
    for (auto k = before.family_offsets[a]; k < before.family_offsets[a + 1]; ++k)
      b.partner[next[a]++] = before.neighbors[k];
  }
  for (const auto& [a, i] : reverse) b.partner[next[a]++] = i;
  // Each row is a, then a's own bonds, then the bonds to a, the last two
  // ascending (rows are sorted; `reverse` was collected in bonding order):
  // merged into one ascending run without repeats, in place.
  b.end.assign(n, 0);
  std::vector<std::uint32_t> merged;
  for (std::uint32_t a = 0; a < n; ++a) {
    if (!wanted[a]) continue;
    std::uint32_t* row = b.partner.data() + b.first[a];
    std::uint32_t* own_end = row + 1 + (before.family_offsets[a + 1] - before.family_offsets[a]);
    std::uint32_t* row_end = b.partner.data() + next[a];
    merged.clear();
    std::set_union(row + 1, own_end, own_end, row_end, std::back_inserter(merged));
    merged.insert(std::lower_bound(merged.begin(), merged.end(), a), a);
    // Repeats inside one run (none in a sorted row) and a among its own bonds.
    merged.erase(std::unique(merged.begin(), merged.end()), merged.end());
    std::copy(merged.begin(), merged.end(), row);
    b.end[a] = b.first[a] + merged.size();
  }
  return b;
}

// Families of the split set (theory.md Sec. 8.3): each particle's own
// horizon, exact partial volumes from the FamilyBuilder; a bond is kept when
// its ends share an origin (siblings) or their origins were bonded before.
//
// Only the rows marked in `rebuild` go through the FamilyBuilder; the others
// are their origin's row with the indices of the split set, which is the
// same family (theory.md Sec. 8.3): their origin was bonded to no parent, so
// the rule above admits none of the children, and their other candidates
// did not change. With every row marked this is the whole rebuild.
//
// `local`: a built row's candidates are the particles whose origins the rule
// admits (BondPartners), not those of a spatial search, which the split
// then does without. The FamilyBuilder gives the same family among them
// (FamilyBuilder::family_among): every cell it would search that the rule
// keeps is among them. A built row of a particle that did not split needs
// the children only (its other bonds are its own). The hhb quadrature and
// the whole rebuild search. `areas` (optional): partial areas kept across
// the run's splits (the local rebuild looks them up and adds its new ones).
void rebuild_families(ParticleSet& p, const ParticleSet& before, const SplitResult& r,
                      const std::vector<std::uint32_t>& new_index, const std::vector<std::uint8_t>& splits,
                      FamilyRebuild mode, CellDiskMemo* areas) {
  const std::vector<std::uint32_t>& origin = r.origin;
  const std::vector<std::uint8_t>& rebuild = r.rebuilt;
  const bool searched = mode == FamilyRebuild::whole || p.quadrature == Quadrature::hhb;
  BondPartners partners;
  if (!searched) {
    std::vector<std::uint8_t> wanted(before.size(), 0);
    for (std::size_t i = 0; i < p.size(); ++i)
      if (rebuild[i]) wanted[origin[i]] = 1;
    partners = bond_partners(before, wanted);
  }
  const FamilyBuilder builder(p, p.quadrature, nullptr, searched);
  const std::int64_t n = static_cast<std::int64_t>(p.size());
  // Only the built rows are kept apart; a copied row's length is its
  // origin's, and it is written straight into the final lists below.
  std::vector<std::vector<std::uint32_t>> built_neighbors(p.size());
  std::vector<std::vector<double>> built_factors(p.size());
  p.family_offsets.assign(p.size() + 1, 0);
  CellDiskMemo::Found new_areas;  // gathered per thread; the memo is only read in the loop
#pragma omp parallel
  {
    std::vector<std::uint32_t> found, candidates, child_candidates;
    std::vector<double> found_factors;
    CellDiskMemo::Found found_areas;
#pragma omp for schedule(dynamic, 256) nowait
    for (std::int64_t i = 0; i < n; ++i) {
      const auto self = static_cast<std::uint32_t>(i);
      const auto a = origin[self];
      if (!rebuild[i]) {
        p.family_offsets[i + 1] = before.family_offsets[a + 1] - before.family_offsets[a];
        continue;
      }
      auto& row_neighbors = built_neighbors[i];
      auto& row_factors = built_factors[i];
      if (searched) {
        builder.family({p.x[i], p.y[i]}, p.horizon[i], self, found, found_factors, candidates);
        row_neighbors.reserve(found.size());
        row_factors.reserve(found.size());
        for (std::size_t k = 0; k < found.size(); ++k) {
          const auto b = origin[found[k]];
          if (a != b && !bonded_before(before, a, b)) continue;
          row_neighbors.push_back(found[k]);
          row_factors.push_back(found_factors[k]);
        }
      } else {
        // A particle that did not split keeps its bonds to the others that
        // did not (the same cells, positions and horizon: the factors the
        // FamilyBuilder gave them, theory.md Sec. 8.3); only the children
        // are candidates. Their indices follow every kept particle's, so
        // the row stays sorted.
        const bool kept = !r.is_child[i];
        if (kept) {
          for (auto k = before.family_offsets[a]; k < before.family_offsets[a + 1]; ++k) {
            if (splits[before.neighbors[k]]) continue;
            row_neighbors.push_back(new_index[before.neighbors[k]]);
            row_factors.push_back(before.partial_volume[k]);
          }
        }
        // Ascending without repeats, as the partners are: the particles that
        // did not split keep their order, and the children follow them all,
        // in parent order (split_particles).
        candidates.clear();
        child_candidates.clear();
        for (auto k = partners.first[a]; k < partners.end[a]; ++k) {
          const auto b = partners.partner[k];
          if (!splits[b]) {
            if (!kept) candidates.push_back(new_index[b]);
            continue;
          }
          for (std::uint32_t c = 0; c < 4; ++c) child_candidates.push_back(new_index[b] + c);
        }
        candidates.insert(candidates.end(), child_candidates.begin(), child_candidates.end());
        builder.family_among({p.x[i], p.y[i]}, p.horizon[i], self, candidates, found, found_factors, areas,
                             &found_areas);
        row_neighbors.insert(row_neighbors.end(), found.begin(), found.end());
        row_factors.insert(row_factors.end(), found_factors.begin(), found_factors.end());
      }
      p.family_offsets[i + 1] = row_neighbors.size();
    }
#pragma omp critical(rebuild_families_areas)
    new_areas.insert(new_areas.end(), found_areas.begin(), found_areas.end());
  }
  if (areas) areas->add(new_areas);
  for (std::size_t i = 0; i < p.size(); ++i) p.family_offsets[i + 1] += p.family_offsets[i];
  p.neighbors.clear();
  p.partial_volume.clear();
  p.neighbors.reserve(p.family_offsets.back());
  p.partial_volume.reserve(p.family_offsets.back());
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (rebuild[i]) {
      p.neighbors.insert(p.neighbors.end(), built_neighbors[i].begin(), built_neighbors[i].end());
      p.partial_volume.insert(p.partial_volume.end(), built_factors[i].begin(), built_factors[i].end());
      continue;
    }
    const auto o = origin[i];
    const auto from = static_cast<std::ptrdiff_t>(before.family_offsets[o]);
    const auto to = static_cast<std::ptrdiff_t>(before.family_offsets[o + 1]);
    const std::uint32_t* old_neighbors = before.neighbors.data();
    const std::uint32_t* renumbered = new_index.data();
    std::transform(old_neighbors + from, old_neighbors + to, std::back_inserter(p.neighbors),
                   [renumbered](std::uint32_t j) { return renumbered[j]; });
    p.partial_volume.insert(p.partial_volume.end(), before.partial_volume.begin() + from,
                            before.partial_volume.begin() + to);
  }
}

// The rows of the split set that the FamilyBuilder must build: every row with
// `whole`, else the children's and those of the particles bonded to a parent
// in either direction before the split.
std::vector<std::uint8_t> rows_to_rebuild(const ParticleSet& before, const std::vector<std::uint32_t>& parents,
                                          const std::vector<std::uint8_t>& splits, const SplitResult& r,
                                          FamilyRebuild mode) {
  std::vector<std::uint8_t> rebuild(r.origin.size(), 1);
  if (mode == FamilyRebuild::whole) return rebuild;
  std::vector<std::uint8_t> bonded_to_parent(before.size(), 0);
  for (const auto parent : parents)
    for (auto k = before.family_offsets[parent]; k < before.family_offsets[parent + 1]; ++k)
      bonded_to_parent[before.neighbors[k]] = 1;
  // (Locals: a store to a byte array could alias every other array.)
  const std::uint64_t* offsets = before.family_offsets.data();
  const std::uint32_t* neighbors = before.neighbors.data();
  const std::uint8_t* split = splits.data();
  for (std::uint32_t i = 0; i < before.size(); ++i) {
    if (bonded_to_parent[i]) continue;
    std::uint8_t any = 0;
    for (auto k = offsets[i], end = offsets[i + 1]; k < end; ++k) any |= split[neighbors[k]];
    bonded_to_parent[i] = any;
  }
  for (std::size_t i = 0; i < rebuild.size(); ++i) rebuild[i] = r.is_child[i] || bonded_to_parent[r.origin[i]];
  return rebuild;
}

// A piece of a free cell (theory.md Sec. 8.2), counter-clockwise.
struct CellPiece {
  std::vector<double> vx, vy;
  double tolerance = 0;  // [m]: a vertex this close to the previous one is the same (a midpoint on a vertex)
  void add(Vec2 v) {
    if (!vx.empty() && std::hypot(v.x - vx.back(), v.y - vy.back()) <= tolerance) return;
    if (vx.size() > 2 && std::hypot(v.x - vx.front(), v.y - vy.front()) <= tolerance) return;
    vx.push_back(v.x), vy.push_back(v.y);
  }
  double area() const { return polygon_signed_area(vx.data(), vy.data(), vx.size()); }
};

// A cell's corners: the vertices where its boundary turns by more than
// 20 degrees. A cell along a curved boundary has that edge as a polyline of
// many vertices that turn little (particle_file.hpp, docs/formats.md): it is
// a triangle or a quadrilateral with one curved edge.
std::vector<std::size_t> cell_corners(const double* vx, const double* vy, std::size_t n) {
  const double cos_limit = std::cos(20.0 * M_PI / 180.0);
  std::vector<std::size_t> corners;
  for (std::size_t k = 0; k < n; ++k) {
    const Vec2 before{vx[(k + n - 1) % n], vy[(k + n - 1) % n]}, at{vx[k], vy[k]}, after{vx[(k + 1) % n], vy[(k + 1) % n]};
    const Vec2 in = at - before, out = after - at;
    const double lengths = std::hypot(in.x, in.y) * std::hypot(out.x, out.y);
    // Turning left by more than the limit (a right turn is a concave corner: no rule for it).
    if (cross(in, out) > 0 && dot(in, out) < cos_limit * lengths) corners.push_back(k);
  }
  return corners;
}

// The four pieces of a free cell with 3 or 4 corners, by the midpoints (in
// length) of its edges between corners, each edge a polyline of the cell's
// vertices: a triangle gives its three corner pieces and the middle
// triangle of the midpoints, a quadrilateral the four pieces of each corner,
// its two edges' midpoints and the midpoints' average. Empty when the cell
// has another number of corners or a piece would not be a counter-clockwise
// polygon.
std::vector<CellPiece> free_cell_pieces(const double* vx, const double* vy, std::size_t n) {
  const auto corners = cell_corners(vx, vy, n);
  const std::size_t m = corners.size();
  if (m != 3 && m != 4) return {};
  const auto vertex = [&](std::size_t k) { return Vec2{vx[k % n], vy[k % n]}; };
  // Edge e runs from corner e to corner e + 1 through vertices first[e] .. last[e] (indices mod n).
  std::vector<std::size_t> first(m), last(m);
  std::vector<Vec2> middle(m);
  std::vector<std::size_t> middle_after(m);  // the vertex before which the midpoint lies
  for (std::size_t e = 0; e < m; ++e) {
    first[e] = corners[e];
    last[e] = corners[(e + 1) % m] + (corners[(e + 1) % m] <= corners[e] ? n : 0);
    double length = 0;
    for (auto k = first[e]; k < last[e]; ++k) length += std::hypot(vertex(k + 1).x - vertex(k).x, vertex(k + 1).y - vertex(k).y);
    double walked = 0;
    for (auto k = first[e]; k < last[e]; ++k) {
      const Vec2 a = vertex(k), b = vertex(k + 1);
      const double segment = std::hypot(b.x - a.x, b.y - a.y);
      if (walked + segment >= 0.5 * length || k + 1 == last[e]) {
        const double t = segment > 0 ? std::min(1.0, (0.5 * length - walked) / segment) : 0.5;
        middle[e] = a + t * (b - a);
        middle_after[e] = k + 1;
        break;
      }
      walked += segment;
    }
  }
  Vec2 centre{0, 0};
  for (const Vec2 c : middle) centre = centre + (1.0 / static_cast<double>(m)) * c;
  double perimeter = 0;
  for (std::size_t k = 0; k < n; ++k) perimeter += std::hypot(vertex(k + 1).x - vertex(k).x, vertex(k + 1).y - vertex(k).y);
  std::vector<CellPiece> pieces(4);
  for (auto& piece : pieces) piece.tolerance = 1e-9 * perimeter;
  for (std::size_t c = 0; c < m; ++c) {
    const std::size_t in = (c + m - 1) % m, out = c;  // the edges into and out of corner c
    CellPiece& piece = pieces[c];
    piece.add(middle[in]);
    for (auto k = middle_after[in]; k <= last[in]; ++k) piece.add(vertex(k));
    for (auto k = first[out] + 1; k < middle_after[out]; ++k) piece.add(vertex(k));
    piece.add(middle[out]);
    if (m == 4) piece.add(centre);
  }
  if (m == 3)
    for (std::size_t e = 0; e < 3; ++e) pieces[3].add(middle[e]);
  for (const auto& piece : pieces)
    if (!(piece.area() > 0)) return {};
  return pieces;
}

}  // namespace

bool is_square_cell(const ParticleSet& p, std::size_t i) {
  const auto b = p.cell_offsets[i], e = p.cell_offsets[i + 1];
  if (e - b != 4) return false;
  double x0 = p.cell_vx[b], x1 = x0, y0 = p.cell_vy[b], y1 = y0;
  for (auto k = b; k < e; ++k) {
    x0 = std::min(x0, p.cell_vx[k]), x1 = std::max(x1, p.cell_vx[k]);
    y0 = std::min(y0, p.cell_vy[k]), y1 = std::max(y1, p.cell_vy[k]);
  }
  const double side = x1 - x0, tolerance = 1e-9 * side;
  if (!(side > 0) || std::fabs((y1 - y0) - side) > tolerance) return false;
  // Every vertex a corner of the box, and the centre in the middle.
  for (auto k = b; k < e; ++k) {
    const bool on_x = std::fabs(p.cell_vx[k] - x0) <= tolerance || std::fabs(p.cell_vx[k] - x1) <= tolerance;
    const bool on_y = std::fabs(p.cell_vy[k] - y0) <= tolerance || std::fabs(p.cell_vy[k] - y1) <= tolerance;
    if (!on_x || !on_y) return false;
  }
  return std::fabs(p.x[i] - 0.5 * (x0 + x1)) <= tolerance && std::fabs(p.y[i] - 0.5 * (y0 + y1)) <= tolerance;
}

bool can_split_cell(const ParticleSet& p, std::size_t i) {
  if (is_square_cell(p, i)) return true;
  const auto b = p.cell_offsets[i], n = p.cell_offsets[i + 1] - b;
  return !free_cell_pieces(&p.cell_vx[b], &p.cell_vy[b], n).empty();
}

double square_side(const ParticleSet& p, std::size_t i) {
  const auto b = p.cell_offsets[i], e = p.cell_offsets[i + 1];
  const auto [low, high] = std::minmax_element(p.cell_vx.begin() + static_cast<std::ptrdiff_t>(b),
                                               p.cell_vx.begin() + static_cast<std::ptrdiff_t>(e));
  return *high - *low;
}

std::array<Vec2, 4> child_offsets(double side) {
  const double q = 0.25 * side;
  return {Vec2{-q, -q}, Vec2{q, -q}, Vec2{-q, q}, Vec2{q, q}};
}

SplitResult split_particles(const ParticleSet& before, const std::vector<std::uint32_t>& parents, FamilyRebuild mode,
                            CellDiskMemo* partial_areas) {
  const std::size_t n = before.size();
  std::vector<std::uint8_t> splits(n, 0);
  for (std::size_t k = 0; k < parents.size(); ++k) {
    const auto i = parents[k];
    if (i >= n || (k > 0 && parents[k - 1] >= i) || !can_split_cell(before, i)) {
      std::ostringstream m;
      m << "refinement: particle " << i
        << " cannot split (not a square or a cell with three or four corners of this set, or listed twice)";
      throw Error(m.str());
    }
    splits[i] = 1;
  }
  SplitResult r;
  ParticleSet& p = r.particles;
  p = empty_like(before);
  p.provenance = before.provenance;
  std::vector<std::uint32_t> first_index(n);  // new index of a kept particle, of the first child of a parent
  {
    const std::size_t count = n + 3 * parents.size(), corners = before.cell_vx.size() + 12 * parents.size();
    for (auto* v : {&p.x, &p.y, &p.volume, &p.cell_size, &p.horizon}) v->reserve(count);
    p.region.reserve(count), p.material.reserve(count), p.cell_offsets.reserve(count + 1);
    p.cell_vx.reserve(corners), p.cell_vy.reserve(corners);
    r.origin.reserve(count), r.is_child.reserve(count);
  }
  const auto append = [&](std::uint32_t from, Vec2 centre, double area, double cell_size, double horizon,
                          const double* vx, const double* vy, std::size_t corners, bool child) {
    p.x.push_back(centre.x);
    p.y.push_back(centre.y);
    p.volume.push_back(area);
    p.cell_size.push_back(cell_size);
    p.horizon.push_back(horizon);
    p.region.push_back(before.region[from]);
    p.material.push_back(before.material[from]);
    for (std::size_t k = 0; k < corners; ++k) p.cell_vx.push_back(vx[k]), p.cell_vy.push_back(vy[k]);
    p.cell_offsets.push_back(p.cell_vx.size());
    r.origin.push_back(from);
    r.is_child.push_back(child ? 1 : 0);
  };
  for (std::uint32_t i = 0; i < n; ++i) {
    if (splits[i]) continue;
    first_index[i] = static_cast<std::uint32_t>(p.x.size());
    const auto b = before.cell_offsets[i], e = before.cell_offsets[i + 1];
    append(i, {before.x[i], before.y[i]}, before.volume[i], before.cell_size[i], before.horizon[i],
           &before.cell_vx[b], &before.cell_vy[b], e - b, false);
  }
  for (const auto i : parents) {
    first_index[i] = static_cast<std::uint32_t>(p.x.size());
    if (is_square_cell(before, i)) {
      const double side = square_side(before, i), q = 0.25 * side;
      for (const Vec2 offset : child_offsets(side)) {
        const Vec2 c{before.x[i] + offset.x, before.y[i] + offset.y};
        // The quarter, counter-clockwise.
        const double vx[4] = {c.x - q, c.x + q, c.x + q, c.x - q}, vy[4] = {c.y - q, c.y - q, c.y + q, c.y + q};
        append(i, c, 0.25 * before.volume[i], 0.5 * before.cell_size[i], 0.5 * before.horizon[i], vx, vy, 4, true);
      }
      continue;
    }
    // A free cell: four children on the cells cut by its edge midpoints, at
    // their centroids. The parent's area (corrected for a curved edge, which
    // the polygon only approximates) is shared in proportion to the pieces'
    // polygon areas, so that the children's areas sum to the parent's.
    const auto b = before.cell_offsets[i], corners = before.cell_offsets[i + 1] - b;
    const double parent_polygon = polygon_signed_area(&before.cell_vx[b], &before.cell_vy[b], corners);
    for (const auto& piece : free_cell_pieces(&before.cell_vx[b], &before.cell_vy[b], corners)) {
      append(i, polygon_centroid(piece.vx.data(), piece.vy.data(), piece.vx.size()),
             before.volume[i] * (piece.area() / parent_polygon), 0.5 * before.cell_size[i], 0.5 * before.horizon[i],
             piece.vx.data(), piece.vy.data(), piece.vx.size(), true);
    }
  }
  for (const auto& set : before.sets) {
    BoundarySet s{set.name, {}};
    for (const auto i : set.particles) {
      if (!splits[i]) s.particles.push_back(first_index[i]);
      else
        for (std::uint32_t c = 0; c < 4; ++c) s.particles.push_back(first_index[i] + c);
    }
    std::sort(s.particles.begin(), s.particles.end());
    p.sets.push_back(std::move(s));
  }
  r.rebuilt = rows_to_rebuild(before, parents, splits, r, mode);
  r.families_built = static_cast<std::size_t>(std::count(r.rebuilt.begin(), r.rebuilt.end(), 1));
  rebuild_families(p, before, r, first_index, splits, mode, partial_areas);
  return r;
}

std::vector<double> values_by_origin(const std::vector<double>& values, const std::vector<std::uint32_t>& origin,
                                     std::size_t blocks) {
  const std::size_t old_n = blocks ? values.size() / blocks : 0, n = origin.size();
  std::vector<double> out(blocks * n);
  for (std::size_t t = 0; t < blocks; ++t)
    for (std::size_t i = 0; i < n; ++i) out[t * n + i] = values[t * old_n + origin[i]];
  return out;
}

std::pair<std::vector<double>, std::vector<double>> displacements_after_split(const ParticleSet& before,
                                                                              const std::vector<double>& ux,
                                                                              const std::vector<double>& uy,
                                                                              const SplitResult& split) {
  const ParticleSet& p = split.particles;
  std::vector<double> cx = values_by_origin(ux, split.origin), cy = values_by_origin(uy, split.origin);
  const std::int64_t n = static_cast<std::int64_t>(p.size());
#pragma omp parallel for schedule(static)
  for (std::int64_t i = 0; i < n; ++i) {
    if (!split.is_child[i]) continue;
    // (Four children per parent: the gradient is computed four times; a split
    // touches few particles, and this keeps each child's line independent.)
    const auto parent = split.origin[i];
    const DisplacementGradient g = family_displacement_gradient(before, ux, uy, parent);
    const double dx = p.x[i] - before.x[parent], dy = p.y[i] - before.y[parent];
    cx[i] += g.du_dx[0][0] * dx + g.du_dx[0][1] * dy;
    cy[i] += g.du_dx[1][0] * dx + g.du_dx[1][1] * dy;
  }
  return {std::move(cx), std::move(cy)};
}

std::vector<std::pair<std::uint32_t, std::uint32_t>> inherited_broken_pairs(
    const SplitResult& split, const std::vector<std::pair<std::uint32_t, std::uint32_t>>& broken_before) {
  std::vector<std::pair<std::uint32_t, std::uint32_t>> out;
  if (broken_before.empty()) return out;
  const ParticleSet& p = split.particles;
  // Each particle of the old set's broken partners (both directions, sorted
  // per particle), so that only the families of particles whose origin had a
  // broken pair are read (a crack's neighbourhood, not the whole set).
  const std::size_t old_count = *std::max_element(split.origin.begin(), split.origin.end()) + std::size_t{1};
  std::vector<std::uint64_t> first(old_count + 1, 0);
  for (const auto& [a, b] : broken_before) ++first[a + 1], ++first[b + 1];
  for (std::size_t a = 0; a < old_count; ++a) first[a + 1] += first[a];
  std::vector<std::uint32_t> partner(first.back());
  std::vector<std::uint64_t> next(first.begin(), first.end() - 1);
  for (const auto& [a, b] : broken_before) partner[next[a]++] = b, partner[next[b]++] = a;
  for (std::size_t a = 0; a < old_count; ++a)
    std::sort(partner.begin() + static_cast<std::ptrdiff_t>(first[a]),
              partner.begin() + static_cast<std::ptrdiff_t>(first[a + 1]));
  for (std::uint32_t i = 0; i < p.size(); ++i) {
    const auto a = split.origin[i];
    const auto begin = partner.begin() + static_cast<std::ptrdiff_t>(first[a]);
    const auto end = partner.begin() + static_cast<std::ptrdiff_t>(first[a + 1]);
    if (begin == end) continue;
    for (auto k = p.family_offsets[i]; k < p.family_offsets[i + 1]; ++k) {
      const auto j = p.neighbors[k];
      const auto b = split.origin[j];
      if (a != b && std::binary_search(begin, end, b)) out.emplace_back(std::min(i, j), std::max(i, j));
    }
  }
  return sorted_unique_pairs(out);
}

}  // namespace pd::solver
