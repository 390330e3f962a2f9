#include "refinement_split.hpp"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <sstream>

#include <omp.h>

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

// The particles of the set before a split whose family holds a parent
// (ascending). A family is directed (a coarse particle's holds a small
// neighbour whose own family need not hold it back), so these are not all
// among the parents' members. A bond i -> j is never longer than
// delta_i + reach_j (reach: the largest distance from a particle to a
// vertex of its cell), the particle file's rule (docs/formats.md) and the
// FamilyBuilder's (a cell farther away cannot meet the horizon): only the
// families of the particles that near the parents' bounding box are read,
// not every bond of the set.
std::vector<std::uint32_t> families_holding_a_parent(const ParticleSet& before,
                                                     const std::vector<std::uint32_t>& parents,
                                                     const std::vector<std::uint8_t>& splits) {
  double x0 = INFINITY, x1 = -INFINITY, y0 = INFINITY, y1 = -INFINITY, reach = 0;
  for (const auto i : parents) {
    x0 = std::min(x0, before.x[i]), x1 = std::max(x1, before.x[i]);
    y0 = std::min(y0, before.y[i]), y1 = std::max(y1, before.y[i]);
    const auto b = before.cell_offsets[i], e = before.cell_offsets[i + 1];
    reach = std::max(reach, polygon_max_vertex_distance(&before.cell_vx[b], &before.cell_vy[b], e - b,
                                                        {before.x[i], before.y[i]}));
  }
  // Well above the round-off the particle file allows its bonds (1e-9).
  constexpr double margin = 1 + 1e-6;
  // (Locals: a store to the vector could alias every other array.)
  const std::uint64_t* offsets = before.family_offsets.data();
  const std::uint32_t* neighbors = before.neighbors.data();
  const std::uint8_t* split = splits.data();
  std::vector<std::uint32_t> holding;
  for (std::uint32_t i = 0; i < before.size(); ++i) {
    const double dx = std::max({x0 - before.x[i], before.x[i] - x1, 0.0});
    const double dy = std::max({y0 - before.y[i], before.y[i] - y1, 0.0});
    const double longest = (before.horizon[i] + reach) * margin;
    if (dx * dx + dy * dy > longest * longest) continue;
    std::uint8_t any = 0;
    for (auto k = offsets[i], end = offsets[i + 1]; k < end; ++k) any |= split[neighbors[k]];
    if (any) holding.push_back(i);
  }
  return holding;
}

// Where a split reaches in the set before it (theory.md Sec. 8.3.1): the
// particles whose rows (or whose children's) the split builds, and the
// partners those rows take their candidates from, found from the parents'
// families and the families near them.
struct SplitReach {
  // Per particle of the set before the split: 1 if it splits or was bonded
  // to a parent in either direction.
  std::vector<std::uint8_t> reached;
  // Per reached particle a (with partners): partner[first[a] .. end[a]),
  // ascending without repeats. For a parent: itself, its own bonds and the
  // particles bonded to it (the origins the bond rule admits in its
  // children's rows). For a particle that did not split: the parents among
  // them (its row keeps its other bonds and takes only children as new
  // candidates).
  std::vector<std::uint64_t> first, end;
  std::vector<std::uint32_t> partner;
};

SplitReach split_reach(const ParticleSet& before, const std::vector<std::uint32_t>& parents,
                       const std::vector<std::uint8_t>& splits, bool with_partners) {
  const std::size_t n = before.size();
  const auto& offsets = before.family_offsets;
  const auto& neighbors = before.neighbors;
  SplitReach s;
  s.reached = splits;
  for (const auto parent : parents)
    for (auto k = offsets[parent]; k < offsets[parent + 1]; ++k) s.reached[neighbors[k]] = 1;
  const std::vector<std::uint32_t> holding = families_holding_a_parent(before, parents, splits);
  for (const auto i : holding) s.reached[i] = 1;
  if (!with_partners) return s;
  // The bonds to a reached particle from its partners, as (particle,
  // partner): every bond to a parent, and the parents' bonds to the others.
  // Each particle's come ascending: a parent's from the first loop (families
  // in order), another's from the second (parents in order).
  std::vector<std::pair<std::uint32_t, std::uint32_t>> reverse;
  for (const auto i : holding)
    for (auto k = offsets[i]; k < offsets[i + 1]; ++k)
      if (splits[neighbors[k]]) reverse.emplace_back(neighbors[k], i);
  for (const auto parent : parents)
    for (auto k = offsets[parent]; k < offsets[parent + 1]; ++k)
      if (!splits[neighbors[k]]) reverse.emplace_back(neighbors[k], parent);
  std::vector<std::uint32_t> reached;  // ascending
  for (std::uint32_t a = 0; a < n; ++a)
    if (s.reached[a]) reached.push_back(a);
  // Each row: its own partners (a and its bonds for a parent, its bonds to
  // parents for another), then the bonds to it; both ascending.
  s.first.assign(n + 1, 0);
  for (const auto a : reached) {
    if (splits[a]) {
      s.first[a + 1] = 1 + (offsets[a + 1] - offsets[a]);
      continue;
    }
    for (auto k = offsets[a]; k < offsets[a + 1]; ++k) s.first[a + 1] += splits[neighbors[k]];
  }
  for (const auto& [a, i] : reverse) ++s.first[a + 1];
  for (std::size_t a = 0; a < n; ++a) s.first[a + 1] += s.first[a];
  s.partner.resize(s.first.back());
  s.end.resize(n);
  std::uint64_t* next = s.end.data();  // where each row's next partner goes, then its end
  std::vector<std::uint64_t> own_end(reached.size());
  for (std::size_t r = 0; r < reached.size(); ++r) {
    const auto a = reached[r];
    next[a] = s.first[a];
    if (splits[a]) s.partner[next[a]++] = a;
    for (auto k = offsets[a]; k < offsets[a + 1]; ++k)
      if (splits[a] || splits[neighbors[k]]) s.partner[next[a]++] = neighbors[k];
    own_end[r] = next[a];
  }
  for (const auto& [a, i] : reverse) s.partner[next[a]++] = i;
  // Merged into one ascending run without repeats, in place.
  std::vector<std::uint32_t> merged;
  for (std::size_t r = 0; r < reached.size(); ++r) {
    const auto a = reached[r];
    std::uint32_t* row = s.partner.data() + s.first[a] + splits[a];  // (a itself goes in below)
    std::uint32_t* middle = s.partner.data() + own_end[r];
    std::uint32_t* row_end = s.partner.data() + next[a];
    merged.clear();
    std::set_union(row, middle, middle, row_end, std::back_inserter(merged));
    if (splits[a]) merged.insert(std::lower_bound(merged.begin(), merged.end(), a), a);
    // Repeats inside one run (none in a sorted row) and a among its own bonds.
    merged.erase(std::unique(merged.begin(), merged.end()), merged.end());
    std::copy(merged.begin(), merged.end(), s.partner.data() + s.first[a]);
    next[a] = s.first[a] + merged.size();
  }
  return s;
}

// The rows of the split set that the FamilyBuilder must build: every row with
// `whole`, else the children's and those of the particles bonded to a parent
// in either direction before the split.
std::vector<std::uint8_t> rows_to_rebuild(const SplitResult& r, const SplitReach& reach, FamilyRebuild mode) {
  std::vector<std::uint8_t> rebuild(r.origin.size(), 1);
  if (mode == FamilyRebuild::whole) return rebuild;
  for (std::size_t i = 0; i < rebuild.size(); ++i) rebuild[i] = r.is_child[i] || reach.reached[r.origin[i]];
  return rebuild;
}

// Whether the split's built families take their candidates from a spatial
// search rather than from the origins the rule admits (theory.md Sec. 8.3):
// the whole rebuild searches, and so does the hhb quadrature.
bool families_searched(FamilyRebuild mode, Quadrature quadrature) {
  return mode == FamilyRebuild::whole || quadrature == Quadrature::hhb;
}

// Families of the split set (theory.md Sec. 8.3): each particle's own
// horizon, exact partial volumes from the FamilyBuilder; a bond is kept when
// its ends share an origin (siblings) or their origins were bonded before.
//
// Only the rows marked in `r.rebuilt` go through the FamilyBuilder; the
// others are their origin's row with the indices of the split set, which is
// the same family (theory.md Sec. 8.3): their origin was bonded to no parent,
// so the rule above admits none of the children, and their other candidates
// did not change. With every row marked this is the whole rebuild.
//
// `local`: a built row's candidates are the particles whose origins the rule
// admits (SplitReach), not those of a spatial search, which the split then
// does without. The FamilyBuilder gives the same family among them
// (FamilyBuilder::family_among): every cell it would search that the rule
// keeps is among them; it forms the reach and area of these cells only. A
// built row of a particle that did not split needs the children only (its
// other bonds are its own). The hhb quadrature and the whole rebuild search.
// `areas` (optional): partial areas kept across the run's splits (the local
// rebuild looks them up and adds its new ones).
void rebuild_families(ParticleSet& p, const ParticleSet& before, const SplitResult& r,
                      const std::vector<std::uint32_t>& parents, const std::vector<std::uint32_t>& new_index,
                      const std::vector<std::uint8_t>& splits, const SplitReach& reach, FamilyRebuild mode,
                      CellDiskMemo* areas) {
  const std::vector<std::uint32_t>& origin = r.origin;
  const std::vector<std::uint8_t>& rebuild = r.rebuilt;
  const bool searched = families_searched(mode, p.quadrature);
  const std::size_t n = p.size();
  std::vector<std::uint32_t> built;  // the rows to build, ascending
  for (std::uint32_t i = 0; i < n; ++i)
    if (rebuild[i]) built.push_back(i);
  // The cells a built row can take as candidates: the children and the
  // particles that did not split among the parents' partners.
  std::vector<std::uint8_t> candidate_cells;
  if (!searched) {
    candidate_cells.assign(r.is_child.begin(), r.is_child.end());
    for (const auto parent : parents)
      for (auto k = reach.first[parent]; k < reach.end[parent]; ++k)
        if (!splits[reach.partner[k]]) candidate_cells[new_index[reach.partner[k]]] = 1;
  }
  const FamilyBuilder builder = searched ? FamilyBuilder(p, p.quadrature, nullptr, true)
                                         : FamilyBuilder(p, p.quadrature, candidate_cells);
  // The built rows go one after another into one pair of buffers per thread
  // (not two vectors per row, each its own allocation): row b is
  // built_size[b] entries from built_start[b] of thread built_thread[b]'s.
  // A thread's buffers are reserved for its share of the built rows'
  // origins' members: a built row has about as many (in case 1 about 0.9 of
  // them: a child's family is about its parent's, half the horizon at half
  // the spacing), so that they seldom grow.
  const auto threads = static_cast<std::size_t>(omp_get_max_threads());
  std::uint64_t origins_members = 0;
  for (const auto i : built) origins_members += before.family_offsets[origin[i] + 1] - before.family_offsets[origin[i]];
  std::vector<std::vector<std::uint32_t>> thread_neighbors(threads);
  std::vector<std::vector<double>> thread_factors(threads);
  std::vector<std::uint64_t> built_start(built.size());
  std::vector<std::uint32_t> built_size(built.size()), built_thread(built.size());
  const auto built_count = static_cast<std::int64_t>(built.size());
  CellDiskMemo::Found new_areas;  // gathered per thread; the memo is only read in the loop
#pragma omp parallel
  {
    const auto thread = static_cast<std::uint32_t>(omp_get_thread_num());
    std::vector<std::uint32_t>& built_neighbors = thread_neighbors[thread];  // this thread's rows, one after another
    std::vector<double>& built_factors = thread_factors[thread];
    built_neighbors.reserve(origins_members / static_cast<std::uint64_t>(omp_get_num_threads()));
    built_factors.reserve(origins_members / static_cast<std::uint64_t>(omp_get_num_threads()));
    std::vector<std::uint32_t> found, candidates, child_candidates;
    std::vector<double> found_factors;
    CellDiskMemo::Found found_areas;
    std::uint32_t candidates_of = FamilyBuilder::none;  // the origin `candidates` were gathered for
#pragma omp for schedule(dynamic, 16) nowait
    for (std::int64_t b = 0; b < built_count; ++b) {
      const auto self = built[b];
      const auto a = origin[self];
      built_thread[b] = thread;
      built_start[b] = built_neighbors.size();
      const auto row_done = [&] { built_size[b] = static_cast<std::uint32_t>(built_neighbors.size() - built_start[b]); };
      if (searched) {
        builder.family({p.x[self], p.y[self]}, p.horizon[self], self, found, found_factors, candidates);
        for (std::size_t k = 0; k < found.size(); ++k) {
          const auto c = origin[found[k]];
          if (a != c && !bonded_before(before, a, c)) continue;
          built_neighbors.push_back(found[k]);
          built_factors.push_back(found_factors[k]);
        }
        row_done();
        continue;
      }
      // A particle that did not split keeps its bonds to the others that
      // did not (the same cells, positions and horizon: the factors the
      // FamilyBuilder gave them, theory.md Sec. 8.3); only the children are
      // candidates. Their indices follow every kept particle's, so the row
      // stays sorted.
      const bool kept = !r.is_child[self];
      if (kept) {
        const auto from = before.family_offsets[a], to = before.family_offsets[a + 1];
        for (auto k = from; k < to; ++k) {
          if (splits[before.neighbors[k]]) continue;
          built_neighbors.push_back(new_index[before.neighbors[k]]);
          built_factors.push_back(before.partial_volume[k]);
        }
      }
      // Ascending without repeats, as the partners are: the particles that
      // did not split keep their order, and the children follow them all,
      // in parent order (split_particles). A kept row's partners are
      // parents. The four children of a parent (consecutive rows) share
      // theirs, less those whose cells cannot meet any of their disks.
      if (a != candidates_of) {
        candidates_of = a;
        candidates.clear();
        child_candidates.clear();
        for (auto k = reach.first[a]; k < reach.end[a]; ++k) {
          const auto c = reach.partner[k];
          if (!splits[c]) {
            candidates.push_back(new_index[c]);
            continue;
          }
          for (std::uint32_t child = 0; child < 4; ++child) child_candidates.push_back(new_index[c] + child);
        }
        candidates.insert(candidates.end(), child_candidates.begin(), child_candidates.end());
        if (!kept) {
          // The children's largest distance from their parent's centre.
          double spread = 0;
          for (auto child = new_index[a]; child < new_index[a] + 4; ++child)
            spread = std::max(spread, std::hypot(p.x[child] - before.x[a], p.y[child] - before.y[a]));
          builder.candidates_near({before.x[a], before.y[a]}, p.horizon[self], spread, candidates, child_candidates);
          candidates.swap(child_candidates);
        }
      }
      builder.family_among({p.x[self], p.y[self]}, p.horizon[self], self, candidates, found, found_factors, areas,
                           &found_areas);
      built_neighbors.insert(built_neighbors.end(), found.begin(), found.end());
      built_factors.insert(built_factors.end(), found_factors.begin(), found_factors.end());
      row_done();
    }
#pragma omp critical(rebuild_families_areas)
    new_areas.insert(new_areas.end(), found_areas.begin(), found_areas.end());
  }
  if (areas) areas->add(new_areas);

  // The lists: a built row from its bonds, a copied row from its origin's
  // with the new indices.
  p.family_offsets.assign(n + 1, 0);
  for (std::size_t i = 0, b = 0; i < n; ++i)
    p.family_offsets[i + 1] = p.family_offsets[i] + (rebuild[i] ? built_size[b++]
                                                                : before.family_offsets[origin[i] + 1] -
                                                                      before.family_offsets[origin[i]]);
  p.neighbors.clear();
  p.partial_volume.clear();
  p.neighbors.reserve(p.family_offsets.back());
  p.partial_volume.reserve(p.family_offsets.back());
  for (std::size_t i = 0, b = 0; i < n; ++i) {
    if (rebuild[i]) {
      const auto from = static_cast<std::ptrdiff_t>(built_start[b]);
      const auto to = from + static_cast<std::ptrdiff_t>(built_size[b]);
      const auto& neighbors = thread_neighbors[built_thread[b]];
      const auto& factors = thread_factors[built_thread[b]];
      p.neighbors.insert(p.neighbors.end(), neighbors.begin() + from, neighbors.begin() + to);
      p.partial_volume.insert(p.partial_volume.end(), factors.begin() + from, factors.begin() + to);
      ++b;
      continue;
    }
    const auto from = static_cast<std::ptrdiff_t>(before.family_offsets[origin[i]]);
    const auto to = static_cast<std::ptrdiff_t>(before.family_offsets[origin[i] + 1]);
    if (from == to) continue;
    p.partial_volume.insert(p.partial_volume.end(), before.partial_volume.begin() + from,
                            before.partial_volume.begin() + to);
    p.neighbors.insert(p.neighbors.end(), before.neighbors.begin() + from, before.neighbors.begin() + to);
    // A row whose first and last members moved down by as many places (no
    // parent between them) moves down whole: a subtraction, not a look-up.
    std::uint32_t* row = p.neighbors.data() + p.family_offsets[i];
    const auto count = static_cast<std::size_t>(to - from);
    const std::uint32_t shift = row[0] - new_index[row[0]];
    if (row[count - 1] - new_index[row[count - 1]] == shift) {
      if (shift != 0)
        for (std::size_t k = 0; k < count; ++k) row[k] -= shift;
    } else {
      for (std::size_t k = 0; k < count; ++k) row[k] = new_index[row[k]];
    }
  }
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
  // The particles that did not split, a run between two parents at a time.
  const auto copy_run = [&](std::uint32_t from, std::uint32_t to) {
    if (from >= to) return;
    const auto first = static_cast<std::ptrdiff_t>(from), last = static_cast<std::ptrdiff_t>(to);
    const auto copy = [&](auto& into, const auto& values) {
      into.insert(into.end(), values.begin() + first, values.begin() + last);
    };
    copy(p.x, before.x), copy(p.y, before.y), copy(p.volume, before.volume), copy(p.cell_size, before.cell_size);
    copy(p.horizon, before.horizon), copy(p.region, before.region), copy(p.material, before.material);
    const std::uint64_t vertices = p.cell_vx.size(), vertex_from = before.cell_offsets[from];
    for (auto i = from; i < to; ++i) p.cell_offsets.push_back(vertices + (before.cell_offsets[i + 1] - vertex_from));
    const auto vertex_first = static_cast<std::ptrdiff_t>(vertex_from);
    const auto vertex_last = static_cast<std::ptrdiff_t>(before.cell_offsets[to]);
    p.cell_vx.insert(p.cell_vx.end(), before.cell_vx.begin() + vertex_first, before.cell_vx.begin() + vertex_last);
    p.cell_vy.insert(p.cell_vy.end(), before.cell_vy.begin() + vertex_first, before.cell_vy.begin() + vertex_last);
    for (auto i = from; i < to; ++i) {
      first_index[i] = static_cast<std::uint32_t>(r.origin.size());
      r.origin.push_back(i);
    }
    r.is_child.insert(r.is_child.end(), to - from, 0);
  };
  std::uint32_t run_start = 0;
  for (const auto parent : parents) {
    copy_run(run_start, parent);
    run_start = parent + 1;
  }
  copy_run(run_start, static_cast<std::uint32_t>(n));
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
  const bool searched = families_searched(mode, before.quadrature);
  SplitReach reach;
  if (mode == FamilyRebuild::local) reach = split_reach(before, parents, splits, !searched);
  r.rebuilt = rows_to_rebuild(r, reach, mode);
  r.families_built = static_cast<std::size_t>(std::count(r.rebuilt.begin(), r.rebuilt.end(), 1));
  rebuild_families(p, before, r, parents, first_index, splits, reach, mode, partial_areas);
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

BrokenPartners::BrokenPartners(const std::vector<std::pair<std::uint32_t, std::uint32_t>>& pairs,
                               std::size_t particle_count)
    : first_(particle_count + 1, 0) {
  for (const auto& [a, b] : pairs) ++first_[a + 1], ++first_[b + 1];
  for (std::size_t a = 0; a < particle_count; ++a) first_[a + 1] += first_[a];
  partner_.resize(first_.back());
  std::vector<std::uint64_t> next(first_.begin(), first_.end() - 1);
  for (const auto& [a, b] : pairs) partner_[next[a]++] = b, partner_[next[b]++] = a;
  for (std::size_t a = 0; a < particle_count; ++a) std::sort(partner_.data() + first_[a], partner_.data() + first_[a + 1]);
}

std::pair<std::vector<double>, std::vector<double>> displacements_after_split(
    const ParticleSet& before, const std::vector<double>& ux, const std::vector<double>& uy, const SplitResult& split,
    const BrokenPartners* broken, const std::vector<std::uint8_t>* by_intact_bonds) {
  const ParticleSet& p = split.particles;
  std::vector<double> cx = values_by_origin(ux, split.origin), cy = values_by_origin(uy, split.origin);
  const std::int64_t n = static_cast<std::int64_t>(p.size());
#pragma omp parallel for schedule(static)
  for (std::int64_t i = 0; i < n; ++i) {
    if (!split.is_child[i]) continue;
    // (Four children per parent: the gradient is computed four times; a split
    // touches few particles, and this keeps each child's line independent.)
    const auto parent = split.origin[i];
    std::optional<DisplacementGradient> intact;
    if (broken && by_intact_bonds && (*by_intact_bonds)[parent] && broken->begin(parent) != broken->end(parent))
      intact = family_displacement_gradient_without(before, ux, uy, parent, broken->begin(parent), broken->end(parent));
    const DisplacementGradient g = intact ? *intact : family_displacement_gradient(before, ux, uy, parent);
    const double dx = p.x[i] - before.x[parent], dy = p.y[i] - before.y[parent];
    cx[i] += g.du_dx[0][0] * dx + g.du_dx[0][1] * dy;
    cy[i] += g.du_dx[1][0] * dx + g.du_dx[1][1] * dy;
  }
  return {std::move(cx), std::move(cy)};
}

std::vector<std::pair<std::uint32_t, std::uint32_t>> inherited_broken_pairs(
    const SplitResult& split, const std::vector<std::pair<std::uint32_t, std::uint32_t>>& broken_before) {
  if (broken_before.empty()) return {};
  const ParticleSet& p = split.particles;
  // Only the families of particles whose origin had a broken pair are read
  // (a crack's neighbourhood, not the whole set).
  const std::size_t old_count = *std::max_element(split.origin.begin(), split.origin.end()) + std::size_t{1};
  const BrokenPartners partners(broken_before, old_count);
  // The broken partners of the current origin marked (a parent's four
  // children are consecutive and share them); an origin is never its own partner.
  std::vector<std::uint8_t> is_partner(old_count, 0);
  std::uint32_t marked = static_cast<std::uint32_t>(old_count);
  const auto mark = [&](std::uint32_t origin, std::uint8_t value) {
    for (const auto* b = partners.begin(origin); b != partners.end(origin); ++b) is_partner[*b] = value;
  };
  // A pair (i, j) found in i's family with j > i goes to `forward`: rows in
  // ascending order, each family ascending, so `forward` comes out sorted.
  // One found with j < i goes to `backward` as (j, i); it is there too when
  // j's family holds i (not always: dual horizons), so the two are merged.
  std::vector<std::pair<std::uint32_t, std::uint32_t>> forward, backward;
  for (std::uint32_t i = 0; i < p.size(); ++i) {
    const auto a = split.origin[i];
    if (partners.begin(a) == partners.end(a)) continue;
    if (a != marked) {
      if (marked < old_count) mark(marked, 0);
      mark(a, 1);
      marked = a;
    }
    for (auto k = p.family_offsets[i]; k < p.family_offsets[i + 1]; ++k) {
      const auto j = p.neighbors[k];
      if (!is_partner[split.origin[j]]) continue;
      if (j > i) forward.emplace_back(i, j);
      else backward.emplace_back(j, i);
    }
  }
  // A family out of ascending order: the counting sort of every pair.
  const auto not_ascending = [](const auto& x, const auto& y) { return x >= y; };
  if (std::adjacent_find(forward.begin(), forward.end(), not_ascending) != forward.end()) {
    forward.insert(forward.end(), backward.begin(), backward.end());
    return sorted_unique_pairs(forward);
  }
  backward = sorted_unique_pairs(backward);
  std::vector<std::pair<std::uint32_t, std::uint32_t>> out;
  out.reserve(forward.size() + backward.size());
  std::set_union(forward.begin(), forward.end(), backward.begin(), backward.end(), std::back_inserter(out));
  return out;
}

}  // namespace pd::solver
