#include "fem_interpolation.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "error.hpp"

namespace pd::validation {

std::array<double, 6> FemInterpolator::shape_functions(double xi, double eta) {
  const double l1 = 1 - xi - eta, l2 = xi, l3 = eta;  // area coordinates of corners 0, 1, 2
  return {l1 * (2 * l1 - 1), l2 * (2 * l2 - 1), l3 * (2 * l3 - 1), 4 * l1 * l2, 4 * l2 * l3, 4 * l3 * l1};
}

std::array<std::array<double, 6>, 2> FemInterpolator::shape_derivatives(double xi, double eta) {
  const double l1 = 1 - xi - eta;
  return {{{-(4 * l1 - 1), 4 * xi - 1, 0, 4 * (l1 - xi), 4 * eta, -4 * eta},
           {-(4 * l1 - 1), 0, 4 * eta - 1, -4 * xi, 4 * xi, 4 * (l1 - eta)}}};
}

FemInterpolator::FemInterpolator(const FemMesh& mesh) : mesh_(mesh) {
  const auto [xmin, xmax] = std::minmax_element(mesh.x.begin(), mesh.x.end());
  const auto [ymin, ymax] = std::minmax_element(mesh.y.begin(), mesh.y.end());
  x0_ = *xmin;
  y0_ = *ymin;
  const double area = (*xmax - *xmin) * (*ymax - *ymin);
  cell_ = std::sqrt(area / std::max<std::size_t>(1, mesh.triangles.size())) * 2;
  nx_ = static_cast<long>((*xmax - *xmin) / cell_) + 1;
  ny_ = static_cast<long>((*ymax - *ymin) / cell_) + 1;
  buckets_.resize(static_cast<std::size_t>(nx_ * ny_));
  for (std::size_t e = 0; e < mesh.triangles.size(); ++e) {
    double bx0 = INFINITY, bx1 = -INFINITY, by0 = INFINITY, by1 = -INFINITY;
    for (auto n : mesh.triangles[e]) {
      bx0 = std::min(bx0, mesh.x[n]), bx1 = std::max(bx1, mesh.x[n]);
      by0 = std::min(by0, mesh.y[n]), by1 = std::max(by1, mesh.y[n]);
    }
    // A curved edge bulges slightly beyond its three nodes: grow the box by a little.
    const double grow = 0.05 * std::max(bx1 - bx0, by1 - by0);
    const long i0 = std::max(0L, static_cast<long>((bx0 - grow - x0_) / cell_));
    const long i1 = std::min(nx_ - 1, static_cast<long>((bx1 + grow - x0_) / cell_));
    const long j0 = std::max(0L, static_cast<long>((by0 - grow - y0_) / cell_));
    const long j1 = std::min(ny_ - 1, static_cast<long>((by1 + grow - y0_) / cell_));
    for (long j = j0; j <= j1; ++j)
      for (long i = i0; i <= i1; ++i) buckets_[static_cast<std::size_t>(j * nx_ + i)].push_back(static_cast<std::uint32_t>(e));
  }
}

FemInterpolator::Location FemInterpolator::locate(double x, double y) const {
  const long i = std::clamp(static_cast<long>((x - x0_) / cell_), 0L, nx_ - 1);
  const long j = std::clamp(static_cast<long>((y - y0_) / cell_), 0L, ny_ - 1);
  Location best;
  double best_outside = INFINITY;
  for (auto e : buckets_[static_cast<std::size_t>(j * nx_ + i)]) {
    const auto& t = mesh_.triangles[e];
    const auto px = [&](int k) { return mesh_.x[t[k]]; };
    const auto py = [&](int k) { return mesh_.y[t[k]]; };
    // Start from the straight triangle's barycentric coordinates.
    const double ax = px(1) - px(0), ay = py(1) - py(0), bx = px(2) - px(0), by = py(2) - py(0);
    const double det = ax * by - ay * bx;
    double xi = ((x - px(0)) * by - (y - py(0)) * bx) / det;
    double eta = (ax * (y - py(0)) - ay * (x - px(0))) / det;
    // Newton on x(xi, eta) = sum N_k x_k (isoparametric map).
    for (int it = 0; it < 12; ++it) {
      const auto [dxi, deta] = shape_derivatives(xi, eta);
      const auto n = shape_functions(xi, eta);
      double fx = -x, fy = -y, jxx = 0, jxy = 0, jyx = 0, jyy = 0;
      for (int k = 0; k < 6; ++k) {
        fx += n[k] * px(k);
        fy += n[k] * py(k);
        jxx += dxi[k] * px(k);
        jxy += deta[k] * px(k);
        jyx += dxi[k] * py(k);
        jyy += deta[k] * py(k);
      }
      const double d = jxx * jyy - jxy * jyx;
      const double step_xi = (fx * jyy - fy * jxy) / d, step_eta = (jxx * fy - jyx * fx) / d;
      xi -= step_xi;
      eta -= step_eta;
      if (std::fabs(step_xi) + std::fabs(step_eta) < 1e-14) break;
    }
    const double outside = std::max({0.0, -xi, -eta, xi + eta - 1});
    if (outside < best_outside) {
      best_outside = outside;
      best = {e, xi, eta};
    }
  }
  if (!(best_outside <= 1e-6)) {
    std::ostringstream m;
    m << "FEM interpolation: the point (" << x << ", " << y << ") m lies outside the FEM mesh";
    throw Error(m.str());
  }
  return best;
}

double FemInterpolator::value_at(const std::vector<double>& nodal, const Location& where) const {
  const auto n = shape_functions(where.xi, where.eta);
  const auto& t = mesh_.triangles[where.element];
  double v = 0;
  for (int k = 0; k < 6; ++k) v += n[k] * nodal[t[k]];
  return v;
}

std::array<double, 2> FemInterpolator::gradient_at(const std::vector<double>& nodal, const Location& where) const {
  const auto [dxi, deta] = shape_derivatives(where.xi, where.eta);
  const auto& t = mesh_.triangles[where.element];
  // Jacobian of (x, y) with respect to (xi, eta), and the field's derivatives in (xi, eta).
  double jxx = 0, jxy = 0, jyx = 0, jyy = 0, f_xi = 0, f_eta = 0;
  for (int k = 0; k < 6; ++k) {
    jxx += dxi[k] * mesh_.x[t[k]];
    jxy += deta[k] * mesh_.x[t[k]];
    jyx += dxi[k] * mesh_.y[t[k]];
    jyy += deta[k] * mesh_.y[t[k]];
    f_xi += dxi[k] * nodal[t[k]];
    f_eta += deta[k] * nodal[t[k]];
  }
  // (f_xi, f_eta) = J^T (f_x, f_y), J = [[jxx, jxy], [jyx, jyy]].
  const double d = jxx * jyy - jxy * jyx;
  return {(jyy * f_xi - jyx * f_eta) / d, (-jxy * f_xi + jxx * f_eta) / d};
}

double FemInterpolator::value(const std::vector<double>& nodal, double x, double y) const {
  return value_at(nodal, locate(x, y));
}

std::vector<double> FemInterpolator::values(const std::vector<double>& nodal, const std::vector<double>& x,
                                            const std::vector<double>& y) const {
  std::vector<double> out(x.size());
  for (std::size_t i = 0; i < x.size(); ++i) out[i] = value(nodal, x[i], y[i]);
  return out;
}

}  // namespace pd::validation
