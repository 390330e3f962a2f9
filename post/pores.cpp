#include "pores.hpp"
#include "number_table.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <limits>
#include <sstream>

#include "crack_branches.hpp"
#include "error.hpp"
#include "tip_tracking.hpp"

namespace pd::post {

std::vector<Pore> read_pores_csv(const std::string& path) {
  const std::string expected = "x_m,y_m,r_m with r_m > 0";
  std::vector<Pore> pores;
  for (const auto& row : read_number_table(path, 3, "the pore file", expected)) {
    Pore p = circle_pore(row.values[0], row.values[1], row.values[2]);
    p.line = row.line;
    if (p.radius <= 0) throw file_error(path, "line " + std::to_string(row.line) + ": expected " + expected);
    pores.push_back(p);
  }
  return pores;
}

void check_pore_file(const std::string& path, const std::vector<Pore>& pores, const ArrivalData& d,
                     std::vector<std::string>& warnings) {
  const PlateExtent plate = plate_extent(d);
  for (std::size_t k = 0; k < pores.size(); ++k) {
    const Pore& p = pores[k];
    char text[400];
    // A circle off the plate (e.g. written in mm) would find no crack at any pore.
    if (!plate.contains(p.x, p.y)) {
      std::snprintf(text, sizeof text, "line %d: pore %zu at (%g, %g) m lies off the plate (%s): the file is in "
                    "metres (x_m,y_m,r_m)", p.line, k + 1, p.x, p.y, plate.text().c_str());
      throw file_error(path, text);
    }
    const double r2 = 0.64 * p.radius * p.radius;
    std::size_t inside = 0;
    for (std::size_t i = 0; i < d.size(); ++i)
      inside += (d.x[i] - p.x) * (d.x[i] - p.x) + (d.y[i] - p.y) * (d.y[i] - p.y) < r2;
    if (inside > 0) {
      std::snprintf(text, sizeof text,
                    "line %d: the circle at (%g, %g) m of radius %g m holds %zu particle centre%s within 0.8 r of "
                    "its centre: a pore of the plate holds none (its cells are removed); the file is in metres "
                    "(x_m,y_m,r_m)",
                    p.line, p.x, p.y, p.radius, inside, inside == 1 ? "" : "s");
      throw file_error(path, text);
    }
    // A circle smaller than a cell holds no centre wherever it lies: its
    // centre inside a cell (within 0.8 of the half side, as generous as
    // above) is in solid material (before 7 December 2026 a circle of
    // 1e-300 m on a crack's path passed, and the crack "visited" it).
    for (std::size_t i = 0; i < d.size(); ++i) {
      const double reach = 0.4 * d.cell_size[i];
      if (std::abs(d.x[i] - p.x) > reach || std::abs(d.y[i] - p.y) > reach) continue;
      std::snprintf(text, sizeof text,
                    "line %d: the circle at (%g, %g) m of radius %g m has its centre in the cell of particle %zu, "
                    "at (%g, %g) m, %g mm across: a pore's centre lies in no cell (its cells are removed); the file "
                    "is in metres (x_m,y_m,r_m)",
                    p.line, p.x, p.y, p.radius, i, d.x[i], d.y[i], d.cell_size[i] * 1e3);
      throw file_error(path, text);
    }
    // A circle centred between cells (on a corner or an edge, which the
    // reach above leaves out) is seen by the particles only if it is a fair
    // part of the cells about it: one of less than a quarter of their size
    // takes less than a fifth of a cell (pi / 16), which no layout shows as
    // a void, so a crack passing by would "visit" a pore the plate does not
    // have (before 7 December 2026 one of 1e-6 m on a cell's corner passed).
    std::size_t nearest = 0;
    double nearest_d2 = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < d.size(); ++i)
      if (const double d2 = (d.x[i] - p.x) * (d.x[i] - p.x) + (d.y[i] - p.y) * (d.y[i] - p.y); d2 < nearest_d2)
        nearest_d2 = d2, nearest = i;
    if (d.size() > 0 && p.radius < smallest_pore_file_cells * d.cell_size[nearest]) {
      std::snprintf(text, sizeof text,
                    "line %d: the circle at (%g, %g) m of radius %g m is %.3g times the cells about it (%g mm "
                    "across, particle %zu's, the nearest): a pore below %g of a cell takes too little of one for "
                    "the particles to show it; give the pore's radius in metres (x_m,y_m,r_m), or leave it out",
                    p.line, p.x, p.y, p.radius, p.radius / d.cell_size[nearest], d.cell_size[nearest] * 1e3, nearest,
                    smallest_pore_file_cells);
      throw file_error(path, text);
    }
  }
  // The same pore twice would count each of its visits twice.
  for (std::size_t k = 0; k < pores.size(); ++k)
    for (std::size_t m = k + 1; m < pores.size(); ++m)
      if (const double apart = std::hypot(pores[k].x - pores[m].x, pores[k].y - pores[m].y); apart <= d.spacing) {
        char text[200];
        std::snprintf(text, sizeof text,
                      ": lines %d and %d give the same pore (centres %g mm apart, within a spacing of %g mm): "
                      "its visits are counted twice",
                      pores[k].line, pores[m].line, apart * 1e3, d.spacing * 1e3);
        warnings.push_back(path + text);
      }
}

bool PoreOutline::contains(double px, double py) const {
  const double i = std::floor((px - x0) / cell), j = std::floor((py - y0) / cell);
  if (!(i >= 0 && j >= 0 && i < static_cast<double>(nx) && j < static_cast<double>(ny))) return false;
  return inside[static_cast<std::size_t>(static_cast<long>(j) * nx + static_cast<long>(i))] != 0;
}

bool Pore::contains(double px, double py) const {
  return has_outline() ? outline.contains(px, py) : std::hypot(px - x, py - y) < radius;
}

double Pore::length_inside(double x0, double y0, double x1, double y1) const {
  if (!has_outline()) {
    // The chord of the disk: the roots of |f + t d|^2 = r^2, clipped to [0, 1].
    const double dx = x1 - x0, dy = y1 - y0, fx = x0 - x, fy = y0 - y;
    const double a = dx * dx + dy * dy, b = fx * dx + fy * dy, c = fx * fx + fy * fy - radius * radius;
    const double disc = b * b - a * c;
    if (a == 0 || disc <= 0) return 0;
    const double t0 = std::max(0.0, (-b - std::sqrt(disc)) / a), t1 = std::min(1.0, (-b + std::sqrt(disc)) / a);
    return t1 > t0 ? (t1 - t0) * std::sqrt(a) : 0;
  }
  const double length = std::hypot(x1 - x0, y1 - y0);
  const long steps = std::max(1L, static_cast<long>(std::ceil(length / (0.5 * outline.cell))));
  long in = 0;
  for (long k = 0; k < steps; ++k) {
    const double f = (k + 0.5) / static_cast<double>(steps);
    in += outline.contains(x0 + f * (x1 - x0), y0 + f * (y1 - y0));
  }
  return length * static_cast<double>(in) / static_cast<double>(steps);
}

double Pore::edge_distance(double px, double py) const {
  if (!has_outline()) return std::hypot(px - x, py - y) - radius;
  // To the nearest edge cell's square: outside the hole, the distance to the
  // hole (its nearest point lies in an edge cell); inside, minus the
  // distance to the nearest edge cell's centre.
  const double half = 0.5 * outline.cell;
  const bool in = outline.contains(px, py);
  double nearest = std::numeric_limits<double>::infinity();
  for (std::size_t k = 0; k < outline.edge_x.size(); ++k) {
    const double ex = std::fabs(px - outline.edge_x[k]), ey = std::fabs(py - outline.edge_y[k]);
    const double to_square = std::hypot(std::max(ex - half, 0.0), std::max(ey - half, 0.0));
    nearest = std::min(nearest, in ? std::hypot(ex, ey) : to_square);
  }
  return in ? -nearest : nearest;
}

bool Pore::within(double px, double py, double ring) const {
  if (!has_outline()) return std::hypot(px - x, py - y) <= radius + ring;
  if (std::hypot(px - x, py - y) > enclosing_radius() + ring) return false;
  return edge_distance(px, py) <= ring;
}

double Pore::enclosing_radius() const {
  // (`reach` is the farthest edge cell's centre; its far corner lies beyond.)
  return has_outline() ? reach + std::sqrt(0.5) * outline.cell : radius;
}

double Pore::x_min() const {
  if (!has_outline()) return x - radius;
  return *std::min_element(outline.edge_x.begin(), outline.edge_x.end()) - 0.5 * outline.cell;
}

double Pore::x_max() const {
  if (!has_outline()) return x + radius;
  return *std::max_element(outline.edge_x.begin(), outline.edge_x.end()) + 0.5 * outline.cell;
}

namespace {

// The outline of a hole made of raster cells `hole_cells` (indices into the
// raster of `nx` columns, origin (x0, y0), cell side h), without its spurs:
// the gaps between free cells next to a hole join it as slits a raster cell
// or two wide, which an opening removes (the cells whose 3 x 3 block lies in
// the hole, grown back by one cell within it).
PoreOutline hole_outline(const std::vector<long>& hole_cells, long nx, double x0, double y0, double h) {
  long i0 = std::numeric_limits<long>::max(), i1 = -1, j0 = std::numeric_limits<long>::max(), j1 = -1;
  for (long c : hole_cells) {
    const long i = c % nx, j = c / nx;
    i0 = std::min(i0, i), i1 = std::max(i1, i), j0 = std::min(j0, j), j1 = std::max(j1, j);
  }
  PoreOutline o;
  o.cell = h;
  o.x0 = x0 + i0 * h, o.y0 = y0 + j0 * h;
  o.nx = i1 - i0 + 1, o.ny = j1 - j0 + 1;
  std::vector<std::uint8_t> raw(static_cast<std::size_t>(o.nx * o.ny), 0);
  for (long c : hole_cells) raw[static_cast<std::size_t>((c / nx - j0) * o.nx + (c % nx - i0))] = 1;
  const auto at = [&](const std::vector<std::uint8_t>& mask, long i, long j) {
    return i >= 0 && j >= 0 && i < o.nx && j < o.ny && mask[static_cast<std::size_t>(j * o.nx + i)] != 0;
  };
  // How many cells of the 3 x 3 block about (i, j) the mask holds.
  const auto block_count = [&](const std::vector<std::uint8_t>& mask, long i, long j) {
    int n = 0;
    for (long dj = -1; dj <= 1; ++dj)
      for (long di = -1; di <= 1; ++di) n += at(mask, i + di, j + dj);
    return n;
  };
  std::vector<std::uint8_t> eroded(raw.size(), 0);
  for (long j = 0; j < o.ny; ++j)
    for (long i = 0; i < o.nx; ++i) eroded[static_cast<std::size_t>(j * o.nx + i)] = block_count(raw, i, j) == 9;
  o.inside.assign(raw.size(), 0);
  bool any = false;
  for (long j = 0; j < o.ny; ++j)
    for (long i = 0; i < o.nx; ++i) {
      const bool kept = at(raw, i, j) && block_count(eroded, i, j) > 0;
      o.inside[static_cast<std::size_t>(j * o.nx + i)] = kept;
      any |= kept;
    }
  if (!any) o.inside = raw;  // a hole thinner than three cells: all of it
  for (long j = 0; j < o.ny; ++j)
    for (long i = 0; i < o.nx; ++i)
      if (at(o.inside, i, j) &&
          (!at(o.inside, i - 1, j) || !at(o.inside, i + 1, j) || !at(o.inside, i, j - 1) || !at(o.inside, i, j + 1)))
        o.edge_x.push_back(o.x0 + (i + 0.5) * h), o.edge_y.push_back(o.y0 + (j + 0.5) * h);
  return o;
}

}  // namespace

std::vector<Pore> detect_pores(const ArrivalData& d, std::vector<Pore>* ignored, std::vector<std::string>* warnings) {
  std::vector<double> sizes = d.cell_size;
  std::nth_element(sizes.begin(), sizes.begin() + sizes.size() / 2, sizes.end());
  const double typical = sizes[sizes.size() / 2];
  const double max_cell = *std::max_element(d.cell_size.begin(), d.cell_size.end());
  if (!(typical > 0)) return {};
  // Occupancy grid at half the typical cell size, one free cell of margin.
  const double h = 0.5 * typical;
  const double x0 = *std::min_element(d.x.begin(), d.x.end()) - max_cell;
  const double y0 = *std::min_element(d.y.begin(), d.y.end()) - max_cell;
  const double x1 = *std::max_element(d.x.begin(), d.x.end()) + max_cell;
  const double y1 = *std::max_element(d.y.begin(), d.y.end()) + max_cell;
  // Counted in doubles: read_points bounds the layout, but not to a product of longs.
  const double cells_x = std::ceil((x1 - x0) / h), cells_y = std::ceil((y1 - y0) / h);
  if (cells_x * cells_y > max_pore_raster_cells) {
    // Before 7 December 2026 no pores were reported without a word.
    if (warnings) {
      char text[400];
      std::snprintf(text, sizeof text,
                    "pores were not looked for: the plate, %.4g x %.4g mm, is %.3g raster cells of %.4g mm (half "
                    "the median cell size), more than the %.3g pd-post lays over it to find holes (particles far "
                    "apart for their cells); give --pores FILE to count pore visits",
                    (x1 - x0) * 1e3, (y1 - y0) * 1e3, cells_x * cells_y, h * 1e3, max_pore_raster_cells);
      warnings->push_back(text);
    }
    return {};
  }
  const long nx = static_cast<long>(cells_x), ny = static_cast<long>(cells_y);
  std::vector<std::uint8_t> filled(static_cast<std::size_t>(nx * ny), 0);
  for (std::size_t p = 0; p < d.size(); ++p) {
    const double half = 0.5 * d.cell_size[p] * 1.05;  // slight overlap closes round-off slits
    const long i0 = std::max(0L, static_cast<long>(std::ceil((d.x[p] - half - x0) / h - 0.5)));
    const long i1 = std::min(nx - 1, static_cast<long>(std::floor((d.x[p] + half - x0) / h - 0.5)));
    const long j0 = std::max(0L, static_cast<long>(std::ceil((d.y[p] - half - y0) / h - 0.5)));
    const long j1 = std::min(ny - 1, static_cast<long>(std::floor((d.y[p] + half - y0) / h - 0.5)));
    for (long j = j0; j <= j1; ++j)
      for (long i = i0; i <= i1; ++i) filled[j * nx + i] = 1;
  }
  // Flood the empty cells: 2 = outside (reached from the border), 3+ = holes.
  std::vector<long> stack;
  std::vector<long> hole_cells;
  auto flood = [&](long start, std::uint8_t tag, double& sx, double& sy, long& count) {
    stack.assign(1, start);
    filled[start] = tag;
    hole_cells.clear();
    while (!stack.empty()) {
      const long c = stack.back();
      stack.pop_back();
      if (tag != 2) hole_cells.push_back(c);
      const long i = c % nx, j = c / nx;
      sx += x0 + (i + 0.5) * h, sy += y0 + (j + 0.5) * h, ++count;
      const long next[4] = {i > 0 ? c - 1 : -1, i + 1 < nx ? c + 1 : -1, j > 0 ? c - nx : -1,
                            j + 1 < ny ? c + nx : -1};
      for (long m : next)
        if (m >= 0 && filled[m] == 0) filled[m] = tag, stack.push_back(m);
    }
  };
  double sx = 0, sy = 0;
  long count = 0;
  flood(0, 2, sx, sy, count);  // corner (0,0) is in the free margin
  std::vector<Pore> pores;
  for (long c = 0; c < nx * ny; ++c) {
    if (filled[c] != 0) continue;
    sx = sy = 0, count = 0;
    flood(c, 3, sx, sy, count);
    Pore p;
    p.x = sx / count;
    p.y = sy / count;
    p.radius = std::sqrt(count * h * h / M_PI);
    if (p.radius < smallest_pore_cells * typical) {
      if (ignored && p.radius >= 0.75 * typical) ignored->push_back(p);
      continue;
    }
    // Its extent: the farthest cell of its outline (spurs removed) from its
    // centre. A hole that reaches more than a cell beyond its circle (an
    // ellipse, a slot, a traced pore with lobes, pores that touch) is
    // measured by its outline: the circle's ring would miss a crack there.
    PoreOutline outline = hole_outline(hole_cells, nx, x0, y0, h);
    for (std::size_t k = 0; k < outline.edge_x.size(); ++k)
      p.reach = std::max(p.reach, std::hypot(outline.edge_x[k] - p.x, outline.edge_y[k] - p.y));
    if (p.reach > p.radius + typical) p.outline = std::move(outline);
    pores.push_back(std::move(p));
  }
  std::sort(pores.begin(), pores.end(), [](const Pore& a, const Pore& b) {
    return a.x != b.x ? a.x < b.x : a.y < b.y;
  });
  return pores;
}

namespace {

// Where and when the crack restarts beyond a pore it entered (rule in pores.hpp):
// the first particle cracked after the entry, within the ring, on the far half,
// of the visiting branch (`visitor`, -1 for none) or of a branch born within the
// ring; or the first time a tip that was within the ring leaves it again, if
// that is after the entry. Never at or before the entry.
void find_restart(PoreVisit& v, int visitor, std::size_t first_tip_sample,
                  const std::vector<CrackBranch>& branches, const std::vector<TipPath>& tips,
                  const Pore& pore, const ArrivalData& data, double ring) {
  auto at_pore = [&](double x, double y) { return pore.within(x, y, ring); };
  const double ex = v.enter_x - pore.x, ey = v.enter_y - pore.y;
  // Beyond the pore: a round one's far half (more than 90 degrees around
  // from the entry); for an outline, across it from the entry point (a
  // straight line to it crosses a cell's size of the pore), since a slot
  // entered at one end across its short side is left on the same half.
  const auto beyond = [&](double x, double y) {
    if (!pore.has_outline()) return (x - pore.x) * ex + (y - pore.y) * ey < 0;
    return pore.length_inside(v.enter_x, v.enter_y, x, y) > 2 * pore.outline.cell;
  };
  const auto restart_beyond = [&](const CrackBranch& branch) {
    for (auto p : branch.particles) {
      const double t = data.arrival[p];
      if (t <= v.enter_time || !at_pore(data.x[p], data.y[p])) continue;
      if (beyond(data.x[p], data.y[p]) && (v.restart_time < 0 || t < v.restart_time))
        v.restart_time = t, v.jumped = true;
    }
  };
  // A restart comes after the entry. A tip that left the ring before it
  // (a branch born in the ring that ran off before the visiting tip
  // arrived, e.g. a crack nucleated at the pore's edge) did not end this
  // visit: its leaving is no restart.
  const auto leaves_ring = [&](const TipPath& tip, std::size_t from) {
    for (std::size_t m = from; m < tip.time.size(); ++m)
      if (!at_pore(tip.x[m], tip.y[m])) {
        if (tip.time[m] > v.enter_time && (v.restart_time < 0 || tip.time[m] < v.restart_time))
          v.restart_time = tip.time[m], v.jumped = false;
        return;
      }
  };
  if (visitor >= 0) {
    restart_beyond(branches[visitor]);
    leaves_ring(tips[visitor], first_tip_sample);
  }
  // The crack may also go on as other branches that start within the
  // ring: the visiting branch's children when it forks at the pore, or a
  // crack that nucleates on the pore's far side while the tip waits.
  for (std::size_t c = 0; c < branches.size(); ++c)
    if (static_cast<int>(c) != visitor && !tips[c].time.empty() && at_pore(tips[c].x[0], tips[c].y[0])) {
      restart_beyond(branches[c]);
      if (visitor < 0) leaves_ring(tips[c], 1);  // a fork at the pore: its tips are the crack's
    }
  if (v.restart_time >= 0) v.trapping_time = v.restart_time - v.enter_time;
}

}  // namespace

std::vector<PoreVisit> find_pore_visits(const std::vector<CrackBranch>& branches,
                                        const std::vector<TipPath>& tips,
                                        const std::vector<Pore>& pores, const ArrivalData& data,
                                        double ring) {
  std::vector<PoreVisit> visits;
  for (std::size_t q = 0; q < pores.size(); ++q) {
    const Pore& pore = pores[q];
    auto at_pore = [&](double x, double y) { return pore.within(x, y, ring); };
    bool visited = false;
    for (std::size_t b = 0; b < branches.size(); ++b) {
      const TipPath& tip = tips[b];
      if (tip.time.empty() || at_pore(tip.x[0], tip.y[0])) continue;  // born at the pore
      std::size_t k = 0;
      double farthest = 0;  // the tip's largest distance from the ring before it enters [m]
      for (; k < tip.time.size() && !at_pore(tip.x[k], tip.y[k]); ++k)
        if (farthest <= ring)  // (only whether it came from beyond the ring's width matters)
          farthest = std::max(farthest, pore.edge_distance(tip.x[k], tip.y[k]) - ring);
      if (k == tip.time.size()) continue;
      // A tip that never left the ring's neighbourhood (a crack nucleated at
      // the pore's edge, first seen just outside the ring) was born there.
      if (farthest <= ring) continue;
      PoreVisit v;
      v.pore = static_cast<int>(q);
      v.branch = branches[b].id;
      v.enter_time = tip.time[k];
      v.enter_x = tip.x[k];
      v.enter_y = tip.y[k];
      find_restart(v, static_cast<int>(b), k + 1, branches, tips, pore, data, ring);
      visits.push_back(v);
      visited = true;
    }
    if (visited) continue;
    // No tip entered the ring from outside, yet a branch forked off its parent
    // within it: the parent reached the pore and split there in one go (its own
    // tip path ends before the ring). The earliest such fork is the visit, by
    // the parent, entering where and when the fork was born.
    std::size_t fork = branches.size();
    for (std::size_t c = 0; c < branches.size(); ++c)
      if (branches[c].parent >= 0 && !tips[c].time.empty() && at_pore(tips[c].x[0], tips[c].y[0]) &&
          (fork == branches.size() || tips[c].time[0] < tips[fork].time[0]))
        fork = c;
    if (fork == branches.size()) continue;
    PoreVisit v;
    v.pore = static_cast<int>(q);
    v.branch = branches[fork].parent;
    v.enter_time = tips[fork].time[0];
    v.enter_x = tips[fork].x[0];
    v.enter_y = tips[fork].y[0];
    find_restart(v, -1, 0, branches, tips, pore, data, ring);
    visits.push_back(v);
  }
  std::stable_sort(visits.begin(), visits.end(),
                   [](const PoreVisit& a, const PoreVisit& b) { return a.branch < b.branch; });
  return visits;
}

}  // namespace pd::post
