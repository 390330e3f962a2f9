#include "quasi_static_problem.hpp"

#include <algorithm>
#include <cmath>

#include "energy_bonds.hpp"
#include "error.hpp"

namespace pd::solver {
namespace {

// Extension |xi + eta| - |xi| of bond b of i -> j in displacement form,
// e = (2 xi.eta + eta.eta) / (|xi + eta| + |xi|): free of the cancellation in
// |y| - |xi| when positions are large next to displacements (a 20 mm plate at
// strain 1e-5 would lose 9 of 16 digits). Both directions of a pair give the
// same value bit for bit. Also returns the current bond vector y and |y|.
struct BondExtension {
  double yx, yy, length, extension;
};
inline BondExtension bond_extension(const std::vector<double>& rx, const std::vector<double>& ry,
                                    const std::vector<double>& u, std::size_t n, std::size_t i, std::size_t j,
                                    double rest_length) {
  const double xix = rx[j] - rx[i], xiy = ry[j] - ry[i];
  const double etax = u[j] - u[i], etay = u[n + j] - u[n + i];
  BondExtension e;
  e.yx = xix + etax;
  e.yy = xiy + etay;
  e.length = std::sqrt(e.yx * e.yx + e.yy * e.yy);
  e.extension = (2 * (xix * etax + xiy * etay) + etax * etax + etay * etay) / (e.length + rest_length);
  return e;
}

}  // namespace

QuasiStaticProblem::QuasiStaticProblem(const Scene& scene, const ParticleSet& p, const SetupOptions& options)
    : QuasiStaticProblem(scene, p, compact_families(p), options) {}

QuasiStaticProblem::QuasiStaticProblem(const Scene& scene, ParticleSet p, Families families,
                                       const SetupOptions& options)
    : scene_(scene), thickness_(scene.material.thickness) {
  const std::size_t n = p.size();
  // The same bonds as the dynamic solver: weights, surface correction, pre-cracks.
  {
    const BondSetup setup = build_bond_setup(scene, p, std::move(families), options);
    facts_ = facts_of(setup);
    constants_ = Pmb::constants(scene.material, setup.horizon);
    model_ = Pmb::summary(constants_, scene.material.plane);
    const BondTable dynamic = bond_table<Pmb>(p, setup, constants_, /*with_damage=*/true);
    asymmetry_ = largest_stiffness_asymmetry(dynamic, p.volume);
    bonds_ = energy_bond_table(dynamic, p.x, p.y, p.volume);
  }
  // A pre-cut pair has no stiffness in either direction: it counts as broken.
  intact_.assign(bonds_.size(), 1);
  for (std::size_t b = 0; b < bonds_.size(); ++b)
    if (bonds_.stiffness[b] == 0) intact_[b] = 0;

  loads_ = resolve_loads(scene, p);
  state_ = state_at_rest(std::move(p), 0);
  reactions_.resize(loads_.size());
  free_.assign(2 * n, 1);
  body_x_.assign(n, 0.0);
  body_y_.assign(n, 0.0);
  for (const auto& load : loads_) {
    if (load.constrains_motion()) {
      for (auto i : load.particles) {
        if (load.spec.has_x) free_[i] = 0;
        if (load.spec.has_y) free_[n + i] = 0;
      }
    } else if (load.spec.kind == LoadKind::traction) {
      for (auto i : load.particles) {
        body_x_[i] += load.body_force_x;
        body_y_[i] += load.body_force_y;
      }
    }
  }
  // Jacobi preconditioner: the Hessian's diagonal of a bond is k (n n^T) at rest,
  // whose x and y parts sum to k; h A_i sum_j k_ij is the scale of both.
  diagonal_.assign(2 * n, 0.0);
  for (std::size_t i = 0; i < n; ++i) {
    double sum = 0;
    for (auto b = bonds_.offsets[i]; b < bonds_.offsets[i + 1]; ++b) sum += bonds_.stiffness[b];
    const double d = sum > 0 ? thickness_ * state_.area()[i] * sum : 1.0;
    diagonal_[i] = diagonal_[n + i] = d;
  }
  work_.fx.assign(n, 0.0);
  work_.fy.assign(n, 0.0);
}

void QuasiStaticProblem::set_load_factor(double factor, std::vector<double>& u) {
  const std::size_t n = particle_count();
  factor_ = factor;
  u.resize(2 * n, 0.0);
  for (const auto& load : loads_) {
    if (!load.constrains_motion()) continue;
    const bool fixed = load.spec.kind == LoadKind::fixed;
    for (auto i : load.particles) {
      if (load.spec.has_x) u[i] = fixed ? 0.0 : load.spec.x * factor;
      if (load.spec.has_y) u[n + i] = fixed ? 0.0 : load.spec.y * factor;
    }
  }
}

void QuasiStaticProblem::internal_force_density(const std::vector<double>& u) const {
  const std::int64_t n = static_cast<std::int64_t>(particle_count());
  const BondTable& t = bonds_;
#pragma omp parallel for schedule(static)
  for (std::int64_t i = 0; i < n; ++i) {
    double fx = 0, fy = 0;
    for (auto b = t.offsets[i]; b < t.offsets[i + 1]; ++b) {
      const auto e = bond_extension(state_.x0(), state_.y0(), u, n, i, t.neighbor[b], t.rest_length[b]);
      const double f = t.stiffness[b] * e.extension / e.length;
      fx += f * e.yx;
      fy += f * e.yy;
    }
    work_.fx[i] = fx;
    work_.fy[i] = fy;
  }
}

void QuasiStaticProblem::residual(const std::vector<double>& u, std::vector<double>& r) {
  const std::size_t n = particle_count();
  internal_force_density(u);
  r.resize(2 * n);
  double external = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const double scale = thickness_ * state_.area()[i];
    const double bx = factor_ * body_x_[i], by = factor_ * body_y_[i];
    const double fx = scale * (work_.fx[i] + bx), fy = scale * (work_.fy[i] + by);
    r[i] = free_[i] ? fx : 0.0;
    r[n + i] = free_[n + i] ? fy : 0.0;
    // The load the body carries: forces of the supports plus applied tractions.
    external += (free_[i] ? scale * scale * bx * bx : fx * fx) + (free_[n + i] ? scale * scale * by * by : fy * fy);
  }
  reaction_norm_ = std::sqrt(external);
  for (std::size_t l = 0; l < loads_.size(); ++l) {
    const auto& load = loads_[l];
    auto& res = reactions_[l];
    res = {};
    for (auto i : load.particles) {
      const double scale = thickness_ * state_.area()[i];
      if (load.constrains_motion()) {
        res.reaction_x -= scale * work_.fx[i];
        res.reaction_y -= scale * work_.fy[i];
      } else if (load.spec.kind == LoadKind::traction) {
        res.reaction_x += scale * factor_ * load.body_force_x;
        res.reaction_y += scale * factor_ * load.body_force_y;
      }
    }
  }
}

void QuasiStaticProblem::hessian_times(const std::vector<double>& u, const std::vector<double>& d,
                                       std::vector<double>& hd) const {
  const std::int64_t n = static_cast<std::int64_t>(particle_count());
  hd.resize(2 * n);
  const BondTable& t = bonds_;
#pragma omp parallel for schedule(static)
  for (std::int64_t i = 0; i < n; ++i) {
    // Change of f_i = sum_j k e n along d: with eta the relative position y_j - y_i,
    // L = |eta|, n = eta / L, e = L - |xi|:  d(e n) = (n.deta) n + (e / L)(deta - (n.deta) n).
    double gx = 0, gy = 0;
    for (auto b = t.offsets[i]; b < t.offsets[i + 1]; ++b) {
      const auto j = t.neighbor[b];
      const auto e = bond_extension(state_.x0(), state_.y0(), u, n, i, j, t.rest_length[b]);
      const double nx = e.yx / e.length, ny = e.yy / e.length;
      const double ddx = d[j] - d[i], ddy = d[n + j] - d[n + i];
      const double along = nx * ddx + ny * ddy;
      const double ratio = e.extension / e.length;
      gx += t.stiffness[b] * (along * nx + ratio * (ddx - along * nx));
      gy += t.stiffness[b] * (along * ny + ratio * (ddy - along * ny));
    }
    // The Hessian is minus the derivative of the force h A_i f_i.
    const double scale = thickness_ * state_.area()[i];
    hd[i] = free_[i] ? -scale * gx : 0.0;
    hd[n + i] = free_[n + i] ? -scale * gy : 0.0;
  }
}

double QuasiStaticProblem::strain_energy(const std::vector<double>& u) const {
  // h sum_i A_i W_i with W_i = 1/4 sum_j k_ij e_ij^2 (broken bonds have k = 0).
  const std::size_t n = particle_count();
  double total = 0;
  for (std::size_t i = 0; i < n; ++i) {
    double w = 0;
    for (auto b = bonds_.offsets[i]; b < bonds_.offsets[i + 1]; ++b) {
      const auto e = bond_extension(state_.x0(), state_.y0(), u, n, i, bonds_.neighbor[b], bonds_.rest_length[b]);
      w += bonds_.stiffness[b] * e.extension * e.extension;
    }
    total += thickness_ * state_.area()[i] * 0.25 * w;
  }
  return total;
}

double QuasiStaticProblem::energy(const std::vector<double>& u) const {
  const std::size_t n = particle_count();
  double work = 0;
  for (std::size_t i = 0; i < n; ++i)
    work += thickness_ * state_.area()[i] * factor_ * (body_x_[i] * u[i] + body_y_[i] * u[n + i]);
  return strain_energy(u) - work;
}

std::size_t QuasiStaticProblem::break_overstretched_bonds(const std::vector<double>& u) {
  const std::size_t n = particle_count();
  std::size_t broken = 0;
  for (std::size_t i = 0; i < n; ++i)
    for (auto b = bonds_.offsets[i]; b < bonds_.offsets[i + 1]; ++b) {
      if (!intact_[b]) continue;
      const auto j = bonds_.neighbor[b];
      // Both directions of a pair see the same extension, so a pair always breaks as a whole.
      const double extension = bond_extension(state_.x0(), state_.y0(), u, n, i, j, bonds_.rest_length[b]).extension;
      if (extension > bonds_.critical_stretch * bonds_.rest_length[b]) {
        intact_[b] = 0;
        bonds_.stiffness[b] = 0;
        if (i < j) ++broken;
      }
    }
  return broken;
}

std::size_t QuasiStaticProblem::broken_bond_count() const {
  std::size_t broken = 0;
  for (auto v : intact_) broken += v ? 0 : 1;
  return broken;
}

void QuasiStaticProblem::set_bond_states(const std::vector<std::uint8_t>& intact) {
  if (intact.size() != intact_.size()) throw Error("the saved bond states do not fit this particle set and scene");
  for (std::size_t b = 0; b < intact.size(); ++b)
    if (!intact[b]) {
      intact_[b] = 0;
      bonds_.stiffness[b] = 0;
    }
}

std::vector<std::pair<std::uint32_t, std::uint32_t>> QuasiStaticProblem::broken_pairs() const {
  // The energy table holds both directions of every pair, so i < j lists each pair once, in order.
  std::vector<std::pair<std::uint32_t, std::uint32_t>> pairs;
  for (std::size_t i = 0; i < particle_count(); ++i)
    for (auto b = bonds_.offsets[i]; b < bonds_.offsets[i + 1]; ++b)
      if (!intact_[b] && i < bonds_.neighbor[b]) pairs.emplace_back(static_cast<std::uint32_t>(i), bonds_.neighbor[b]);
  std::sort(pairs.begin(), pairs.end());
  return pairs;
}

std::vector<double> QuasiStaticProblem::damage() const {
  const std::size_t n = particle_count();
  std::vector<double> d(n, 0.0);
  if (!scene_.effects.damage && facts_.precrack_cut == 0) return d;
  for (std::size_t i = 0; i < n; ++i) {
    double intact_area = 0;
    for (auto b = bonds_.offsets[i]; b < bonds_.offsets[i + 1]; ++b)
      if (intact_[b]) intact_area += static_cast<double>(bonds_.damage_weight[b]);
    const double value = 1.0 - intact_area / bonds_.family_area[i];
    d[i] = value < 1e-9 ? 0.0 : value;
  }
  return d;
}

}  // namespace pd::solver
