#pragma once
// Loads resolved against a particle set: which particles each load acts on,
// the value each of them gets, and for tractions the equivalent body-force
// density (docs/scenes.md).
#include <cstdint>
#include <string>
#include <vector>

#include "particle_file.hpp"
#include "scene.hpp"

namespace pd::solver {

// Particles of a region: a named set of the particle file, "all", the
// particles whose centres lie in the closed box, or the particle nearest to a
// point. pd::Error names `key` and the scene file for an unknown set, an empty
// region, or a point farther than a cell from every particle.
std::vector<std::uint32_t> resolve_region(const RegionSpec& region, const ParticleSet& particles,
                                          const std::string& scene_path, const std::string& key);

// The most damaged particle of a region (ties: the smallest reference x,
// then y), for the stop condition's reason: a crack that reached the set, or
// one particle beside a loaded edge. damage < 0 for an empty region.
struct RegionPeak {
  double damage = -1;
  double x = 0, y = 0;  // reference position [m]
};
RegionPeak most_damaged(const std::vector<std::uint32_t>& region, const std::vector<double>& damage,
                        const std::vector<double>& x, const std::vector<double>& y);

// "stop condition: damage >= D in REGION (reached first at (x, y) mm, damage d)".
std::string stop_condition_reason(const StopSpec& stop, const RegionPeak& peak);

struct ResolvedLoad {
  LoadSpec spec;
  std::vector<std::uint32_t> particles;
  // The given components for particles[m] at f(t) = 1 (LoadSpec::x_at at the
  // particle's reference position: uniform, or varying linearly) [m/s, m or Pa].
  std::vector<double> value_x, value_y;
  // Traction only. The traction t [Pa] acts on an edge of length L [m]; it is
  // spread as a uniform body-force density b = t L / sum_{i in set} A_i [N/m^3]
  // over the set's particles, so the resultant b sum A_i h = t L h [N] is exact.
  double edge_length = 0;      // L [m]
  double set_extent = 0;       // [m] the larger side of the set's cells' bounding box (L when not given)
  double body_force_x = 0;     // b_x at f(t) = 1 [N/m^3]
  double body_force_y = 0;
  // The larger side of the bounding box of the particles the load was
  // resolved on [m]: the scale load_size_warnings holds displacements to.
  double plate_size = 0;
  bool constrains_motion() const {
    return spec.kind == LoadKind::velocity || spec.kind == LoadKind::displacement || spec.kind == LoadKind::fixed;
  }
};

// Per constrained or traction load: resultant of the internal forces on its
// particles.
struct LoadResultant {
  double reaction_x = 0, reaction_y = 0;  // [N]: minus the internal force resultant on the set
                                           // (= the applied resultant for a traction)
};

// The scene's loads on the particles. pd::Error (naming the scene file) when
// a region cannot be resolved, or when two loads constrain the same component
// of the same particles (a particle's component can follow one prescription
// only): the message names both loads and how many particles they share.
std::vector<ResolvedLoad> resolve_loads(const Scene& scene, const ParticleSet& particles);

// What is suspicious but runs: no load at all (the plate stays at rest; a
// switching scene's dynamic part, which `starts_from_equilibrium`, springs
// back from the quasi-static part's equilibrium with nothing holding it); a
// traction or an initial velocity on a component that another load
// constrains (the constraint wins; that part of the load has no effect), one
// line per pair of loads; constraints (velocity, displacement, fixed) that
// hold both components of every one of the `particle_count` particles (no
// particle is left to move by the equations of motion; 0: not looked for).
// For the run's plan.
std::vector<std::string> load_warnings(const std::vector<ResolvedLoad>& loads, bool starts_from_equilibrium,
                                       std::size_t particle_count = 0);

// Quasi-static loads: tractions whose resultant along x or y no load holds
// against (none prescribes that component of any particle), or whose moment
// nothing resists (the held components leave a turn about a point free: one
// particle held, or x held only at one height and y only at one abscissa),
// leave the plate without an equilibrium; it would move off or turn as a
// rigid body, and every minimisation would run to
// quasi_static.max_iterations. pd::Error naming the scene, the tractions, the
// component and the resultant, or the moment, the point and the loads that hold.
void check_tractions_held(const Scene& scene, const std::vector<ResolvedLoad>& loads, const ParticleSet& particles);

// The refusal of a [stop] condition that holds before the run's first step
// (`first`: "step" or "load step"), with `damage` there at the start from
// `from` (the pre-cracks, ...): the run would stop at once.
std::string stop_holds_at_start(const Scene& scene, double damage, const std::string& first, const std::string& from);

// Quasi-static loads: constraints (displacement, fixed) that prescribe one
// translation to every particle they hold, with no traction: the whole plate
// follows them rigidly and carries no load (strain energy 0 at every step; a
// support forgotten). A plan warning naming the loads, or empty.
std::string rigid_translation_warning(const std::vector<ResolvedLoad>& loads);

// The largest magnitude of a load's value over its set, at time factor 1
// (Pa, m/s or m by its kind).
double largest_load_value(const ResolvedLoad& load);

// A value of `load` (a component of one of its particles') that is not 0
// but that the quasi-static load factor `factor` scales, as the load step
// applies it (value x factor), to 0 or to a subnormal double (below
// std::numeric_limits<double>::min()): the arithmetic loses such a load, and
// the step would go on as if unloaded. 0 where none is (a factor of 0, or
// one that leaves every value a normal double, however small).
double value_lost_at_factor(const ResolvedLoad& load, double factor);

// A displacement load whose largest value, `largest` [m], is above a tenth of
// the plate's size (ResolvedLoad::plate_size): a mean strain of 10 % or more,
// far past any brittle solid's failure (load_size_warnings's rule).
bool beyond_plate(const ResolvedLoad& load, double largest);

// Load values that are most likely in another unit (scene values are SI and
// loads take no unit): a traction below 1e-8 E or above E (1 meant as MPa
// is 1 Pa), a velocity above a tenth of the wave speed sqrt(E / rho) (mm/s
// read as m/s), a displacement above a tenth of the plate's size (mm read as
// m). One line per load, for the run's plan; it runs as written.
// `load_factor`: the largest magnitude of a quasi-static run's load factors,
// by which its loads are scaled (1 for a dynamic run).
std::vector<std::string> load_size_warnings(const MaterialSpec& material, const std::vector<ResolvedLoad>& loads,
                                            double load_factor = 1);

// Default loaded edge length of a traction set: the longer side of the
// bounding box of the set's cells (centre +- cell_size / 2).
double set_edge_length(const ParticleSet& particles, const std::vector<std::uint32_t>& set);

}  // namespace pd::solver
