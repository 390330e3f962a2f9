#include "bond_weights.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>

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
  phi_a = std::remainder(phi_a, 2 * M_PI);  // into (-pi, pi]; |phi_a| < pi/2 since a is on the line
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
    const double mid = 0.5 * (x0 + x1);
    if (p / std::cos(mid) < radius) integral += p * p * p / 3.0 * (sec_cubed_integral(x1) - sec_cubed_integral(x0));
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
  SquareMomentTable(double spacing, double horizon)
      : reach_(static_cast<long>(std::ceil(horizon / spacing)) + 1), width_(2 * reach_ + 1) {
    moment_.resize(static_cast<std::size_t>(width_ * width_));
    for (long dj = -reach_; dj <= reach_; ++dj)
      for (long di = -reach_; di <= reach_; ++di) {
        const double cx = di * spacing, cy = dj * spacing, h = 0.5 * spacing;
        const double vx[4] = {cx - h, cx + h, cx + h, cx - h}, vy[4] = {cy - h, cy - h, cy + h, cy + h};
        moment_[static_cast<std::size_t>((dj + reach_) * width_ + (di + reach_))] =
            polygon_disk_distance_moment(vx, vy, 4, Vec2{0, 0}, horizon);
      }
  }
  bool covers(long di, long dj) const { return std::labs(di) <= reach_ && std::labs(dj) <= reach_; }
  double operator()(long di, long dj) const {
    return moment_[static_cast<std::size_t>((dj + reach_) * width_ + (di + reach_))];
  }

private:
  long reach_, width_;
  std::vector<double> moment_;
};

// How the weight of a bond i -> j is computed: from the square table of a
// level (its spacing and horizon), when i is a square of a level whose
// horizon is its own and j a square of the same level, else from j's cell
// polygon. Two sets whose bond has the same route and the same geometry give
// the same weight bit for bit.
// (Partial-volume weights, phi_ij A_j |xi_ij|, have one route; `phi` is their phi_ij.)
struct WeightRoute {
  bool table = false;
  double spacing = 0, horizon = 0;
  double phi = 0;
  bool operator==(const WeightRoute& o) const {
    return table == o.table && spacing == o.spacing && horizon == o.horizon && phi == o.phi;
  }
};

WeightRoute weight_route(const Families& f, bool moments, std::size_t i, double horizon, std::uint32_t j, double phi) {
  if (!moments) return {false, 0, 0, phi};
  const std::uint8_t l = f.level[i];
  if (l == Families::no_level || f.levels[l].horizon != horizon || f.level[j] != l) return {};
  return {true, f.levels[l].spacing, f.levels[l].horizon};
}

}  // namespace

PerBond<double> bond_energy_weights(const ParticleSet& p, const Families& families, BondWeights weights,
                                    const EarlierBondWeights* earlier, std::size_t* computed) {
  PerBond<double> e;
  e.listed.resize(families.neighbors.size());
  const std::int64_t n = static_cast<std::int64_t>(p.size());
  // Between two whole squares the distance moment comes from a per-offset
  // table (97-99 % of an NB-NUG grid's bonds; it removes most of the
  // set-up's trigonometry). The table is exact too: the same integral, about
  // the offset's exact position. One table per resolution level.
  const bool moments = weights == BondWeights::distance_moment;
  std::vector<SquareMomentTable> tables;
  for (const auto& level : families.levels)
    tables.emplace_back(level.spacing, level.horizon > 0 ? level.horizon : p.horizon_nominal);
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
  std::size_t computed_bonds = 0;
#pragma omp parallel reduction(+ : computed_bonds)
  {
    // The earlier particle's bonds: route and weight, in family order.
    std::vector<WeightRoute> earlier_route;
    std::vector<double> earlier_weight;
#pragma omp for schedule(dynamic, 256)
    for (std::int64_t i = 0; i < n; ++i) {
      const auto particle = static_cast<std::size_t>(i);
      if (families.on_stencil[particle]) continue;
      const Vec2 xi{p.x[i], p.y[i]};
      const double horizon = p.horizon[particle];
      earlier_route.clear();
      earlier_weight.clear();
      const std::uint32_t o = earlier ? earlier->same_family[particle] : Families::none;
      if (o != Families::none) {
        const Families& f = *earlier->families;
        f.for_each_bond(o, [&](const BondRef& b) {
          // A stencil bond's weight is its level's table entry (distance
          // moments); a partial-volume stencil weight is formed from the cell
          // steps, not the positions, and is never taken over.
          const StencilLevel* level = b.on_stencil ? &f.levels[b.level] : nullptr;
          // A partial-volume weight also needs the same phi_ij (a family
          // made listed from a stencil holds the stencil's, not the file's).
          earlier_route.push_back(!level    ? weight_route(f, moments, o, horizon, b.neighbor, b.partial_volume)
                                  : moments ? WeightRoute{true, level->spacing, level->horizon}
                                            : WeightRoute{true, -1, -1});
          earlier_weight.push_back((*earlier->weights)(b));
        });
      }
      const auto first_bond = families.offsets[i];
      const bool take_over = o != Families::none && earlier_route.size() == families.offsets[i + 1] - first_bond;
      for (auto b = first_bond; b < families.offsets[i + 1]; ++b) {
        const auto j = families.neighbors[b];
        const WeightRoute route = weight_route(families, moments, particle, horizon, j, families.partial_volume[b]);
        if (take_over) {
          const std::size_t k = b - first_bond;
          if (earlier_route[k] == route) {
            e.listed[b] = earlier_weight[k];
            continue;
          }
        }
        ++computed_bonds;
        if (!moments) {
          e.listed[b] = families.partial_volume[b] * p.volume[j] * std::hypot(p.x[j] - xi.x, p.y[j] - xi.y);
          continue;
        }
        if (route.table) {
          const std::uint8_t l = families.level[particle];
          const double dx = families.levels[l].spacing;
          const long di = std::lround((p.x[j] - xi.x) / dx), dj = std::lround((p.y[j] - xi.y) / dx);
          if (tables[l].covers(di, dj)) {
            e.listed[b] = tables[l](di, dj);
            continue;
          }
        }
        const auto first = p.cell_offsets[j], count = p.cell_offsets[j + 1] - first;
        const double* vx = p.cell_vx.data() + first;
        const double* vy = p.cell_vy.data() + first;
        const double polygon_area = std::fabs(polygon_signed_area(vx, vy, count));
        e.listed[b] = polygon_disk_distance_moment(vx, vy, count, xi, horizon) * (p.volume[j] / polygon_area);
      }
    }
  }
  if (computed) *computed = computed_bonds;
  return e;
}

}  // namespace pd
