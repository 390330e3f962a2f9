#include "bond_weights.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <optional>

namespace pd {
namespace {

// Antiderivative of sec^3: int sec^3 = (sec tan + ln(sec + tan)) / 2, for
// |phi| < pi/2, with ln(sec + tan) = asinh(tan): near phi = -pi/2 the sum
// sec + tan cancels to zero or below in floating point (log -> -inf or NaN),
// which an edge whose line passes a hair off the centre reaches.
double sec_cubed_integral(double phi) {
  const double sec = 1.0 / std::cos(phi), tan = std::tan(phi);
  return 0.5 * (sec * tan + std::asinh(tan));
}

// Signed int over the triangle (centre, a, b) ∩ disk of the distance to the
// centre; a and b relative to the centre. In polar coordinates about the
// centre: int_{theta_a}^{theta_b} min(rho(theta), R)^3 / 3 dtheta, where
// rho = p / cos(phi) is the distance to the edge's line (p its distance, phi the
// angle from the foot of the perpendicular).
double triangle_disk_moment(Vec2 a, Vec2 b, double radius) {
  const double sweep = std::atan2(cross(a, b), dot(a, b));
  const double scale = std::sqrt(dot(a, a) * dot(b, b));
  if (std::fabs(cross(a, b)) <= 1e-14 * scale) return 0.0;  // the edge's line passes through the centre
  const Vec2 d = b - a;
  const Vec2 foot = a + (-dot(a, d) / dot(d, d)) * d;
  const double p = std::sqrt(dot(foot, foot));
  const double foot_angle = std::atan2(foot.y, foot.x);
  double phi_a = std::atan2(a.y, a.x) - foot_angle;
  // Into [-pi, pi]; |phi_a| < pi/2 since a is on the line. remainder(x, 2 pi)
  // is x itself for |x| <= pi (a quotient below 1/2 rounds to 0, 1/2 to even 0).
  if (!(std::fabs(phi_a) <= M_PI)) phi_a = std::remainder(phi_a, 2 * M_PI);
  const double phi_b = phi_a + sweep;
  const double lo = std::min(phi_a, phi_b), hi = std::max(phi_a, phi_b);
  const double r3 = radius * radius * radius / 3.0;

  double breaks[4] = {lo, hi, hi, hi};
  int count = 1;
  if (p < radius) {
    const double phi_c = std::acos(p / radius);  // rho = R there
    for (double c : {-phi_c, phi_c})
      if (c > lo && c < hi) breaks[count++] = c;
  }
  breaks[count++] = hi;
  std::sort(breaks, breaks + count);
  double integral = 0;
  for (int k = 0; k + 1 < count; ++k) {
    const double x0 = breaks[k], x1 = breaks[k + 1];
    if (x1 <= x0) continue;
    // With p >= R the edge is nowhere inside (p / cos >= p >= R): no cosine needed.
    const double mid = 0.5 * (x0 + x1);
    if (p < radius && p / std::cos(mid) < radius)
      integral += p * p * p / 3.0 * (sec_cubed_integral(x1) - sec_cubed_integral(x0));
    else integral += r3 * (x1 - x0);
  }
  return sweep >= 0 ? integral : -integral;
}

}  // namespace

double polygon_disk_distance_moment(const double* vx, const double* vy, std::size_t n, Vec2 center, double radius) {
  double total = 0;
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t l = (k + 1) % n;
    total += triangle_disk_moment(Vec2{vx[k], vy[k]} - center, Vec2{vx[l], vy[l]} - center, radius);
  }
  return std::fabs(total);
}

namespace {

// int over (square cell at offset (di, dj) cells) ∩ disk(0, horizon) of |x| dA,
// for every offset within the horizon and one cell beyond: between two whole
// squares of one size the distance moment depends only on the offset.
class SquareMomentTable {
public:
  // `memo` (optional): moments kept from earlier set-ups (the same squares
  // about the same centre, 0), and where this table's new ones are kept.
  SquareMomentTable(double spacing, double horizon, CellDiskMemo* memo)
      : reach_(static_cast<long>(std::ceil(horizon / spacing)) + 1), width_(2 * reach_ + 1) {
    moment_.resize(static_cast<std::size_t>(width_ * width_));
    CellDiskMemo::Found found;
    for (long dj = -reach_; dj <= reach_; ++dj)
      for (long di = -reach_; di <= reach_; ++di) {
        const double cx = di * spacing, cy = dj * spacing, h = 0.5 * spacing;
        const double vx[4] = {cx - h, cx + h, cx + h, cx - h}, vy[4] = {cy - h, cy - h, cy + h, cy + h};
        const auto key = CellDiskMemo::key(vx, vy, Vec2{0, 0}, horizon);
        const double* known = memo ? memo->find(key) : nullptr;
        const double moment = known ? *known : polygon_disk_distance_moment(vx, vy, 4, Vec2{0, 0}, horizon);
        if (memo && !known) found.emplace_back(key, moment);
        moment_[static_cast<std::size_t>((dj + reach_) * width_ + (di + reach_))] = moment;
      }
    if (memo) memo->add(found);
  }
  bool covers(long di, long dj) const { return std::labs(di) <= reach_ && std::labs(dj) <= reach_; }
  double operator()(long di, long dj) const {
    return moment_[static_cast<std::size_t>((dj + reach_) * width_ + (di + reach_))];
  }

private:
  long reach_, width_;
  std::vector<double> moment_;
};

// How the weight of a bond i -> j is computed (its route): from the square
// table of a level (its spacing and horizon), when i is a square of a level
// whose horizon is its own and j a square of the same level, else from j's
// cell polygon. Two sets whose bond has the same route and the same geometry
// give the same weight bit for bit. (Partial-volume weights, phi_ij A_j
// |xi_ij|, have one route, which also needs the same phi_ij: a family made
// listed from a stencil holds the stencil's, not the file's.)
//
// A particle's part of the route is the same for all its bonds: whether its
// own level's table applies and that level's spacing and horizon. So the
// routes of an earlier particle's bonds are compared with the later one's
// bond by bond, in family order, without being formed.
//
// The table route of `f`'s particle i with horizon `horizon` [m]: its level
// (its bonds to squares of that level take the table), or Families::no_level.
std::uint8_t table_level(const Families& f, bool moments, std::size_t i, double horizon) {
  const std::uint8_t l = f.level[i];
  return moments && l != Families::no_level && f.levels[l].horizon == horizon ? l : Families::no_level;
}

// The weights of the earlier particle o that has the same family as
// particle i of the later set (EarlierBondWeights), bond by bond.
class EarlierRow {
public:
  // `own_level`: i's table_level in the later families `later`.
  EarlierRow(const EarlierBondWeights& earlier, std::uint32_t o, bool moments, double horizon,
             const Families& later, std::uint8_t own_level)
      : f_(*earlier.families), w_(*earlier.weights), moments_(moments) {
    on_stencil_ = f_.on_stencil[o];
    level_ = f_.level[o];
    count_ = on_stencil_ ? f_.levels[level_].size() : f_.offsets[o + 1] - f_.offsets[o];
    first_ = on_stencil_ ? 0 : f_.offsets[o];
    // A listed earlier bond takes o's table under i's horizon (the route of
    // the earlier set's bond for the later particle's horizon).
    table_level_ = on_stencil_ ? Families::no_level : table_level(f_, moments, o, horizon);
    // Both tables the same: spacing and horizon of o's level and of i's.
    if (own_level != Families::no_level && level_ != Families::no_level)
      same_table_ = f_.levels[level_].spacing == later.levels[own_level].spacing &&
                    f_.levels[level_].horizon == later.levels[own_level].horizon;
  }
  std::size_t size() const { return count_; }
  // Bond k's earlier weight if it has the later bond's route (`table`: the
  // later bond takes its table; `phi`: its partial volume), else nullptr.
  const double* same_route(std::size_t k, bool table, double phi) const {
    if (on_stencil_) {
      // A stencil bond's weight is its level's table entry (distance
      // moments); a partial-volume stencil weight is formed from the cell
      // steps, not the positions, and is never taken over.
      return moments_ && table && same_table_ ? &w_.stencil[level_][k] : nullptr;
    }
    const auto b = first_ + k;
    if (!moments_) return phi == f_.partial_volume[b] ? &w_.listed[b] : nullptr;
    const bool earlier_table = table_level_ != Families::no_level && f_.level[f_.neighbors[b]] == table_level_;
    const bool same = table == earlier_table && (!table || same_table_);
    return same ? &w_.listed[b] : nullptr;
  }
  // Whether every bond of the row has the later bond's route, when no
  // neighbour changed its level between the sets (`levels_kept`): a listed
  // earlier row whose own table route is the later particle's, and whose
  // table, if any, is the same. Then each bond's table route is the same
  // test (the neighbour's level against the same level) in both sets, and
  // same_route would hand every earlier weight over.
  bool whole_row_same(bool levels_kept, std::uint8_t own_level) const {
    if (!moments_ || !levels_kept || on_stencil_ || table_level_ != own_level) return false;
    return own_level == Families::no_level || same_table_;
  }
  std::uint64_t first() const { return first_; }

private:
  const Families& f_;
  const PerBond<double>& w_;
  bool moments_;
  bool on_stencil_ = false, same_table_ = false;
  std::uint8_t level_ = Families::no_level, table_level_ = Families::no_level;
  std::size_t count_ = 0;
  std::uint64_t first_ = 0;
};

}  // namespace

PerBond<double> bond_energy_weights(const ParticleSet& p, const Families& families, BondWeights weights,
                                    const EarlierBondWeights* earlier, std::size_t* computed,
                                    CellDiskMemo* memo) {
  PerBond<double> e;
  // Not zeroed: the loop below writes every listed bond's weight (a stencil
  // particle's row is empty), copied, taken over or computed.
  e.listed.resize(families.neighbors.size());
  const std::int64_t n = static_cast<std::int64_t>(p.size());
  // Between two whole squares the distance moment comes from a per-offset
  // table (97-99 % of an NB-NUG grid's bonds; it removes most of the
  // set-up's trigonometry). The table is exact too: the same integral, about
  // the offset's exact position. One table per resolution level.
  const bool moments = weights == BondWeights::distance_moment;
  std::vector<SquareMomentTable> tables;
  for (const auto& level : families.levels)
    tables.emplace_back(level.spacing, level.horizon > 0 ? level.horizon : p.horizon_nominal, memo);
  // The stencils: whole squares at whole cell steps.
  e.stencil.resize(families.levels.size());
  for (std::size_t l = 0; l < families.levels.size(); ++l) {
    const StencilLevel& level = families.levels[l];
    const double dx = level.spacing;
    for (std::size_t o = 0; o < level.size(); ++o) {
      const long di = level.di[o], dj = level.dj[o];
      e.stencil[l].push_back(moments ? tables[l](di, dj) : level.phi[o] * dx * dx * std::hypot(di * dx, dj * dx));
    }
  }
  // Whether every particle the sets share has the level it had (its square
  // on the same level's lattice): then a bond's table route changes only
  // with its own particle's (EarlierRow::whole_row_same).
  bool levels_kept = false;
  if (earlier && earlier->origin.size() == p.size()) {
    levels_kept = true;
    for (std::size_t i = 0; i < p.size() && levels_kept; ++i) {
      const std::uint32_t o = earlier->origin[i];
      levels_kept = o == Families::none || families.level[i] == earlier->families->level[o];
    }
  }
  std::size_t computed_bonds = 0;
  // The moments computed here that the memo lacks, gathered per thread and
  // added to it after the loop (the memo is only read inside it).
  CellDiskMemo::Found new_moments;
#pragma omp parallel reduction(+ : computed_bonds)
  {
    CellDiskMemo::Found found_here;
#pragma omp for schedule(dynamic, 256) nowait
    for (std::int64_t i = 0; i < n; ++i) {
      const auto particle = static_cast<std::size_t>(i);
      if (families.on_stencil[particle]) continue;
      const Vec2 xi{p.x[i], p.y[i]};
      const double horizon = p.horizon[particle];
      const std::uint8_t own_level = table_level(families, moments, particle, horizon);
      const std::uint32_t o = earlier ? earlier->same_family[particle] : Families::none;
      const auto first_bond = families.offsets[i];
      std::optional<EarlierRow> before;
      if (o != Families::none) before.emplace(*earlier, o, moments, horizon, families, own_level);
      const bool take_over = before && before->size() == families.offsets[i + 1] - first_bond;
      if (take_over && before->whole_row_same(levels_kept, own_level)) {
        const auto from = earlier->weights->listed.begin() + static_cast<std::ptrdiff_t>(before->first());
        std::copy(from, from + static_cast<std::ptrdiff_t>(before->size()),
                  e.listed.begin() + static_cast<std::ptrdiff_t>(first_bond));
        continue;
      }
      for (auto b = first_bond; b < families.offsets[i + 1]; ++b) {
        const auto j = families.neighbors[b];
        const bool table = own_level != Families::no_level && families.level[j] == own_level;
        if (take_over) {
          if (const double* w = before->same_route(b - first_bond, table, families.partial_volume[b])) {
            e.listed[b] = *w;
            continue;
          }
        }
        ++computed_bonds;
        if (!moments) {
          e.listed[b] = families.partial_volume[b] * p.volume[j] * std::hypot(p.x[j] - xi.x, p.y[j] - xi.y);
          continue;
        }
        if (table) {
          const std::uint8_t l = own_level;
          const double dx = families.levels[l].spacing;
          // Whole cell steps up to round-off: any rounding gives the same step.
          const auto di = static_cast<long>(std::nearbyint((p.x[j] - xi.x) / dx));
          const auto dj = static_cast<long>(std::nearbyint((p.y[j] - xi.y) / dx));
          if (tables[l].covers(di, dj)) {
            e.listed[b] = tables[l](di, dj);
            continue;
          }
        }
        const auto first = p.cell_offsets[j], count = p.cell_offsets[j + 1] - first;
        const double* vx = p.cell_vx.data() + first;
        const double* vy = p.cell_vy.data() + first;
        const double polygon_area = std::fabs(polygon_signed_area(vx, vy, count));
        // Looked up by the polygon computation's own inputs (its vertices
        // relative to the centre, polygon_disk_distance_moment), computed
        // at one call site either way.
        const bool memoised = memo && count == 4;
        CellDiskMemo::Key key;
        const double* known = nullptr;
        if (memoised) {
          key = CellDiskMemo::key(vx, vy, xi, horizon);
          known = memo->find(key);
        }
        const double moment = known ? *known : polygon_disk_distance_moment(vx, vy, count, xi, horizon);
        if (memoised && !known) found_here.emplace_back(key, moment);
        e.listed[b] = moment * (p.volume[j] / polygon_area);
      }
    }
#pragma omp critical(bond_energy_weights_memo)
    new_moments.insert(new_moments.end(), found_here.begin(), found_here.end());
  }
  if (memo) memo->add(new_moments);
  if (computed) *computed = computed_bonds;
  return e;
}

}  // namespace pd
