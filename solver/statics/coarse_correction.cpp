#include "coarse_correction.hpp"

#include <Eigen/Sparse>
#include <Eigen/SparseCholesky>
#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>
#include <utility>

#include "error.hpp"
#include "lattice_kernel.hpp"

namespace pd::solver {

struct CoarseCorrection::Factor {
  Eigen::SparseMatrix<double> matrix;  // A_c with its shift (undamped)
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt;
};

CoarseCorrection::CoarseCorrection(const std::vector<double>& x, const std::vector<double>& y, double square_side,
                                   std::vector<std::uint8_t> free, std::vector<double> scale)
    : particle_count_(x.size()), free_(std::move(free)), scale_(std::move(scale)),
      factor_(std::make_unique<Factor>()) {
  if (x.empty() || !(square_side > 0)) throw Error("coarse correction: no particles or no square side");
  const auto [x_low, x_high] = std::minmax_element(x.begin(), x.end());
  const auto [y_low, y_high] = std::minmax_element(y.begin(), y.end());
  const auto columns = static_cast<std::size_t>(std::floor((*x_high - *x_low) / square_side)) + 1;
  const auto rows = static_cast<std::size_t>(std::floor((*y_high - *y_low) / square_side)) + 1;
  square_.resize(particle_count_);
  dx_.resize(particle_count_);
  dy_.resize(particle_count_);
  for (std::size_t i = 0; i < particle_count_; ++i) {
    const auto column = std::min(columns - 1, static_cast<std::size_t>((x[i] - *x_low) / square_side));
    const auto row = std::min(rows - 1, static_cast<std::size_t>((y[i] - *y_low) / square_side));
    square_[i] = static_cast<std::uint32_t>(row * columns + column);
    // Rotation about the square's centre, scaled by its side: the three
    // motions then have values of the same order (a well-scaled A_c).
    dx_[i] = (x[i] - (*x_low + (static_cast<double>(column) + 0.5) * square_side)) / square_side;
    dy_[i] = (y[i] - (*y_low + (static_cast<double>(row) + 0.5) * square_side)) / square_side;
  }
}

CoarseCorrection::~CoarseCorrection() = default;

void CoarseCorrection::mode_at(std::size_t i, int mode, double& vx, double& vy) const {
  switch (mode) {
    case 0: vx = 1.0, vy = 0.0; break;
    case 1: vx = 0.0, vy = 1.0; break;
    default: vx = -dy_[i], vy = dx_[i]; break;  // an infinitesimal rotation
  }
  if (!free_[i] || !held_[i]) vx = 0.0;
  if (!free_[particle_count_ + i] || !held_[i]) vy = 0.0;
}

namespace {

// Union-find over the particles (path halving).
std::uint32_t root_of(std::vector<std::uint32_t>& parent, std::uint32_t i) {
  while (parent[i] != i) i = parent[i] = parent[parent[i]];
  return i;
}

}  // namespace

void CoarseCorrection::assemble(const LatticeKernel& bonds) {
  const std::size_t n = particle_count_;
  // 1. The aggregates: the particles of a square joined by the bonds that hold.
  std::vector<std::uint32_t> parent(n);
  std::iota(parent.begin(), parent.end(), 0u);
  bonds.for_each_intact_bond([&](std::uint32_t i, std::uint32_t j, double, double, double) {
    if (square_[i] != square_[j]) return;
    const auto a = root_of(parent, i), b = root_of(parent, j);
    if (a != b) parent[std::max(a, b)] = std::min(a, b);
  });
  // A body the cracks cut loose from every support (debris) has rigid
  // motions of no energy, and the forces on it sum to round-off only: its
  // particles take no part in the coarse motions (held_ = 0), which would
  // otherwise invert that round-off. Held: connected by bonds that hold to a
  // particle with a prescribed component.
  std::vector<std::uint32_t> body(n);
  std::iota(body.begin(), body.end(), 0u);
  bonds.for_each_intact_bond([&](std::uint32_t i, std::uint32_t j, double, double, double) {
    const auto a = root_of(body, i), b = root_of(body, j);
    if (a != b) body[std::max(a, b)] = std::min(a, b);
  });
  std::vector<std::uint8_t> body_held(n, 0);
  for (std::size_t i = 0; i < n; ++i)
    if (!free_[i] || !free_[n + i]) body_held[root_of(body, static_cast<std::uint32_t>(i))] = 1;
  held_.resize(n);
  for (std::size_t i = 0; i < n; ++i) held_[i] = body_held[root_of(body, static_cast<std::uint32_t>(i))];

  aggregate_.assign(n, 0);
  std::vector<std::uint32_t> number(n, UINT32_MAX);
  aggregate_count_ = 0;
  for (std::size_t i = 0; i < n; ++i) {
    auto& id = number[root_of(parent, static_cast<std::uint32_t>(i))];
    if (id == UINT32_MAX) id = static_cast<std::uint32_t>(aggregate_count_++);
    aggregate_[i] = id;
  }

  // 2. A_c = P^T K0 P. Row i of K0 u is h A_i sum_j k_ij n n^T (u_i - u_j)
  //    (QuasiStaticProblem::hessian_times), so the energy of a coarse motion
  //    P c is 1/2 sum over directed bonds of 1/2 h A_i k_ij (g.c)^2, with g
  //    the bond's row n^T (P_i - P_j): 3 entries at i's aggregate and 3 at j's.
  //    Each bond adds 1/2 h A_i k_ij g g^T, the two directions of a pair the
  //    pair's whole term (A_i k_ij = A_j k_ji, Sec. 4.7).
  using Block = std::array<double, 9>;
  std::vector<std::vector<std::pair<std::uint32_t, Block>>> rows(aggregate_count_);
  // Adds w u v^T to the block (a, b). (One block at a time: a new block may
  // move the others of its row.)
  const auto add = [&rows](std::uint32_t a, std::uint32_t b, double w, const std::array<double, 3>& u,
                           const std::array<double, 3>& v) {
    Block* values = nullptr;
    for (auto& [column, block] : rows[a])
      if (column == b) values = &block;
    if (!values) values = &rows[a].emplace_back(b, Block{}).second;
    for (int p = 0; p < 3; ++p)
      for (int q = 0; q < 3; ++q) (*values)[3 * p + q] += w * u[p] * v[q];
  };
  bonds.for_each_intact_bond([&](std::uint32_t i, std::uint32_t j, double k, double n_x, double n_y) {
    const double w = 0.5 * scale_[i] * k;
    std::array<double, 3> g_i, g_j;
    for (int m = 0; m < 3; ++m) {
      double vx, vy;
      mode_at(i, m, vx, vy);
      g_i[m] = n_x * vx + n_y * vy;
      mode_at(j, m, vx, vy);
      g_j[m] = -(n_x * vx + n_y * vy);
    }
    const auto a = aggregate_[i], b = aggregate_[j];
    if (a == b) {
      const std::array<double, 3> g{g_i[0] + g_j[0], g_i[1] + g_j[1], g_i[2] + g_j[2]};
      add(a, a, w, g, g);
      return;
    }
    add(a, a, w, g_i, g_i);
    add(a, b, w, g_i, g_j);
    add(b, a, w, g_j, g_i);
    add(b, b, w, g_j, g_j);
  });

  // 3. The factorisation. A coarse motion without energy (a fragment cut
  //    loose, an aggregate of one particle whose rotation is a translation,
  //    one of prescribed components only) makes A_c singular: a shift of
  //    1e-9 of the median diagonal entry keeps it defined, and P^T r is 0 (a
  //    fragment's forces sum to 0) or round-off there.
  const std::size_t coarse = coarse_unknown_count();
  std::vector<Eigen::Triplet<double>> entries;
  std::vector<double> diagonal;
  for (std::uint32_t a = 0; a < aggregate_count_; ++a)
    for (const auto& [b, values] : rows[a])
      for (int p = 0; p < 3; ++p)
        for (int q = 0; q < 3; ++q) {
          if (a == b && p == q && values[3 * p + q] > 0) diagonal.push_back(values[3 * p + q]);
          if (values[3 * p + q] != 0.0)
            entries.emplace_back(static_cast<int>(3 * a + p), static_cast<int>(3 * b + q), values[3 * p + q]);
        }
  double shift = 1.0;  // (no stiffness anywhere: any positive number)
  if (!diagonal.empty()) {
    const auto middle = diagonal.begin() + static_cast<std::ptrdiff_t>(diagonal.size() / 2);
    std::nth_element(diagonal.begin(), middle, diagonal.end());
    shift = 1e-9 * *middle;
  }
  for (std::size_t c = 0; c < coarse; ++c) entries.emplace_back(static_cast<int>(c), static_cast<int>(c), shift);
  auto& matrix = factor_->matrix;
  matrix.resize(static_cast<int>(coarse), static_cast<int>(coarse));
  matrix.setFromTriplets(entries.begin(), entries.end());
  factor_->ldlt.compute(matrix);
  if (factor_->ldlt.info() != Eigen::Success) throw Error("coarse correction: the coarse matrix could not be factorised");
}

void CoarseCorrection::set_damping(double mu, const std::vector<double>& diagonal, const std::vector<double>& coupling) {
  const std::size_t n = particle_count_;
  if (!(mu > 0)) {
    factor_->ldlt.compute(factor_->matrix);
  } else {
    // P^T B P is block diagonal over the aggregates (B acts within a
    // particle, and a particle's motions are its own aggregate's): per
    // particle, the 3 x 3 term V^T B_i V with V its 2 x 3 motions.
    std::vector<Eigen::Triplet<double>> entries;
    std::vector<double> blocks(9 * aggregate_count_, 0.0);
    for (std::size_t i = 0; i < n; ++i) {
      double vx[3], vy[3];
      for (int m = 0; m < 3; ++m) mode_at(i, m, vx[m], vy[m]);
      const double a = diagonal[i], c = coupling[i], b = diagonal[n + i];
      double* g = &blocks[9 * aggregate_[i]];
      for (int p = 0; p < 3; ++p)
        for (int q = 0; q < 3; ++q)
          g[3 * p + q] += vx[p] * (a * vx[q] + c * vy[q]) + vy[p] * (c * vx[q] + b * vy[q]);
    }
    for (std::size_t agg = 0; agg < aggregate_count_; ++agg)
      for (int p = 0; p < 3; ++p)
        for (int q = 0; q < 3; ++q)
          if (blocks[9 * agg + 3 * p + q] != 0.0)
            entries.emplace_back(static_cast<int>(3 * agg + p), static_cast<int>(3 * agg + q),
                                 mu * blocks[9 * agg + 3 * p + q]);
    Eigen::SparseMatrix<double> damping(factor_->matrix.rows(), factor_->matrix.cols());
    damping.setFromTriplets(entries.begin(), entries.end());
    const Eigen::SparseMatrix<double> damped = factor_->matrix + damping;
    factor_->ldlt.compute(damped);
  }
  if (factor_->ldlt.info() != Eigen::Success) throw Error("coarse correction: the coarse matrix could not be factorised");
}

void CoarseCorrection::add_correction(const std::vector<double>& r, std::vector<double>& s) const {
  const std::size_t n = particle_count_;
  Eigen::VectorXd restricted = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(coarse_unknown_count()));
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t a = aggregate_[i];
    for (int mode = 0; mode < 3; ++mode) {
      double vx, vy;
      mode_at(i, mode, vx, vy);
      restricted[static_cast<Eigen::Index>(3 * a + mode)] += vx * r[i] + vy * r[n + i];
    }
  }
  const Eigen::VectorXd coarse = factor_->ldlt.solve(restricted);
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t a = aggregate_[i];
    for (int mode = 0; mode < 3; ++mode) {
      double vx, vy;
      mode_at(i, mode, vx, vy);
      const double c = coarse[static_cast<Eigen::Index>(3 * a + mode)];
      s[i] += vx * c;
      s[n + i] += vy * c;
    }
  }
}

}  // namespace pd::solver
