#include "quasi_static_problem.hpp"

#include <algorithm>
#include <cmath>

#include "deformed_bond.hpp"
#include "energy_bonds.hpp"
#include "error.hpp"
#include "lattice_double.hpp"
#include "lattice_sweep.hpp"
#include "lattice_tangent.hpp"
#include "model_registry.hpp"
#include "neighbor_kernel.hpp"
#include "state_energy_gradient.hpp"
#include "variable_horizon_bonds.hpp"

namespace pd::solver {
namespace {

// The bond of the energy table b of i -> j at the displacements u (x block, then y block).
// The same reference bond as the kernels (the table's).
inline DeformedBond<double> bond_at(const BondTable& t, const std::vector<double>& u, std::size_t i,
                                    std::uint64_t b) {
  const std::size_t n = t.particle_count, j = t.neighbor[b];
  return deformed_bond(static_cast<double>(t.xi_x[b]), static_cast<double>(t.xi_y[b]), t.rest_length[b],
                       u[j] - u[i], u[n + j] - u[n + i]);
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
    if (scene.model == ModelType::osb) {
      // OSB: the dynamic solver's constants, made into the energy table (both
      // directions of every pair, each end's own weights kept), on which the
      // residual is the exact gradient of sum_i A_i W_i (theory.md Sec. 5.6).
      state_based_ = true;
      broken_bond_in_dilatation_ =
          with_osb(scene.osb_failure, [](auto model) { return decltype(model)::broken_bond_in_dilatation; });
      osb_ = Osb::constants(scene.material, setup.horizon);
      model_ = with_osb(scene.osb_failure, [&](auto model) { return decltype(model)::summary(osb_, scene.material.plane); });
      BondTable dynamic = bond_table(p, setup, bond_constants_of<Osb>(p, setup, osb_), osb_.critical_stretch,
                                     /*with_damage=*/true);
      add_dilatation_weights(p, setup, dynamic);
      asymmetry_ = largest_stiffness_asymmetry(dynamic, p.volume);
      bonds_ = energy_bond_table(std::move(dynamic), p.x, p.y, p.volume);
      theta_.assign(n, 0.0);
      pressure_.assign(n, 0.0);
    } else if (scene.quasi_static.lattice_kernels) {
      constants_ = Model::constants(scene.material, setup.horizon);
      model_ = Model::summary(constants_, scene.material.plane);
      build_lattice(p, setup);
    } else {
      constants_ = Model::constants(scene.material, setup.horizon);
      model_ = Model::summary(constants_, scene.material.plane);
      // Dual horizons (no damage, horizon_mode.hpp): the energy of theory.md
      // Sec. 6.6, whose table is built the same way from each owner's bonds.
      BondTable dynamic = setup.horizon_mode == HorizonMode::dual_horizon
                              ? dual_horizon_energy_rows<Model>(p, setup, scene.material)
                              : bond_table(p, setup, bond_constants_of<Model>(p, setup, constants_),
                                           constants_.critical_stretch, /*with_damage=*/true);
      // The dual-horizon forces are this energy's gradient by construction
      // (every bond acts on both ends): nothing to report.
      asymmetry_ = setup.horizon_mode == HorizonMode::dual_horizon ? 0.0
                                                                   : largest_stiffness_asymmetry(dynamic, p.volume);
      bonds_ = energy_bond_table(std::move(dynamic), p.x, p.y, p.volume);
    }
  }
  // A pre-cut pair has no stiffness in either direction: it counts as broken.
  intact_.assign(bonds_.size(), 1);
  for (std::size_t b = 0; b < bonds_.size(); ++b)
    if (bonds_.stiffness[b] == 0) intact_[b] = 0;

  loads_ = resolve_loads(scene, p);
  check_tractions_held(scene, loads_, p);
  state_ = state_at_rest(std::move(p), 0);
  if (lattice_) {
    // The general particles' lists made energy-symmetric, once the set-up's
    // families and the cell polygons are gone (the peak of the set-up's
    // memory is here). The state's own displacements and forces are not
    // used (the problem keeps its own): they go first.
    state_.motion = Kinematics();
    lattice_->symmetrise_general_bonds(state_.reference);
  }
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
  // (Lattice kernels: build_lattice has set it from the bonds' constants.)
  if (!lattice_) diagonal_.assign(2 * n, 0.0);
  for (std::size_t i = 0; i < n && !lattice_; ++i) {
    double sum = 0;
    for (auto b = bonds_.offsets[i]; b < bonds_.offsets[i + 1]; ++b) sum += bonds_.stiffness[b];
    const double d = sum > 0 ? thickness_ * state_.area()[i] * sum : 1.0;
    diagonal_[i] = diagonal_[n + i] = d;
  }
  work_.fx.assign(n, 0.0);
  work_.fy.assign(n, 0.0);
  if (lattice_) {
    if (scene_.quasi_static.coarse_correction) {
      // Squares of two horizons (about 4 m^2 particles each, m = delta / dx).
      std::vector<double> scale(n);
      for (std::size_t i = 0; i < n; ++i) scale[i] = thickness_ * state_.area()[i];
      coarse_ = std::make_unique<CoarseCorrection>(state_.x0(), state_.y0(), 2.0 * model_.horizon, free_,
                                                   std::move(scale));
    }
    refresh_lattice_preconditioner();  // needs the free components
    refresh_lattice_damage();
  }
}

void QuasiStaticProblem::build_lattice(const ParticleSet& p, const BondSetup& setup) {
  // The dynamic solver's kernels as they are (force_field.cpp), with damage
  // on so that they keep bond states, held between breaking rounds; the
  // general particles' lists made energy-symmetric (energy_bonds.hpp). Nothing
  // per bond is stored for the lattice particles: memory as a dynamic run.
  const auto bond_constants = bond_constants_of<Model>(p, setup, constants_);
  LatticeModelSetup model;
  model.bond_constants = bond_constants;
  model.stiffness = [this](double energy_weight, double rest_length) {
    return Model::bond_stiffness(constants_, 1.0, energy_weight, rest_length);
  };
  model.critical_stretch = constants_.critical_stretch;
  model.general_pairs_in_float = false;  // the energy-symmetric double lists (symmetrise_general_bonds)
  // A plate without lattice squares (a free mesh) runs on the kernel's
  // general particles' lists alone: every product below is theirs then.
  model.general_lists_without_lattice = true;
  lattice_ = std::make_unique<LatticeKernel>(p, setup, model, /*with_damage=*/true);
  lattice_->hold_bond_states(true);
  lambda_ = setup.lambda;
  const std::size_t n = p.size();
  lattice_damage_.assign(n, 0.0);
  scratch_.assign(n, 0.0);
}

void QuasiStaticProblem::refresh_lattice_preconditioner() {
  // Block Jacobi: per particle M_i = h A_i sum_j k_ij n n^T over the bonds
  // that hold (the small-strain Hessian's diagonal block, theory.md
  // Sec. 4.12), recomputed after every breaking round. Where a crack cut a
  // particle's bonds across it, the block is stiff along the bonds left and
  // soft across them, which a scalar per particle cannot say.
  const std::size_t n = particle_count();
  std::vector<double> xx, xy, yy;
  lattice_->intact_stiffness_blocks(xx, xy, yy);
  diagonal_.resize(2 * n);
  coupling_.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const double scale = thickness_ * state_.area()[i];
    const double trace = xx[i] + yy[i];
    if (!(trace > 0)) {  // no bond holds it: any positive scale (its forces are 0)
      diagonal_[i] = diagonal_[n + i] = 1.0;
      coupling_[i] = 0;
      continue;
    }
    // A particle whose bonds all lie along one line has a singular block:
    // 1 % of the trace on the diagonal keeps it invertible (the order of the
    // geometric stiffness k e/|y| that holds such a particle sideways near
    // s0, e/|y| ~ 1e-2) and changes an intact particle's block by 1 %.
    const double floor = 1e-2 * trace;
    diagonal_[i] = scale * (xx[i] + floor);
    diagonal_[n + i] = scale * (yy[i] + floor);
    // A prescribed component takes no part: the free one is scaled alone.
    coupling_[i] = free_[i] && free_[n + i] ? scale * xy[i] : 0.0;
  }
  if (coarse_) {
    coarse_->assemble(*lattice_);  // the aggregates and A_c of the bonds that hold
    if (damping_ > 0) coarse_->set_damping(damping_, diagonal_, coupling_);
  }
}

void QuasiStaticProblem::set_lattice_damping(double mu) {
  if (!lattice_ || !(mu >= 0))
    throw Error(scene_.path + ": a damped round needs the lattice kernels and a damping >= 0");
  if (mu == damping_) return;
  damping_ = mu;
  if (coarse_) coarse_->set_damping(mu, diagonal_, coupling_);
}

void QuasiStaticProblem::precondition(const std::vector<double>& r, std::vector<double>& s) const {
  if (coupling_.empty()) {
    EnergyProblem::precondition(r, s);
    return;
  }
  const std::int64_t n = static_cast<std::int64_t>(particle_count());
  s.resize(r.size());
  // A damped round's blocks are (1 + mu) B (theory.md Sec. 4.14).
  const double inverse_damping = 1.0 / (1.0 + damping_);
  for (std::int64_t i = 0; i < n; ++i) {
    const double a = diagonal_[i], c = coupling_[i], b = diagonal_[n + i];
    const double inverse_det = inverse_damping / (a * b - c * c);  // > 0: c^2 <= xx yy < a b
    s[i] = (b * r[i] - c * r[n + i]) * inverse_det;
    s[n + i] = (a * r[n + i] - c * r[i]) * inverse_det;
  }
  if (coarse_) coarse_->add_correction(r, s);
}

void QuasiStaticProblem::lattice_force_density(Kinematics& k, bool in_double) const {
  k.fx.resize(particle_count());
  k.fy.resize(particle_count());
  if (in_double) lattice_->compute_in_double<Model>(k, lambda_, scratch_);
  else lattice_->compute<Model, DamageOn>(k, lattice_damage_);  // held: the states stay as they are
}

void QuasiStaticProblem::refresh_lattice_damage() {
  // The index follows the states only: any displacements do (held states).
  Kinematics rest;
  rest.ux.assign(particle_count(), 0.0);
  rest.uy.assign(particle_count(), 0.0);
  lattice_force_density(rest, false);
}

void QuasiStaticProblem::set_load_factor(double factor, std::vector<double>& u) {
  const std::size_t n = particle_count();
  factor_ = factor;
  u.resize(2 * n, 0.0);
  for (const auto& load : loads_) {
    if (!load.constrains_motion()) continue;
    const bool fixed = load.spec.kind == LoadKind::fixed;
    for (std::size_t m = 0; m < load.particles.size(); ++m) {
      const auto i = load.particles[m];
      if (load.spec.has_x) u[i] = fixed ? 0.0 : load.value_x[m] * factor;
      if (load.spec.has_y) u[n + i] = fixed ? 0.0 : load.value_y[m] * factor;
    }
  }
}

void QuasiStaticProblem::internal_force_density(const std::vector<double>& u) const {
  // The neighbour-list kernel of the dynamic solver on the energy table
  // (broken bonds have stiffness 0 there, so no bond states are needed).
  const std::size_t n = particle_count();
  work_.ux.assign(u.begin(), u.begin() + static_cast<std::ptrdiff_t>(n));
  work_.uy.assign(u.begin() + static_cast<std::ptrdiff_t>(n), u.end());
  if (state_based_) {
    state_force_density(work_);
    return;
  }
  if (lattice_) {
    lattice_force_density(work_, double_residual_);
    return;
  }
  compute_bond_forces<Model, DamageOff>(bonds_, work_, nullptr, nullptr, nullptr,
                                        static_cast<std::int64_t>(n));
}

void QuasiStaticProblem::state_force_density(Kinematics& k) const {
  // Minus the gradient of the OSB energy on the energy table, with the bond
  // states as they are: nothing breaks inside a minimisation. The pre-pass
  // (the dynamic solver's) sums every bond with a dilatation weight (cut_bond
  // takes it from a broken bond under variant (a)); the gradient reads the
  // states for variant (b) (theory.md Secs. 5.6, 5.8).
  k.fx.resize(particle_count());
  k.fy.resize(particle_count());
  compute_dilatation<Osb, DamageOff>(bonds_, k, nullptr, theta_.data(), pressure_.data());
  with_osb(scene_.osb_failure, [&](auto model) {
    compute_state_energy_forces<decltype(model)>(bonds_, k, intact_.data(), pressure_.data(),
                                                 Osb::dilatation_coefficient(osb_));
  });
}

void QuasiStaticProblem::cut_bond(std::size_t b) {
  intact_[b] = 0;
  bonds_.stiffness[b] = 0;
  if (!bonds_.energy_stiffness.empty()) bonds_.energy_stiffness[b] = 0;
  if (state_based_ && !broken_bond_in_dilatation_) bonds_.volume_over_length[b] = bonds_.partner_volume_over_length[b] = 0;
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
  if (lattice_ && lattice_hessian_ != LatticeHessian::central_difference) {
    double largest = 0;
    for (double v : d) largest = std::max(largest, std::fabs(v));
    if (largest == 0) {
      std::fill(hd.begin(), hd.end(), 0.0);
      return;
    }
    probe_.ux.resize(n);
    probe_.uy.resize(n);
    double s = 0;
    if (lattice_hessian_ == LatticeHessian::tangent) {
      // The tangent at u: the float sweep of Model::force_change along d / s,
      // scaled to a largest component of 1 (float range, no subnormals).
      s = largest;
      tangent_dx_.resize(n);
      tangent_dy_.resize(n);
      for (std::int64_t i = 0; i < n; ++i) {
        probe_.ux[i] = u[i];
        probe_.uy[i] = u[n + i];
        tangent_dx_[i] = d[i] / s;
        tangent_dy_[i] = d[n + i] / s;
      }
      lattice_->force_change<Model>(probe_, tangent_dx_, tangent_dy_);
    } else {
      // The small-strain Hessian K0: minus the force of the displacements s d
      // from rest, over s, with s such that the largest displacement is 1e-6
      // horizon (strains <= 4e-6 at m = 4: linear to that order; the sweep's
      // float arithmetic on these small differences adds ~1e-7). K0 differs
      // from the Hessian at u by the geometric terms and the rotation of the
      // bonds, of the order of the strain (theory.md Sec. 4.12).
      s = 1e-6 * model_.horizon / largest;
      for (std::int64_t i = 0; i < n; ++i) {
        probe_.ux[i] = s * d[i];
        probe_.uy[i] = s * d[n + i];
      }
      lattice_force_density(probe_, false);
      // (the result is the force of s d: divided by s below)
    }
    const double to_force = lattice_hessian_ == LatticeHessian::tangent ? s : 1.0 / s;
    for (std::int64_t i = 0; i < n; ++i) {
      const double scale = thickness_ * state_.area()[i] * to_force;
      hd[i] = free_[i] ? -scale * probe_.fx[i] : 0.0;
      hd[n + i] = free_[n + i] ? -scale * probe_.fy[i] : 0.0;
    }
    if (damping_ > 0)  // a damped round: + mu B d (theory.md Sec. 4.14)
      for (std::int64_t i = 0; i < n; ++i) {
        const double a = diagonal_[i], c = coupling_[i], b = diagonal_[n + i];
        if (free_[i]) hd[i] += damping_ * (a * d[i] + c * d[n + i]);
        if (free_[n + i]) hd[n + i] += damping_ * (c * d[i] + b * d[n + i]);
      }
    return;
  }
  if (state_based_ || lattice_) {
    // Lattice kernels with central differences (set_lattice_hessian): the same
    // central differences of the double-precision force.
    // OSB: the derivative of its exact energy gradient (theory.md Sec. 5.6),
    // taken by central differences with a step of 1e-6 horizon on the largest
    // component (truncation ~1e-12, rounding ~1e-16 |u| / step, both far
    // below the minimiser's tolerance).
    double largest = 0;
    for (double v : d) largest = std::max(largest, std::fabs(v));
    if (largest == 0) {
      std::fill(hd.begin(), hd.end(), 0.0);
      return;
    }
    const double step = 1e-6 * (state_based_ ? osb_.horizon : model_.horizon) / largest;
    const auto force_at = [&](double sign, std::vector<double>& fx, std::vector<double>& fy) {
      probe_.ux.resize(n);
      probe_.uy.resize(n);
      for (std::int64_t i = 0; i < n; ++i) {
        probe_.ux[i] = u[i] + sign * step * d[i];
        probe_.uy[i] = u[n + i] + sign * step * d[n + i];
      }
      if (state_based_) state_force_density(probe_);
      else lattice_force_density(probe_, true);
      fx = probe_.fx;
      fy = probe_.fy;
    };
    std::vector<double> px, py, mx, my;
    force_at(+1, px, py);
    force_at(-1, mx, my);
    for (std::int64_t i = 0; i < n; ++i) {
      const double scale = thickness_ * state_.area()[i] / (2 * step);
      hd[i] = free_[i] ? -scale * (px[i] - mx[i]) : 0.0;
      hd[n + i] = free_[n + i] ? -scale * (py[i] - my[i]) : 0.0;
    }
    return;
  }
  // The energy table: minus the change of h A_i f_i along d, the sum of
  // Model::force_change over the bonds (broken ones have stiffness 0).
  const double* ud = u.data();
  const double* dd = d.data();
  double* out = hd.data();
#pragma omp parallel
  bond_force_change_in_team<Model>(bonds_, ud, ud + n, dd, dd + n, nullptr, nullptr, n, out, out + n);
  for (std::int64_t i = 0; i < n; ++i) {
    const double scale = thickness_ * state_.area()[i];
    hd[i] = free_[i] ? -scale * hd[i] : 0.0;
    hd[n + i] = free_[n + i] ? -scale * hd[n + i] : 0.0;
  }
}

std::vector<double> QuasiStaticProblem::strain_energy_density(const std::vector<double>& u) const {
  // The model's energy density (broken bonds have k = 0 in the energy table).
  const std::size_t n = particle_count();
  Kinematics at_u;
  at_u.ux.assign(u.begin(), u.begin() + static_cast<std::ptrdiff_t>(n));
  at_u.uy.assign(u.begin() + static_cast<std::ptrdiff_t>(n), u.end());
  std::vector<double> w(n, 0.0);
  if (lattice_)
    lattice_->strain_energy_density<Model>(at_u, lambda_, w);
  else if (state_based_)
    with_osb(scene_.osb_failure, [&](auto model) {
      add_state_energy_density<decltype(model)>(bonds_, at_u, intact_.data(), Osb::dilatation_coefficient(osb_), w);
    });
  else
    add_bond_energy_density<Model>(bonds_, at_u, nullptr, w);
  return w;
}

double QuasiStaticProblem::strain_energy(const std::vector<double>& u) const {
  // h sum_i A_i W_i.
  const auto w = strain_energy_density(u);
  double total = 0;
  for (std::size_t i = 0; i < w.size(); ++i) total += thickness_ * state_.area()[i] * w[i];
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
  if (lattice_) {
    // The kernel's own rule, once, at u: every pair over s0 breaks (both
    // directions; float extension in the sweep, double in the lists).
    const std::size_t before = lattice_->broken_bond_count();
    work_.ux.assign(u.begin(), u.begin() + static_cast<std::ptrdiff_t>(n));
    work_.uy.assign(u.begin() + static_cast<std::ptrdiff_t>(n), u.end());
    lattice_->hold_bond_states(false);
    lattice_force_density(work_, false);
    lattice_->hold_bond_states(true);
    const std::size_t broken = (lattice_->broken_bond_count() - before) / 2;
    if (broken > 0) refresh_lattice_preconditioner();
    return broken;
  }
  std::size_t broken = 0;
  for (std::size_t i = 0; i < n; ++i)
    for (auto b = bonds_.offsets[i]; b < bonds_.offsets[i + 1]; ++b) {
      if (!intact_[b]) continue;
      const auto j = bonds_.neighbor[b];
      // Both directions of a pair see the same extension, so a pair always breaks as a whole.
      // (Osb::holds is the same criterion, theory.md Sec. 5.)
      if (!Model::holds(bonds_.critical_stretch * bonds_.rest_length[b], bond_at(bonds_, u, i, b))) {
        cut_bond(b);
        if (i < j) ++broken;
      }
    }
  return broken;
}

std::size_t QuasiStaticProblem::break_pairs(const std::vector<std::pair<std::uint32_t, std::uint32_t>>& pairs) {
  const std::size_t before = broken_bond_count();
  const auto not_a_bond = [&](std::uint32_t i, std::uint32_t j) {
    return Error(scene_.path + ": particles " + std::to_string(i) + " and " + std::to_string(j) + " are not bonded");
  };
  for (const auto& [i, j] : pairs) {
    if (i >= particle_count() || j >= particle_count()) throw not_a_bond(i, j);
    if (lattice_) {
      if (!lattice_->break_pair(i, j)) throw not_a_bond(i, j);
      continue;
    }
    bool found = false;
    for (auto [from, to] : {std::pair{i, j}, std::pair{j, i}})
      for (auto b = bonds_.offsets[from]; b < bonds_.offsets[from + 1]; ++b)
        if (bonds_.neighbor[b] == to) {
          cut_bond(b);
          found = true;
        }
    if (!found) throw not_a_bond(i, j);
  }
  if (lattice_) {
    refresh_lattice_damage();
    refresh_lattice_preconditioner();
  }
  return (broken_bond_count() - before) / 2;
}

std::size_t QuasiStaticProblem::broken_bond_count() const {
  if (lattice_) return lattice_->broken_bond_count();
  std::size_t broken = 0;
  for (auto v : intact_) broken += v ? 0 : 1;
  return broken;
}

void QuasiStaticProblem::set_bond_states(const std::vector<std::uint8_t>& intact) {
  if (lattice_) {
    lattice_->set_bond_states(intact);  // the kernel's layout (bond_states)
    refresh_lattice_damage();
    refresh_lattice_preconditioner();
    return;
  }
  if (intact.size() != intact_.size()) throw Error("the saved bond states do not fit this particle set and scene");
  for (std::size_t b = 0; b < intact.size(); ++b)
    if (!intact[b]) cut_bond(b);
}

const std::vector<std::uint8_t>& QuasiStaticProblem::bond_states() const {
  if (!lattice_) return intact_;
  lattice_->bond_states(lattice_states_);
  return lattice_states_;
}

std::vector<std::pair<std::uint32_t, std::uint32_t>> QuasiStaticProblem::broken_pairs() const {
  if (lattice_)
    throw Error(scene_.path + ": quasi_static.kernels = \"lattice\" does not list its broken pairs (use \"lists\")");
  // The energy table holds both directions of every pair, so i < j lists each pair once, in order.
  std::vector<std::pair<std::uint32_t, std::uint32_t>> pairs;
  for (std::size_t i = 0; i < particle_count(); ++i)
    for (auto b = bonds_.offsets[i]; b < bonds_.offsets[i + 1]; ++b)
      if (!intact_[b] && i < bonds_.neighbor[b]) pairs.emplace_back(static_cast<std::uint32_t>(i), bonds_.neighbor[b]);
  return pairs;
}

std::vector<double> QuasiStaticProblem::damage() const {
  const std::size_t n = particle_count();
  std::vector<double> d(n, 0.0);
  if (!scene_.effects.damage && facts_.precrack_cut == 0) return d;
  if (lattice_) return lattice_damage_;
  for (std::size_t i = 0; i < n; ++i) {
    double intact_area = 0;
    for (auto b = bonds_.offsets[i]; b < bonds_.offsets[i + 1]; ++b)
      if (intact_[b]) intact_area += static_cast<double>(bonds_.damage_weight[b]);
    d[i] = damage_index(intact_area, bonds_.family_area[i]);
  }
  return d;
}

}  // namespace pd::solver
