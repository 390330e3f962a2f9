#include "simulation.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "error.hpp"
#include "bond_setup.hpp"

namespace pd::solver {

Simulation::Simulation(const Scene& scene, const ParticleSet& p, const SimulationOptions& options)
    : Simulation(scene, p, compact_families(p), options) {}

Simulation::Simulation(const Scene& scene, const ParticleSet& p, Families families, const SimulationOptions& options)
    : scene_(scene), ref_x_(p.x), ref_y_(p.y), area_(p.volume) {
  const std::size_t n = p.size();
  density_ = scene.material.density;
  thickness_ = scene.material.thickness;
  {
    const bool damage = scene.effects.damage;
    auto run_bonds = build_run_bonds(scene, p, std::move(families), options.particle_file_hash,
                                     options.surface_correction_cache);
    pmb_ = run_bonds.pmb;
    lambda_iterations_ = run_bonds.lambda_iterations;
    lambda_from_cache_ = run_bonds.lambda_from_cache;
    precrack_cut_ = run_bonds.precrack_cut;
    bond_count_ = run_bonds.families.bond_count();
    stable_dt_ = pd::solver::stable_time_step(p, run_bonds, density_);
    if (options.lattice_kernel) {
      lattice_ = std::make_unique<LatticeKernel>(p, run_bonds, damage);
      if (lattice_->empty()) lattice_.reset();
      else lattice_compute_ = damage ? &LatticeKernel::compute<DamageOn> : &LatticeKernel::compute<DamageOff>;
    }
    if (!lattice_) {
      bonds_ = bond_table(p, run_bonds, damage, damage ? &damage_.intact : nullptr);
      kernel_ = damage ? &compute_internal_forces<DamageOn> : &compute_internal_forces<DamageOff>;
    }
    lambda_ = std::move(run_bonds.lambda);
    damage_.damage.assign(n, 0.0);
  }
  loads_ = resolve_loads(scene, p);
  resultants_.resize(loads_.size());

  if (scene.time.automatic) {
    dt_ = scene.time.safety * stable_dt_;
  } else {
    dt_ = scene.time.step;
    if (dt_ > stable_dt_ && !scene.time.force) {
      std::ostringstream m;
      m << scene.path << ": key 'time.step' = " << dt_ << " s is above the stable limit " << stable_dt_
        << " s of this particle set (theory.md Sec. 4); use a smaller step, step = \"auto\", "
           "or set time.force = true to run anyway";
      throw Error(m.str());
    }
  }

  k_.x = ref_x_;
  k_.y = ref_y_;
  k_.vx.assign(n, 0.0);
  k_.vy.assign(n, 0.0);
  k_.fx.assign(n, 0.0);
  k_.fy.assign(n, 0.0);
  for (const auto& load : loads_) {
    if (load.spec.kind != LoadKind::initial_velocity) continue;
    for (auto i : load.particles) {
      if (load.spec.has_x) k_.vx[i] = load.spec.x;
      if (load.spec.has_y) k_.vy[i] = load.spec.y;
    }
  }
  arrival_.assign(scene.output.damage_thresholds.size() * n, -1.0);
  compute_forces();
  apply_velocity_constraints(0.0, 0.0);
  if (scene.effects.damage) record_damage_arrivals();
}

void Simulation::compute_forces() {
  if (lattice_) {
    ((*lattice_).*lattice_compute_)(k_, ref_x_, ref_y_, damage_.damage);
  } else {
    kernel_(bonds_, k_, scene_.effects.damage ? &damage_ : nullptr);
  }
  for (std::size_t l = 0; l < loads_.size(); ++l) {
    const auto& load = loads_[l];
    auto& r = resultants_[l];
    r = {};
    if (load.constrains_motion()) {
      for (auto i : load.particles) {
        r.reaction_x -= k_.fx[i] * area_[i] * thickness_;
        r.reaction_y -= k_.fy[i] * area_[i] * thickness_;
      }
    } else if (load.spec.kind == LoadKind::traction) {
      const double f = load.spec.time_function(time_);
      double area = 0;
      for (auto i : load.particles) {
        k_.fx[i] += f * load.body_force_x;
        k_.fy[i] += f * load.body_force_y;
        area += area_[i];
      }
      r.reaction_x = f * load.body_force_x * area * thickness_;
      r.reaction_y = f * load.body_force_y * area * thickness_;
    }
  }
}

// Velocity of constrained components over the step from time_ to time_end; at
// time_half = time_end (end of a step) it sets the final velocities.
void Simulation::apply_velocity_constraints(double time_half, double time_end) {
  const double dt = time_end - time_;
  for (const auto& load : loads_) {
    const auto& s = load.spec;
    if (s.kind == LoadKind::velocity) {
      const double f = s.time_function(time_half);
      for (auto i : load.particles) {
        if (s.has_x) k_.vx[i] = s.x * f;
        if (s.has_y) k_.vy[i] = s.y * f;
      }
    } else if (s.kind == LoadKind::displacement || s.kind == LoadKind::fixed) {
      const double f = s.kind == LoadKind::fixed ? 0.0 : s.time_function(time_end);
      for (auto i : load.particles) {
        // The velocity that carries the particle to its prescribed place at time_end.
        if (dt > 0) {
          if (s.has_x) k_.vx[i] = (ref_x_[i] + s.x * f - k_.x[i]) / dt;
          if (s.has_y) k_.vy[i] = (ref_y_[i] + s.y * f - k_.y[i]) / dt;
        } else if (s.kind == LoadKind::fixed) {
          k_.vx[i] = k_.vy[i] = 0;
        }
      }
    }
  }
}

void Simulation::step() {
  const double dt = dt_, half = 0.5 * dt, inv_density = 1.0 / density_;
  const double t0 = time_, t1 = time_ + dt;
  const std::int64_t n = static_cast<std::int64_t>(particle_count());

  // Loaded particles at t_n, for the external work of this step.
  struct Before { double x, y, vx, vy, fx, fy; };
  std::vector<std::vector<Before>> before(loads_.size());
  for (std::size_t l = 0; l < loads_.size(); ++l)
    if (loads_[l].spec.kind != LoadKind::initial_velocity)
      for (auto i : loads_[l].particles)
        before[l].push_back({k_.x[i], k_.y[i], k_.vx[i], k_.vy[i], k_.fx[i], k_.fy[i]});

  // Half kick, then the constrained velocities over the step, then drift.
  Kinematics& k = k_;
#pragma omp parallel for schedule(static)
  for (std::int64_t i = 0; i < n; ++i) {
    k.vx[i] += half * k.fx[i] * inv_density;
    k.vy[i] += half * k.fy[i] * inv_density;
  }
  apply_velocity_constraints(t0 + half, t1);
#pragma omp parallel for schedule(static)
  for (std::int64_t i = 0; i < n; ++i) {
    k.x[i] += dt * k.vx[i];
    k.y[i] += dt * k.vy[i];
  }
  // Prescribed displacements land exactly (no round-off from the drift).
  for (const auto& load : loads_) {
    const auto& s = load.spec;
    if (s.kind != LoadKind::displacement && s.kind != LoadKind::fixed) continue;
    const double f = s.kind == LoadKind::fixed ? 0.0 : s.time_function(t1);
    for (auto i : load.particles) {
      if (s.has_x) k.x[i] = ref_x_[i] + s.x * f;
      if (s.has_y) k.y[i] = ref_y_[i] + s.y * f;
    }
  }

  time_ = t1;
  compute_forces();

  bool bad = false;
#pragma omp parallel for schedule(static) reduction(|| : bad)
  for (std::int64_t i = 0; i < n; ++i) {
    k.vx[i] += half * k.fx[i] * inv_density;
    k.vy[i] += half * k.fy[i] * inv_density;
    bad = bad || !std::isfinite(k.vx[i]) || !std::isfinite(k.vy[i]) || !std::isfinite(k.x[i]) ||
          !std::isfinite(k.y[i]);
  }
  // End-of-step velocities: prescribed ones at t1; displaced particles keep
  // the step's average velocity; fixed ones rest.
  for (std::size_t l = 0; l < loads_.size(); ++l) {
    const auto& load = loads_[l];
    const auto& s = load.spec;
    if (s.kind == LoadKind::velocity) {
      const double f = s.time_function(t1);
      for (auto i : load.particles) {
        if (s.has_x) k.vx[i] = s.x * f;
        if (s.has_y) k.vy[i] = s.y * f;
      }
    } else if (s.kind == LoadKind::displacement || s.kind == LoadKind::fixed) {
      for (std::size_t m = 0; m < load.particles.size(); ++m) {
        const auto i = load.particles[m];
        if (s.has_x) k.vx[i] = s.kind == LoadKind::fixed ? 0.0 : (k.x[i] - before[l][m].x) / dt;
        if (s.has_y) k.vy[i] = s.kind == LoadKind::fixed ? 0.0 : (k.y[i] - before[l][m].y) / dt;
      }
    }
  }

  // External work of this step (trapezoidal rule). A constraint does the work
  // that changes the kinetic energy of its particles minus the work of the
  // internal forces on them; a traction does b . du.
  for (std::size_t l = 0; l < loads_.size(); ++l) {
    const auto& load = loads_[l];
    const auto& s = load.spec;
    if (s.kind == LoadKind::initial_velocity) continue;
    double work = 0;
    for (std::size_t m = 0; m < load.particles.size(); ++m) {
      const auto i = load.particles[m];
      const Before& b = before[l][m];
      const double dux = k.x[i] - b.x, duy = k.y[i] - b.y;
      double w = 0;
      if (s.kind == LoadKind::traction) {
        const double f0 = s.time_function(t0), f1 = s.time_function(t1);
        w = 0.5 * (f0 + f1) * (load.body_force_x * dux + load.body_force_y * duy);
      } else {
        if (s.has_x) w += 0.5 * density_ * (k.vx[i] * k.vx[i] - b.vx * b.vx) - 0.5 * (b.fx + k.fx[i]) * dux;
        if (s.has_y) w += 0.5 * density_ * (k.vy[i] * k.vy[i] - b.vy * b.vy) - 0.5 * (b.fy + k.fy[i]) * duy;
      }
      work += w * area_[i] * thickness_;
    }
    external_work_ += work;
  }

  ++step_;
  if (scene_.effects.damage) record_damage_arrivals();

  if (bad) {
    for (std::int64_t i = 0; i < n; ++i) {
      const char* what = !std::isfinite(k.x[i]) || !std::isfinite(k.y[i]) ? "position"
                         : !std::isfinite(k.vx[i]) || !std::isfinite(k.vy[i]) ? "velocity" : nullptr;
      if (what) {
        non_finite_ = {true, static_cast<std::size_t>(i), what};
        break;
      }
    }
  }
}

void Simulation::record_damage_arrivals() {
  const auto& thresholds = scene_.output.damage_thresholds;
  const std::size_t n = particle_count();
  const std::int64_t count = static_cast<std::int64_t>(n);
  const double* damage = damage_.damage.data();
  double* arrival = arrival_.data();
#pragma omp parallel for schedule(static)
  for (std::int64_t i = 0; i < count; ++i) {
    if (damage[i] == 0.0) continue;  // most particles: one test
    for (std::size_t t = 0; t < thresholds.size(); ++t) {
      double& first = arrival[t * n + static_cast<std::size_t>(i)];
      if (first < 0 && damage[i] >= thresholds[t]) first = time_;
    }
  }
}

const std::vector<double>& Simulation::damage() const { return damage_.damage; }

std::size_t Simulation::broken_bond_count() const {
  if (!scene_.effects.damage) return precrack_cut_;
  if (lattice_) return lattice_->broken_bond_count();
  return static_cast<std::size_t>(std::count(damage_.intact.begin(), damage_.intact.end(), 0));
}

std::vector<double> Simulation::strain_energy_density() const {
  std::vector<double> w(particle_count(), 0.0);
  if (lattice_)
    lattice_->strain_energy_density(k_, ref_x_, ref_y_, lambda_, w);
  else
    compute_strain_energy_density(bonds_, k_, scene_.effects.damage ? damage_.intact.data() : nullptr, w);
  return w;
}

EnergyTotals Simulation::energies() const {
  EnergyTotals e;
  const auto w = strain_energy_density();
  // Serial sums: a fixed order, so restarted runs report identical numbers.
  for (std::size_t i = 0; i < particle_count(); ++i) {
    const double volume = area_[i] * thickness_;
    const double v2 = k_.vx[i] * k_.vx[i] + k_.vy[i] * k_.vy[i];
    const double a2 = (k_.fx[i] * k_.fx[i] + k_.fy[i] * k_.fy[i]) / (density_ * density_);
    e.kinetic += 0.5 * density_ * v2 * volume;
    e.kinetic_half_step += 0.5 * density_ * (v2 - 0.25 * dt_ * dt_ * a2) * volume;
    e.strain += w[i] * volume;
  }
  e.external_work = external_work_;
  return e;
}

std::vector<LoadResultant> Simulation::load_resultants() const { return resultants_; }

std::vector<double> Simulation::displacement_xyz() const {
  std::vector<double> u(3 * particle_count(), 0.0);
  for (std::size_t i = 0; i < particle_count(); ++i) {
    u[3 * i] = k_.x[i] - ref_x_[i];
    u[3 * i + 1] = k_.y[i] - ref_y_[i];
  }
  return u;
}

std::vector<double> Simulation::velocity_xyz() const {
  std::vector<double> v(3 * particle_count(), 0.0);
  for (std::size_t i = 0; i < particle_count(); ++i) {
    v[3 * i] = k_.vx[i];
    v[3 * i + 1] = k_.vy[i];
  }
  return v;
}

Simulation::State Simulation::save_state() const {
  State s;
  save_state(s);
  return s;
}

void Simulation::save_state(State& s) const {
  s.step = step_;
  s.time = time_;
  s.external_work = external_work_;
  s.kinematics.x = k_.x;  // (copy assignments reuse the vectors' storage)
  s.kinematics.y = k_.y;
  s.kinematics.vx = k_.vx;
  s.kinematics.vy = k_.vy;
  s.kinematics.fx = k_.fx;
  s.kinematics.fy = k_.fy;
  s.damage.damage = damage_.damage;
  if (lattice_ && scene_.effects.damage) lattice_->bond_states(s.damage.intact);
  else s.damage.intact = damage_.intact;
  s.arrival = arrival_;
}

void Simulation::restore_state(const State& s) {
  const std::size_t state_count = !scene_.effects.damage ? 0
                                  : lattice_              ? lattice_->bond_state_count()
                                                          : damage_.intact.size();
  if (s.kinematics.x.size() != particle_count() || s.arrival.size() != arrival_.size() ||
      s.damage.intact.size() != state_count || s.damage.damage.size() != particle_count())
    throw Error("the saved state does not fit this particle set and scene");
  step_ = s.step;
  time_ = s.time;
  external_work_ = s.external_work;
  k_ = s.kinematics;
  damage_.damage = s.damage.damage;
  if (lattice_) {
    if (scene_.effects.damage) lattice_->set_bond_states(s.damage.intact);
  } else {
    damage_.intact = s.damage.intact;
  }
  arrival_ = s.arrival;
  // Forces and resultants are functions of the positions and bond states;
  // recompute the load resultants (the kernel gives the same forces and
  // states, but the saved ones are kept bit for bit).
  const Kinematics saved = k_;
  const std::vector<double> saved_damage = damage_.damage;
  compute_forces();
  k_ = saved;
  damage_.damage = saved_damage;
  if (lattice_) {
    if (scene_.effects.damage) lattice_->set_bond_states(s.damage.intact);
  } else {
    damage_.intact = s.damage.intact;
  }
  non_finite_ = {};
}

void Simulation::break_pairs(const std::vector<std::pair<std::uint32_t, std::uint32_t>>& pairs) {
  if (!scene_.effects.damage) return;
  if (lattice_) {
    for (const auto& [i, j] : pairs) lattice_->break_pair(i, j);
    return;
  }
  // A pair is broken in whichever directions the bond table holds (on
  // non-uniform grids a pair may be there in one only).
  for (std::uint32_t i = 0; i < particle_count(); ++i)
    for (auto b = bonds_.offsets[i]; b < bonds_.offsets[i + 1]; ++b) {
      const std::uint32_t j = bonds_.neighbor[b];
      if (std::binary_search(pairs.begin(), pairs.end(), std::pair{std::min(i, j), std::max(i, j)}))
        damage_.intact[b] = 0;
    }
}

void Simulation::set_velocities(const std::vector<double>& vx, const std::vector<double>& vy) {
  k_.vx = vx;
  k_.vy = vy;
}

void Simulation::set_positions(const std::vector<double>& x, const std::vector<double>& y) {
  k_.x = x;
  k_.y = y;
  compute_forces();
}

}  // namespace pd::solver
