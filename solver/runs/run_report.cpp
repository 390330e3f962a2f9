#include "run_report.hpp"

#include "units.hpp"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <iomanip>
#include <iostream>
#include <ostream>
#include <sstream>

#include "atomic_file.hpp"
#include "error.hpp"
#include "json_text.hpp"
#include "material_scales.hpp"
#include "pd/version.hpp"
#include "peak_memory.hpp"
#include "results_format.hpp"
#include "units.hpp"

namespace pd::solver {

JsonObject& JsonObject::number(const std::string& key, double value) {
  // Round-trip exact, as the plan and load_steps.csv write load factors: a
  // reader gets the double the run used (before 7 December 2026, 12 digits).
  fields_.emplace_back(key, json_number(value));
  return *this;
}

JsonObject& JsonObject::integer(const std::string& key, std::int64_t value) {
  fields_.emplace_back(key, std::to_string(value));
  return *this;
}

JsonObject& JsonObject::text(const std::string& key, const std::string& value) {
  fields_.emplace_back(key, json_string(value));
  return *this;
}

JsonObject& JsonObject::boolean(const std::string& key, bool value) {
  fields_.emplace_back(key, value ? "true" : "false");
  return *this;
}

JsonObject& JsonObject::texts(const std::string& key, const std::vector<std::string>& values) {
  std::string list = "[";
  for (std::size_t k = 0; k < values.size(); ++k) list += (k ? ", " : "") + json_string(values[k]);
  fields_.emplace_back(key, list + "]");
  return *this;
}

JsonObject& JsonObject::object(const std::string& key, const JsonObject& value) {
  fields_.emplace_back(key, value.str(true));
  return *this;
}

std::string JsonObject::str(bool one_line) const {
  std::string out = one_line ? "{" : "{\n";
  for (std::size_t k = 0; k < fields_.size(); ++k) {
    if (!one_line) out += "  ";
    out += json_string(fields_[k].first) + ": " + fields_[k].second;
    if (k + 1 < fields_.size()) out += one_line ? ", " : ",\n";
  }
  return out + (one_line ? "}" : "\n}\n");
}

namespace {

// How the OpenMP threads wait at a barrier, as the runtime read it at start:
// pd-solve sets OMP_WAIT_POLICY=passive unless the user set it or
// GOMP_SPINCOUNT (main.cpp). The runtime takes "active" and "passive" in any
// case, with spaces around; anything else leaves its default.
std::string thread_waiting() {
  const char* policy = std::getenv("OMP_WAIT_POLICY");
  const char* spins = std::getenv("GOMP_SPINCOUNT");
  std::string p = policy ? policy : "";
  std::string word;
  for (char c : p)
    if (!std::isspace(static_cast<unsigned char>(c))) word += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  const std::string setting = policy ? " (OMP_WAIT_POLICY=" + p + ")" : "";
  if (word == "passive") return "waiting threads sleep" + setting;
  if (word == "active") return "waiting threads spin" + setting;
  const std::string fallback = spins ? "waiting threads spin " + std::string(spins) + " polls, then sleep (GOMP_SPINCOUNT)"
                                     : "waiting threads spin a while, then sleep (the OpenMP runtime's default)";
  return fallback + (policy ? "; OMP_WAIT_POLICY=" + p + " is neither active nor passive" : "");
}

// A plate the pre-cracks cut apart runs, but a piece without a support or a
// load moves off freely, which is rarely what was meant (a crack drawn
// across the whole plate, or in the wrong unit): said before the first step.
// So is a particle set in pieces without cuts: a neck or a ligament of the
// geometry that the grid left without a particle (pd-mesh's uniform grid
// keeps whole cells only), or particles without a bond.
std::string pieces_warning(const SetupFacts& setup) {
  if (setup.pieces.count <= 1) return "";
  std::ostringstream w;
  const bool by_cuts = setup.pieces_without_cuts < setup.pieces.count;
  w << (by_cuts ? "the pre-cracks cut the plate into " : "the particle set falls into ") << setup.pieces.count
    << " pieces that no intact bond joins (the largest of ";
  for (std::size_t k = 0; k < setup.pieces.largest.size(); ++k)
    w << (k ? (k + 1 == setup.pieces.largest.size() ? " and " : ", ") : "") << setup.pieces.largest[k];
  w << " particles)";
  if (by_cuts) {
    if (setup.pieces_without_cuts > 1) w << "; without the cuts it has " << setup.pieces_without_cuts;
    w << ": check that each crack ends inside the plate (coordinates in m), with more than a spacing of "
         "ligament left beyond its tip";
  } else {
    w << ": the geometry is one piece, so the grid left a neck or a ligament without a particle, or particles "
         "without a bond (pd-mesh warns of both); a smaller spacing, or pd-mesh --grid nbnug, keeps them";
  }
  return w.str();
}

// A load's values in SI as the run uses them, and its time function: the
// plan shows what a value written in another unit became.
std::string load_values_text(const ResolvedLoad& load) {
  const char* unit = load.spec.kind == LoadKind::traction       ? "Pa"
                     : load.spec.kind == LoadKind::displacement ? "m"
                                                                : "m/s";
  std::ostringstream t;
  const auto component = [&](const char* name, bool given, const std::vector<double>& values) {
    if (!given) return;
    t << ", " << name;
    if (load.spec.kind == LoadKind::fixed) {
      t << " held";
      return;
    }
    if (values.empty()) return;
    const auto [low, high] = std::minmax_element(values.begin(), values.end());
    if (*low == *high) t << " = " << format_number(*low) << " " << unit;
    else t << " from " << format_number(*low) << " to " << format_number(*high) << " " << unit << " over the set";
  };
  component("x", load.spec.has_x, load.value_x);
  component("y", load.spec.has_y, load.value_y);
  const TimeFunction& f = load.spec.time_function;
  if (load.spec.kind == LoadKind::initial_velocity) t << " at t = 0";
  else if (f.kind == TimeFunction::Kind::ramp) t << ", ramped over " << format_number(f.ramp_time) << " s";
  else if (f.kind == TimeFunction::Kind::table && !f.table.empty())
    t << ", times a table of " << f.table.size() << " points from " << format_number(f.table.front().first)
      << " to " << format_number(f.table.back().first) << " s";
  return t.str();
}

// A time table written in another unit (us as s: [[0, 0], [200, 1]]) keeps
// its load near its first value through the run, as a ramp longer than the
// run does; a table of zeros, or one that starts after the run, as well.
std::vector<std::string> time_table_warnings(const Scene& scene, const std::vector<ResolvedLoad>& loads) {
  std::vector<std::string> warnings;
  const double end = scene.time.end;
  if (scene.quasi_static.enabled || !(end > 0)) return warnings;
  for (const auto& load : loads) {
    const TimeFunction& f = load.spec.time_function;
    if (f.kind != TimeFunction::Kind::table || f.table.empty() || load.spec.kind == LoadKind::initial_velocity ||
        load.spec.kind == LoadKind::fixed)
      continue;
    double largest = 0, largest_at = 0;
    for (const auto& [t, value] : f.table)
      if (std::fabs(value) > largest) largest = std::fabs(value), largest_at = t;
    double within = std::max(std::fabs(f(0.0)), std::fabs(f(end)));
    for (const auto& [t, value] : f.table)
      if (t >= 0 && t <= end) within = std::max(within, std::fabs(value));
    std::ostringstream w;
    w << "load '" << load.spec.name << "': ";
    if (largest == 0) {
      w << "its table's factors are all 0: the load has no effect";
    } else if (f.table.front().first >= end) {
      w << "its table starts at t = " << f.table.front().first << " s, after the run's end (time.end = " << end
        << " s): the load keeps the table's first factor, " << f.table.front().second
        << ", throughout; table times are in s (1 us = 1e-6)";
    } else if (within < 0.01 * largest) {
      w << "its table's largest factor (" << largest << ") comes at t = " << largest_at
        << " s, after the run's end (time.end = " << end << " s): within the run the load reaches "
        << 100 * within / largest << " % of it; table times are in s (1 us = 1e-6)";
    } else {
      continue;
    }
    warnings.push_back(w.str());
  }
  return warnings;
}

// The path a velocity load's set travels over [0, end] per m/s of its value:
// the integral of |f(t)|, exact for the piecewise-linear time functions
// (trapezoids between the ramp's or the table's corners).
double travel_per_unit_velocity(const TimeFunction& f, double end) {
  std::vector<double> corners = {0.0, end};
  if (f.kind == TimeFunction::Kind::ramp && f.ramp_time < end) corners.push_back(f.ramp_time);
  if (f.kind == TimeFunction::Kind::table)
    for (const auto& [t, value] : f.table)
      if (t > 0 && t < end) corners.push_back(t);
  std::sort(corners.begin(), corners.end());
  double travel = 0;
  for (std::size_t k = 1; k < corners.size(); ++k)
    travel += 0.5 * (std::fabs(f(corners[k - 1])) + std::fabs(f(corners[k]))) * (corners[k] - corners[k - 1]);
  return travel;
}

// A velocity in mm/s written as m/s (50 for 0.05) may stay below the wave
// speed's tenth that load_size_warnings holds it to, and still move its set
// by a good part of the plate over the run: a mean strain of 10 % or more,
// far past any brittle solid's failure.
std::vector<std::string> velocity_travel_warnings(const Scene& scene, const std::vector<ResolvedLoad>& loads) {
  std::vector<std::string> warnings;
  const double end = scene.time.end;
  if (!(end > 0)) return warnings;  // (a quasi-static scene has no velocity loads)
  for (const auto& load : loads) {
    if (load.spec.kind != LoadKind::velocity || !(load.plate_size > 0)) continue;
    const double travel = largest_load_value(load) * travel_per_unit_velocity(load.spec.time_function, end);
    if (!(travel > 0.1 * load.plate_size)) continue;
    std::ostringstream w;
    w << "load '" << load.spec.name << "': a velocity of up to " << largest_load_value(load)
      << " m/s moves its set by up to " << travel << " m over the run (time.end = " << end << " s), "
      << travel / load.plate_size << " times the plate's size (" << load.plate_size
      << " m): velocities are in m/s (1 mm/s = 1e-3)";
    warnings.push_back(w.str());
  }
  return warnings;
}

}  // namespace

std::vector<std::string> plan_warnings(const Scene& scene, const ProblemFacts& problem, std::size_t particle_count,
                                       const std::string& output_dir) {
  std::vector<std::string> warnings;
  // (`-o "run "` where the folder "run " exists: taken, the space unseen.)
  if (std::string w = white_space_name_warning(output_dir, "-o"); !w.empty()) warnings.push_back(std::move(w));
  // (The same for the particle file: particles = "plate.pdp " where that file exists.)
  if (std::string w = particles_white_space_check(scene); !w.empty()) warnings.push_back(std::move(w));
  for (auto& w : material_range_warnings(scene.material)) warnings.push_back(std::move(w));
  for (auto& w : load_warnings(problem.loads, scene.starts_from_equilibrium, particle_count))
    warnings.push_back(std::move(w));
  double load_factor = 1;  // (a dynamic run's loads are their values)
  if (scene.quasi_static.enabled) {
    if (std::string w = rigid_translation_warning(problem.loads); !w.empty()) warnings.push_back(std::move(w));
    // A separation stop that can never be met: it needs bonds that break and
    // a load cell, a displacement load that moves its set; before 7 December
    // 2026 the key was taken without a word. Supports alone (fixed loads,
    // displacements of 0) under tractions react with the tractions'
    // resultant at every equilibrium, which no breaking lowers (until 7
    // December 2026 a displacement of 0 passed for a load cell without a
    // word).
    const double fraction = scene.quasi_static.stop_reaction_fraction;
    const bool load_cell = std::any_of(problem.loads.begin(), problem.loads.end(), [](const ResolvedLoad& l) {
      return l.spec.kind == LoadKind::displacement && largest_load_value(l) > 0;
    });
    if (fraction > 0 && (!scene.effects.damage || !load_cell)) {
      std::ostringstream w;
      w << "quasi_static.stop_reaction_fraction = " << fraction << " has no effect: "
        << (!scene.effects.damage
                ? "with effects.damage = false no bond breaks, and the sample never separates; leave it out"
                : "it compares the reaction of the displacement loads that move their set (the load cell) with its "
                  "peak, and no load of type = \"displacement\" moves its set (the supports' reaction, fixed loads' "
                  "or displacements' of 0, balances the tractions at every equilibrium and does not fall as bonds "
                  "break); pull with a displacement load, or stop on damage with a [stop] region")
        << " (docs/scenes.md)";
      warnings.push_back(w.str());
    }
    for (const auto& w : scene.quasi_static.inert_keys) warnings.push_back(w);
    load_factor = 0;
    for (double f : scene.quasi_static.load_factors) load_factor = std::max(load_factor, std::fabs(f));
  }
  for (auto& w : load_size_warnings(scene.material, problem.loads, load_factor)) warnings.push_back(std::move(w));
  if (std::string w = pieces_warning(problem.setup); !w.empty()) warnings.push_back(std::move(w));
  // A ramp longer than the run (a time in ms written as s): the load never
  // reaches its value, and nothing else would show it.
  if (scene.time.end > 0)
    for (const auto& load : problem.loads) {
      const TimeFunction& f = load.spec.time_function;
      if (f.kind != TimeFunction::Kind::ramp || f.ramp_time <= scene.time.end ||
          load.spec.kind == LoadKind::initial_velocity || load.spec.kind == LoadKind::fixed)
        continue;
      std::ostringstream w;
      w << "load '" << load.spec.name << "' ramps to its value over ramp_time = " << f.ramp_time
        << " s, longer than the run (time.end = " << scene.time.end << " s): it reaches "
        << 100 * scene.time.end / f.ramp_time << " % of it; times are in s, or with a unit (\"200 us\")";
      warnings.push_back(w.str());
    }
  for (auto& w : time_table_warnings(scene, problem.loads)) warnings.push_back(std::move(w));
  for (auto& w : velocity_travel_warnings(scene, problem.loads)) warnings.push_back(std::move(w));
  if (!scene.quasi_static.enabled)
    for (const auto& load : problem.loads) {
      // A displacement whose time function is not 0 at t = 0 is imposed in
      // full by the first step: the set jumps there, an impact at u / dt
      // that tears it off the plate. (After a quasi-static part a strip is
      // held where that part left it: not a jump.)
      const double at_start = load.spec.time_function(0.0);
      if (load.spec.kind != LoadKind::displacement || at_start == 0 || largest_load_value(load) == 0) continue;
      std::ostringstream w;
      w << "load '" << load.spec.name << "' prescribes a displacement of up to "
        << largest_load_value(load) * std::fabs(at_start) << " m from the first step on: its set jumps there in one "
        << "time step (an impact at displacement / dt); ramp it (ramp_time, or a table from 0) or load with a "
        << "velocity";
      warnings.push_back(w.str());
    }
  // Brittle solids break at strains of 1e-3 to a few 1e-2: a critical
  // stretch above 0.1 most likely comes from E or G0 in another unit
  // ("3.24 MPa" for GPa is within the believable range of moduli).
  if (scene.effects.damage && problem.model.critical_stretch > 0.1) {
    std::ostringstream w;
    w << "the critical stretch s0 = " << problem.model.critical_stretch << ": bonds stretch by "
      << 100 * problem.model.critical_stretch << " % before they break; check youngs_modulus and fracture_energy "
      << "(and their units)";
    warnings.push_back(w.str());
  }
  // Keys about damage in a scene without it: they can never act (a scene
  // of a cracking run with --set effects.damage=false). Values other than the
  // defaults were written by the user.
  if (!scene.effects.damage) {
    if (scene.output.damage_thresholds != OutputSpec{}.damage_thresholds)
      warnings.push_back("output.damage_thresholds is set, but effects.damage = false: no bond breaks during the "
                         "run, so the arrival times show no crack growth");
    if (scene.refinement.enabled && scene.refinement.damage_threshold != RefinementSpec{}.damage_threshold)
      warnings.push_back("refinement.damage_threshold is set, but effects.damage = false: only the strain "
                         "criterion can split a particle");
  }
  warnings.insert(warnings.end(), problem.run_warnings.begin(), problem.run_warnings.end());
  return warnings;
}

void require_plan_written(std::ostream& log) {
  if (log.rdbuf() == nullptr) return;
  errno = 0;
  log.flush();
  const int error = errno;
  if (log) return;
  throw Error(std::string(&log == &std::cout ? "cannot write to standard output" : "cannot write the run's report") +
              (error != 0 ? std::string(": ") + std::strerror(error) : std::string(" (disk full?)")) +
              "; the run stops before its first step rather than run without its report");
}

void print_plan_header(std::ostream& log, const RunContext& run, const ProblemFacts& problem, const std::string& kind,
                       const std::string& particles_extra) {
  const Scene& scene = run.scene;
  const ModelSummary& model = problem.model;
  const SetupFacts& setup = problem.setup;
  log << "pd-solve " << version_string << " (" << kind << ")\n"
      << "  scene:     " << scene.path << "\n"
      << "  particles: " << scene.particle_file << " (" << run.particle_count << " particles, " << setup.bond_count
      << " directed bonds, spacing " << run.spacing << " m, "
      << (setup.horizon_mode == HorizonMode::uniform ? "horizon " : "largest horizon ") << model.horizon << " m"
      << particles_extra
      << ")\n"
      << "  material:  E " << scene.material.youngs_modulus << " Pa, rho "
      // (a quasi-static scene may leave the density out: it only sets the dynamic part's masses)
      << (scene.material.density > 0 ? format_number(scene.material.density) + " kg/m^3" : std::string("not given"))
      << ", G0 " << scene.material.fracture_energy << " J/m^2, thickness " << scene.material.thickness
      << " m, plane " << to_string(scene.material.plane)
      // As written (0.4999999999 is not the 0.5 a model refuses).
      << (scene.material.poisson_ratio > 0 ? ", nu " + shortest_text(scene.material.poisson_ratio) : std::string())
      << "\n"
      << "  model:     " << model.description << " (model Poisson ratio " << model.model_poisson_ratio << "), "
      << model.constants_text
      << (setup.horizon_mode == HorizonMode::uniform
              ? std::string()
              : std::string(" (of the largest horizon; each bond has its owner's, horizons ") +
                    to_string(setup.horizon_mode) + ", theory.md Sec. 6)")
      << ", bond weights " << to_string(scene.bond_weights) << "\n"
      << "  effects:   damage " << (scene.effects.damage ? "on" : "off") << ", surface correction "
      << (scene.effects.surface_correction
              ? std::string("on (") +
                    (setup.lambda_from_cache ? "from cache" : std::to_string(setup.lambda_iterations) + " iterations") +
                    ")"
              : std::string("off"))
      << ", pre-cracks " << scene.precracks.size() << " (" << setup.precrack_cut << " directed bonds cut)\n"
      << "  loads:     ";
  if (problem.loads.empty()) log << "none";
  for (const auto& load : problem.loads)
    log << "\n    " << load.spec.name << ": " << to_string(load.spec.kind) << " on " << load.spec.region.describe()
        << " (" << load.particles.size() << " particles)"
        << (load.spec.kind == LoadKind::traction ? ", edge length " + format_number(load.edge_length) + " m" : "")
        << load_values_text(load);
  log << "\n";
  std::ostream* echo = warning_echo(run);
  for (const auto& warning : plan_warnings(scene, problem, problem.particle_count ? problem.particle_count : run.particle_count,
                                            run.output_dir())) {
    log << "  warning:   " << warning << "\n";
    if (echo) *echo << "pd-solve: warning: " << warning << "\n";
  }
}

namespace {

// Whether stdout and stderr of the user's command go to one place (a
// terminal, 2>&1). On several processes each process's streams are pipes to
// the launcher (Open MPI's mpirun, a process of the name orterun, our
// parent where the processes run on its machine), which writes them where
// the user's streams go: then its own stdout and stderr are compared. Not
// known (another launcher, a remote machine): false, and warnings are echoed.
bool stdout_and_stderr_in_one_place(bool several_processes) {
  struct stat out{}, err{};
  if (!several_processes)
    return fstat(STDOUT_FILENO, &out) == 0 && fstat(STDERR_FILENO, &err) == 0 && out.st_dev == err.st_dev &&
           out.st_ino == err.st_ino;
  const std::string parent = "/proc/" + std::to_string(getppid());
  std::error_code error;
  const std::string launcher = std::filesystem::read_symlink(parent + "/exe", error).filename().string();
  if (error || (launcher != "orterun" && launcher != "mpirun" && launcher != "mpiexec")) return false;
  return stat((parent + "/fd/1").c_str(), &out) == 0 && stat((parent + "/fd/2").c_str(), &err) == 0 &&
         out.st_dev == err.st_dev && out.st_ino == err.st_ino;
}

}  // namespace

std::ostream* warning_echo(const RunContext& run) {
  if (run.options.log != nullptr) return nullptr;
  return stdout_and_stderr_in_one_place(run.processes > 1) ? nullptr : &std::cerr;
}

void print_plan_footer(std::ostream& log, const RunContext& run, const std::string& output_plan) {
  log << "  threads:   " << run.threads
      << (run.threads_by_size ? " (one per " + format_number(threads_by_size_bonds) +
                                    " directed bonds: a small plate runs faster so; --threads N to choose)"
                              : std::string())
      << (run.processes > 1 ? " per process, " + std::to_string(run.processes) + " processes (MPI)" : std::string())
      << (run.threads > 1 ? ", " + thread_waiting() : std::string()) << "\n"
      << "  output:    " << run.output_dir() << (output_plan.empty() ? "" : ": " + output_plan) << "\n";
  if (run.scene.stop.enabled)
    log << "  stop:      when damage >= " << run.scene.stop.damage << " in " << run.scene.stop.region.describe()
        << "\n";
  log << std::flush;
}

JsonObject summary_fields(const RunContext& run, const ProblemFacts& problem, const std::string& mode,
                          const std::string& stop_reason, double wall_seconds) {
  const Scene& scene = run.scene;
  const auto& m = scene.material;
  JsonObject material;
  material.number("youngs_modulus_Pa", m.youngs_modulus)
      .number("density_kg_m3", m.density)
      .number("fracture_energy_J_m2", m.fracture_energy)
      .number("thickness_m", m.thickness)
      .number("material_poisson_ratio", m.poisson_ratio)
      .number("model_poisson_ratio", problem.model.model_poisson_ratio);
  JsonObject constants;
  for (const auto& [name, value] : problem.model.constants) constants.number(name, value);
  constants.number("spacing_m", run.spacing);
  constants.text("horizons", to_string(problem.setup.horizon_mode));
  JsonObject effects;
  effects.boolean("damage", scene.effects.damage).boolean("surface_correction", scene.effects.surface_correction);
  JsonObject counts;
  counts.integer("particles", static_cast<std::int64_t>(problem.particle_count ? problem.particle_count : run.particle_count))
      .integer("directed_bonds", static_cast<std::int64_t>(problem.setup.bond_count))
      .integer("precrack_bonds_cut", static_cast<std::int64_t>(problem.setup.precrack_cut))
      .integer("loads", static_cast<std::int64_t>(problem.loads.size()));
  // Counted once per run on the whole plate (pieces_warning; on several processes too).
  if (problem.setup.pieces.count > 0)
    counts.integer("pieces", static_cast<std::int64_t>(problem.setup.pieces.count));
  JsonObject j;
  j.text("tool", std::string("pd-solve ") + version_string)
      .text("mode", mode)
      .text("scene", scene.path)
      .text("scene_text", scene.canonical_text)
      .text("particle_file", scene.particle_file)
      .text("particle_file_hash", run.particle_hash)
      .text("run_id", scene.run_id)
      .text("model", problem.model.name)
      .text("bond_weights", to_string(scene.bond_weights))
      .text("plane", to_string(m.plane))
      .object("material", material)
      .object("constants", constants)
      .object("effects", effects)
      .object("counts", counts)
      .text("stop_reason", stop_reason)
      .texts("warnings", plan_warnings(scene, problem, problem.particle_count ? problem.particle_count : run.particle_count,
                                            run.output_dir()))
      .integer("threads", run.threads)
      .text("omp_wait_policy", std::getenv("OMP_WAIT_POLICY") ? std::getenv("OMP_WAIT_POLICY") : "default")
      .integer("processes", run.processes)
      .number("wall_time_s", wall_seconds);
  return j;
}

void write_summary(const RunContext& run, JsonObject summary, std::uint64_t bond_count) {
  summary.integer("peak_memory_bytes", static_cast<std::int64_t>(peak_memory_bytes()))
      .number("peak_memory_bytes_per_directed_bond",
              bond_count > 0 ? static_cast<double>(peak_memory_bytes()) / static_cast<double>(bond_count) : 0.0);
  const std::string text = summary.str();
  write_atomically(run.path(results::summary_file), [&](std::ofstream& out) { out << text; });
}

std::string peak_memory_text(std::uint64_t bond_count) {
  std::ostringstream out;
  out << peak_memory_bytes() / (1024 * 1024) << " MB ("
      << static_cast<double>(peak_memory_bytes()) / static_cast<double>(std::max<std::uint64_t>(1, bond_count))
      << " bytes per directed bond)";
  return out.str();
}

}  // namespace pd::solver
