#include "dual_horizon_statics.hpp"

#include <chrono>
#include <cmath>

#include "bond_setup.hpp"
#include "compact_families.hpp"
#include "error.hpp"
#include "pmb.hpp"
#include "variable_horizon_bonds.hpp"

namespace pd::validation {
namespace {

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// K u per particle [N/m of thickness]: minus the linearised internal force,
// sum over the row of V_i k n (n . (u_i - u_j)). Every bond is in two rows
// (its owner's and, as a dual entry, its neighbour's) with V_i k_own =
// V_j k_dual (variable_horizon_bonds.hpp), so K is symmetric.
void apply_stiffness(const solver::BondTable& t, const ParticleSet& p, const std::vector<double>& ux,
                     const std::vector<double>& uy, std::vector<double>& kx, std::vector<double>& ky) {
  const auto n = static_cast<std::int64_t>(p.size());
#pragma omp parallel for schedule(static)
  for (std::int64_t i = 0; i < n; ++i) {
    double fx = 0, fy = 0;
    for (auto b = t.offsets[i]; b < t.offsets[i + 1]; ++b) {
      const auto j = t.neighbor[b];
      const double ex = t.xi_x[b] / t.rest_length[b], ey = t.xi_y[b] / t.rest_length[b];
      const double stretch = ex * (ux[i] - ux[j]) + ey * (uy[i] - uy[j]);
      fx += t.stiffness[b] * stretch * ex;
      fy += t.stiffness[b] * stretch * ey;
    }
    kx[i] = p.volume[i] * fx;
    ky[i] = p.volume[i] * fy;
  }
}

}  // namespace

LinearStaticResult solve_dual_horizon_static(const solver::Scene& scene, const ParticleSet& p,
                                             const std::vector<PrescribedX>& prescribed, double tolerance,
                                             long max_iterations) {
  if (!scene.dual_horizon.value_or(false) || scene.model != solver::ModelType::pmb ||
      scene.effects.surface_correction || scene.quasi_static.enabled)
    throw Error(scene.path + ": the linear dual-horizon solution needs model.dual_horizon = true, PMB, no surface "
                "correction and no [quasi_static]");
  LinearStaticResult out;
  auto start = std::chrono::steady_clock::now();
  const solver::BondSetup setup = solver::build_bond_setup(scene, p, compact_families(p), {});
  const solver::BondTable table =
      solver::variable_horizon_table<solver::Pmb>(p, setup, scene.material, setup.horizon_mode, false, nullptr);
  const std::size_t n = p.size();
  for (std::size_t i = 0; i < n; ++i)
    for (auto b = table.offsets[i]; b < table.offsets[i + 1]; ++b)
      if (!std::isfinite(table.stiffness[b]) || !(table.rest_length[b] > 0))
        throw Error(scene.particle_file + ": bond " + std::to_string(i) + " -> " + std::to_string(table.neighbor[b]) +
                    " has stiffness " + std::to_string(table.stiffness[b]) + " N/m^4 and length " +
                    std::to_string(table.rest_length[b]) + " m");
  // Fixed x unknowns and their values.
  std::vector<std::uint8_t> fixed_x(n, 0);
  std::vector<double> ux(n, 0.0), uy(n, 0.0);
  for (const auto& c : prescribed) {
    const auto* set = p.find_set(c.set);
    if (!set) throw Error(scene.particle_file + ": no boundary set '" + c.set + "' to prescribe u_x on");
    for (auto i : set->particles) fixed_x[i] = 1, ux[i] = c.ux;
  }
  // Jacobi preconditioner: the diagonal of K.
  std::vector<double> dx(n, 0.0), dy(n, 0.0);
  for (std::size_t i = 0; i < n; ++i)
    for (auto b = table.offsets[i]; b < table.offsets[i + 1]; ++b) {
      const double ex = table.xi_x[b] / table.rest_length[b], ey = table.xi_y[b] / table.rest_length[b];
      dx[i] += p.volume[i] * table.stiffness[b] * ex * ex;
      dy[i] += p.volume[i] * table.stiffness[b] * ey * ey;
    }
  out.setup_seconds = seconds_since(start);

  start = std::chrono::steady_clock::now();
  // r = f - K u on the free unknowns (f = 0: loads are prescribed displacements only).
  std::vector<double> kx(n), ky(n), rx(n), ry(n), zx(n), zy(n), sx(n), sy(n);
  const auto residual = [&] {
    apply_stiffness(table, p, ux, uy, kx, ky);
    for (std::size_t i = 0; i < n; ++i) rx[i] = fixed_x[i] ? 0.0 : -kx[i], ry[i] = -ky[i];
  };
  const auto dot = [&](const std::vector<double>& ax, const std::vector<double>& ay, const std::vector<double>& bx,
                       const std::vector<double>& by) {
    double s = 0;
    for (std::size_t i = 0; i < n; ++i) s += ax[i] * bx[i] + ay[i] * by[i];
    return s;
  };
  residual();
  const double reference = std::sqrt(dot(rx, ry, rx, ry));  // |f - K u_prescribed|
  for (std::size_t i = 0; i < n; ++i) {
    zx[i] = dx[i] > 0 ? rx[i] / dx[i] : 0.0, zy[i] = dy[i] > 0 ? ry[i] / dy[i] : 0.0;
    sx[i] = zx[i], sy[i] = zy[i];
  }
  double rz = dot(rx, ry, zx, zy);
  std::vector<double> qx(n), qy(n);
  long k = 0;
  double norm = reference;
  for (; k < max_iterations && norm > tolerance * reference; ++k) {
    apply_stiffness(table, p, sx, sy, qx, qy);
    for (std::size_t i = 0; i < n; ++i)
      if (fixed_x[i]) qx[i] = 0.0;
    const double alpha = rz / dot(sx, sy, qx, qy);
    for (std::size_t i = 0; i < n; ++i) {
      ux[i] += alpha * sx[i], uy[i] += alpha * sy[i];
      rx[i] -= alpha * qx[i], ry[i] -= alpha * qy[i];
      zx[i] = dx[i] > 0 ? rx[i] / dx[i] : 0.0, zy[i] = dy[i] > 0 ? ry[i] / dy[i] : 0.0;
    }
    const double rz_next = dot(rx, ry, zx, zy);
    for (std::size_t i = 0; i < n; ++i) sx[i] = zx[i] + rz_next / rz * sx[i], sy[i] = zy[i] + rz_next / rz * sy[i];
    rz = rz_next;
    norm = std::sqrt(dot(rx, ry, rx, ry));
  }
  // The recurrence drifts from the true residual: report the true one.
  residual();
  out.relative_residual = reference > 0 ? std::sqrt(dot(rx, ry, rx, ry)) / reference : 0.0;
  out.converged = out.relative_residual <= 10 * tolerance;
  out.iterations = k;
  out.solve_seconds = seconds_since(start);
  // Constraint forces: what holds the prescribed unknowns, K u there.
  for (const auto& c : prescribed) {
    double sum = 0;
    for (auto i : p.find_set(c.set)->particles) sum += kx[i];
    out.reaction_x.push_back(sum);
  }
  out.ux = std::move(ux);
  out.uy = std::move(uy);
  return out;
}

}  // namespace pd::validation
