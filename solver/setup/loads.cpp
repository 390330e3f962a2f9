#include "loads.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numeric>
#include <optional>
#include <sstream>
#include <utility>

#include "error.hpp"
#include "units.hpp"

namespace pd::solver {
namespace {

// The particle whose centre is nearest to `point`. Ties (equal distances to
// within 1e-9 of the cell size, e.g. a point on a cell corner) go to the
// lowest, then the leftmost particle, whatever the particles' order.
std::uint32_t nearest_particle(const ParticleSet& p, Vec2 point, const std::string& where,
                               const std::string& key) {
  const auto distance = [&](std::size_t i) { return std::hypot(p.x[i] - point.x, p.y[i] - point.y); };
  std::size_t best = 0;
  for (std::size_t i = 1; i < p.size(); ++i)
    if (distance(i) < distance(best)) best = i;
  const double nearest = distance(best), tie = nearest + 1e-9 * p.cell_size[best];
  for (std::size_t i = 0; i < p.size(); ++i)
    if (distance(i) <= tie && (p.y[i] < p.y[best] || (p.y[i] == p.y[best] && p.x[i] < p.x[best]))) best = i;
  // A point farther than a cell from every particle lies outside the plate or
  // in a hole: most likely a mistake (e.g. millimetres for metres).
  if (nearest > p.cell_size[best]) {
    std::ostringstream m;
    m << where << ": key '" << key << ".nearest' = [" << point.x << ", " << point.y
      << "]: the nearest particle, at (" << p.x[best] << ", " << p.y[best] << ") m, is " << nearest
      << " m away, more than its cell size " << p.cell_size[best]
      << " m: the point lies outside the plate or in a hole (coordinates are in metres; the plate spans x in ["
      << p.xmin << ", " << p.xmax << "], y in [" << p.ymin << ", " << p.ymax << "] m)";
    throw Error(m.str());
  }
  return static_cast<std::uint32_t>(best);
}

// The key of the k-th load of a scene in messages: its place in the scene file.
std::string load_key(const LoadSpec& load, std::size_t k) {
  return "loads[" + std::to_string(load.file_index >= 0 ? static_cast<std::size_t>(load.file_index) : k) + "]";
}

// How a load is named in messages: by its name, else by its key.
std::string label(const std::vector<ResolvedLoad>& loads, std::size_t l) {
  const LoadSpec& s = loads[l].spec;
  return (s.name.empty() ? load_key(s, l) : "'" + s.name + "'") + " (" + to_string(s.kind) + " on " +
         s.region.describe() + ")";
}

// A component on which a load acts for particles that an earlier constraint
// already prescribes.
struct SharedComponent {
  std::size_t constraint = 0;  // the load that constrains the component first
  std::size_t other = 0;       // the load that acts on it too
  char component = 'x';
  std::size_t particles = 0;   // how many particles both act on
  std::uint32_t example = 0;   // one of them
};

// Which loads to look for on constrained components.
enum class Sharers { constraints, tractions_and_initial_velocities };

// Per component, which constraint owns each particle (the first one that
// constrains it), and the loads of the kind `sharers` given on the same
// component of owned particles.
std::vector<SharedComponent> shared_components(const std::vector<ResolvedLoad>& loads, Sharers sharers) {
  // Sized by the loads' own particles: they may index a refined set larger
  // than the particle file (a restarted adaptive run's plan).
  std::size_t particle_count = 0;
  for (const auto& load : loads)
    for (auto i : load.particles) particle_count = std::max<std::size_t>(particle_count, i + std::size_t{1});
  std::vector<SharedComponent> shared;
  for (const char component : {'x', 'y'}) {
    const auto given = [&](const ResolvedLoad& load) { return component == 'x' ? load.spec.has_x : load.spec.has_y; };
    std::vector<std::int64_t> owner(particle_count, -1);
    std::map<std::pair<std::size_t, std::size_t>, SharedComponent> pairs;
    const auto visit = [&](std::size_t l, bool claim) {
      for (auto i : loads[l].particles) {
        if (owner[i] == static_cast<std::int64_t>(l)) continue;
        if (owner[i] < 0) {
          if (claim) owner[i] = static_cast<std::int64_t>(l);
          continue;
        }
        const auto first = static_cast<std::size_t>(owner[i]);
        ++pairs.try_emplace({first, l}, SharedComponent{first, l, component, 0, i}).first->second.particles;
      }
    };
    for (std::size_t l = 0; l < loads.size(); ++l)
      if (loads[l].constrains_motion() && given(loads[l])) visit(l, true);
    if (sharers == Sharers::constraints) {
      for (auto& [key, s] : pairs) shared.push_back(s);
      continue;
    }
    pairs.clear();
    for (std::size_t l = 0; l < loads.size(); ++l)
      if (!loads[l].constrains_motion() && given(loads[l])) visit(l, false);
    for (auto& [key, s] : pairs) shared.push_back(s);
  }
  return shared;
}

}  // namespace

std::vector<std::uint32_t> resolve_region(const RegionSpec& region, const ParticleSet& p,
                                          const std::string& scene_path, const std::string& key) {
  std::vector<std::uint32_t> out;
  // The scene's line (or ", --set") of the region's key when the scene reader gave it.
  const std::string& where = region.where.empty() ? scene_path : region.where;
  if (region.has_nearest) {
    if (p.size() > 0) out.push_back(nearest_particle(p, region.nearest, where, key));
  } else if (region.has_box) {
    for (std::size_t i = 0; i < p.size(); ++i)
      if (p.x[i] >= region.box[0] && p.x[i] <= region.box[2] && p.y[i] >= region.box[1] && p.y[i] <= region.box[3])
        out.push_back(static_cast<std::uint32_t>(i));
  } else if (region.set == "all") {
    out.resize(p.size());
    std::iota(out.begin(), out.end(), 0u);
  } else if (const BoundarySet* s = p.find_set(region.set)) {
    out = s->particles;
  } else {
    std::string known;
    for (const auto& s : p.sets) known += (known.empty() ? "" : ", ") + s.name;
    // A round plate has no side sets, and a file may have no set at all (docs/mesher.md, "Boundary sets").
    throw Error(where + ": key '" + key + ".set' = \"" + region.set + "\": no such boundary set in the particle file " +
                (known.empty() ? std::string("(it has none: no straight side, hole or named Physical Curve of its "
                                             "geometry made one; use \"all\", a box or nearest, or name the curves "
                                             "with Physical Curve in the .geo)")
                               : "(known: " + known + ", or \"all\")"));
  }
  if (out.empty()) {
    // A box in mm read as metres lies far off the plate: say where the plate is.
    std::ostringstream m;
    m << where << ": key '" << key << "': " << region.describe() << " contains no particle";
    if (region.has_box)
      m << " (the plate spans x in [" << p.xmin << ", " << p.xmax << "], y in [" << p.ymin << ", " << p.ymax
        << "] m; box coordinates are in m, [xmin, ymin, xmax, ymax])";
    throw Error(m.str());
  }
  return out;
}

double set_edge_length(const ParticleSet& p, const std::vector<std::uint32_t>& set) {
  double xmin = INFINITY, xmax = -INFINITY, ymin = INFINITY, ymax = -INFINITY;
  for (auto i : set) {
    const double h = 0.5 * p.cell_size[i];
    xmin = std::min(xmin, p.x[i] - h), xmax = std::max(xmax, p.x[i] + h);
    ymin = std::min(ymin, p.y[i] - h), ymax = std::max(ymax, p.y[i] + h);
  }
  return std::max(xmax - xmin, ymax - ymin);
}

std::vector<ResolvedLoad> resolve_loads(const Scene& scene, const ParticleSet& p) {
  std::vector<ResolvedLoad> loads;
  // The plate's bounding box from the particle file (the particles' centres
  // where a set has none).
  double plate_size = std::max(p.xmax - p.xmin, p.ymax - p.ymin);
  if (!(plate_size > 0) && !scene.loads.empty() && p.size() > 0) {
    const auto [x0, x1] = std::minmax_element(p.x.begin(), p.x.end());
    const auto [y0, y1] = std::minmax_element(p.y.begin(), p.y.end());
    plate_size = std::max(*x1 - *x0, *y1 - *y0);
  }
  for (std::size_t k = 0; k < scene.loads.size(); ++k) {
    ResolvedLoad load;
    load.spec = scene.loads[k];
    load.plate_size = plate_size;
    load.particles = resolve_region(load.spec.region, p, scene.path, load_key(load.spec, k));
    for (auto i : load.particles) {
      load.value_x.push_back(load.spec.x_at({p.x[i], p.y[i]}));
      load.value_y.push_back(load.spec.y_at({p.x[i], p.y[i]}));
    }
    // Lengths in mm written as m lie a thousand plates off: a point of a
    // value that varies with position, or an edge length, more than a hundred
    // plate sizes beyond the plate is refused (the box and nearest-point
    // regions are checked the same way, by the particles they hold).
    const auto plate_text = [&] {
      std::ostringstream m;
      m << "the plate spans x in [" << p.xmin << ", " << p.xmax << "], y in [" << p.ymin << ", " << p.ymax
        << "] m; lengths in a scene are in m (1 mm = 1e-3)";
      return m.str();
    };
    // A length near the largest double over a small plate overflows the
    // ratio: say "more than" the largest number instead of "inf".
    const auto plate_sizes = [&](double length) {
      const double ratio = length / plate_size;
      std::ostringstream m;
      if (std::isfinite(ratio))
        m << ratio;
      else
        m << "more than " << shortest_text(std::numeric_limits<double>::max());
      return m.str();
    };
    for (const LinearVariation* v : {&load.spec.x_variation, &load.spec.y_variation})
      for (const auto& [key, point] : v->written_points) {
        const double off = std::max({p.xmin - point.x, point.x - p.xmax, p.ymin - point.y, point.y - p.ymax, 0.0});
        if (plate_size > 0 && off > 100 * plate_size) {
          std::ostringstream m;
          m << scene.path << ": key '" << key << "' = [" << shortest_text(point.x) << ", " << shortest_text(point.y)
            << "] lies " << plate_sizes(off) << " plate sizes off the plate (" << plate_text() << ")";
          throw Error(m.str());
        }
      }
    if (load.spec.kind == LoadKind::traction) {
      load.set_extent = set_edge_length(p, load.particles);
      if (plate_size > 0 && load.spec.edge_length > 100 * plate_size) {
        std::ostringstream m;
        m << scene.path << ": key '" << load_key(load.spec, k) << ".edge_length' = "
          << shortest_text(load.spec.edge_length) << " m is " << plate_sizes(load.spec.edge_length)
          << " times the plate's size (" << plate_text() << ")";
        throw Error(m.str());
      }
      load.edge_length = load.spec.edge_length > 0 ? load.spec.edge_length : load.set_extent;
      double area = 0;
      for (auto i : load.particles) area += p.volume[i];
      load.body_force_x = load.spec.x * load.edge_length / area;
      load.body_force_y = load.spec.y * load.edge_length / area;
    }
    loads.push_back(std::move(load));
  }
  // A component can follow one prescription only: which one would win depends
  // on the order of the loads in the file, so two are an error.
  for (const auto& s : shared_components(loads, Sharers::constraints)) {
    std::ostringstream m;
    m << scene.path << ": loads " << label(loads, s.constraint) << " and " << label(loads, s.other)
      << " both constrain the " << s.component << " component of " << s.particles << " particle"
      << (s.particles == 1 ? "" : "s") << " (e.g. the one at (" << p.x[s.example] << ", " << p.y[s.example]
      << ") m): a component can follow one constraint only; give one of them a region that leaves out the shared "
         "particles (a box), or constrain different components";
    throw Error(m.str());
  }
  return loads;
}

namespace {

// The loads that constrain both components of every one of `particle_count`
// particles, as labels ("'hold' (fixed on \"all\")"), or empty where a
// particle keeps a free component.
std::string loads_holding_every_particle(const std::vector<ResolvedLoad>& loads, std::size_t particle_count) {
  if (particle_count == 0) return {};
  std::vector<std::uint8_t> held(particle_count, 0);  // bit 0: x, bit 1: y
  std::string holders;
  for (std::size_t l = 0; l < loads.size(); ++l) {
    const ResolvedLoad& load = loads[l];
    if (!load.constrains_motion() || (!load.spec.has_x && !load.spec.has_y)) continue;
    const std::uint8_t bits = (load.spec.has_x ? 1 : 0) | (load.spec.has_y ? 2 : 0);
    for (auto i : load.particles) {
      if (i >= particle_count) return {};  // (the loads of a refined set, larger than the count given)
      held[i] |= bits;
    }
    holders += (holders.empty() ? "" : ", ") + label(loads, l);
  }
  for (const std::uint8_t h : held)
    if (h != 3) return {};
  return holders;
}

}  // namespace

std::vector<std::string> load_warnings(const std::vector<ResolvedLoad>& loads, bool starts_from_equilibrium,
                                       std::size_t particle_count) {
  std::vector<std::string> warnings;
  // Every particle's motion prescribed: nothing moves by the equations of
  // motion, the run only imposes the loads (before 7 December 2026 no word).
  if (const std::string holders = loads_holding_every_particle(loads, particle_count); !holders.empty())
    warnings.push_back("the constraints " + holders + " hold both components of every one of the " +
                       std::to_string(particle_count) + " particles: no particle is left to move, and the run " +
                       "computes only the motion the loads prescribe; give them sets or boxes that leave the " +
                       "plate free between the loaded edges (docs/scenes.md, [[loads]])");
  if (loads.empty() && !starts_from_equilibrium)
    warnings.push_back("no [[loads]] act in this run: the plate stays at rest (docs/scenes.md)");
  // (Before 7 December 2026 a switching scene's dynamic part was told its
  // plate stays at rest: it springs back from the equilibrium.)
  if (loads.empty() && starts_from_equilibrium)
    warnings.push_back("no [[loads]] of phase = \"dynamic\": the dynamic part starts from the quasi-static part's "
                       "equilibrium with nothing holding the plate, which springs back from it; to hold a strip "
                       "where the quasi-static part left it, give it a load of phase = \"dynamic\", type = "
                       "\"velocity\", x = 0, y = 0 (docs/scenes.md, \"Quasi-static, then dynamic\")");
  for (const auto& s : shared_components(loads, Sharers::tractions_and_initial_velocities)) {
    std::ostringstream m;
    m << "load " << label(loads, s.other) << " acts on the " << s.component << " component of " << s.particles
      << " particle" << (s.particles == 1 ? "" : "s") << " that load " << label(loads, s.constraint)
      << " constrains: there the constraint wins and that part of the load has no effect";
    warnings.push_back(m.str());
  }
  return warnings;
}

RegionPeak most_damaged(const std::vector<std::uint32_t>& region, const std::vector<double>& damage,
                        const std::vector<double>& x, const std::vector<double>& y) {
  RegionPeak peak;
  for (auto i : region)
    if (damage[i] > peak.damage || (damage[i] == peak.damage && (x[i] < peak.x || (x[i] == peak.x && y[i] < peak.y))))
      peak = {damage[i], x[i], y[i]};
  return peak;
}

std::string stop_condition_reason(const StopSpec& stop, const RegionPeak& peak) {
  std::ostringstream m;
  m << "stop condition: damage >= " << stop.damage << " in " << stop.region.describe() << " (at ("
    << peak.x * 1e3 << ", " << peak.y * 1e3 << ") mm, damage " << peak.damage << ")";
  return m.str();
}

std::string stop_holds_at_start(const Scene& scene, double damage, const std::string& first, const std::string& from) {
  std::ostringstream m;
  m << scene.path << ": table [stop]: damage >= " << scene.stop.damage << " in " << scene.stop.region.describe()
    << " holds before the first " << first << " (damage " << damage << " there at the start, from " << from
    << "): the run would stop at once; choose a region the crack has to reach, or a higher stop.damage";
  return m.str();
}

std::string rigid_translation_warning(const std::vector<ResolvedLoad>& loads) {
  std::optional<double> value[2];  // the one value of each component held (none: free)
  std::string holders;
  for (std::size_t l = 0; l < loads.size(); ++l) {
    const ResolvedLoad& load = loads[l];
    if (load.spec.kind == LoadKind::traction && (load.spec.x != 0 || load.spec.y != 0)) return {};
    if (!load.constrains_motion()) continue;
    const bool fixed = load.spec.kind == LoadKind::fixed;
    const bool given[2] = {load.spec.has_x, load.spec.has_y};
    const bool uniform[2] = {load.spec.x_variation.is_uniform(), load.spec.y_variation.is_uniform()};
    const double values[2] = {fixed ? 0.0 : load.spec.x, fixed ? 0.0 : load.spec.y};
    for (int c = 0; c < 2; ++c) {
      if (!given[c]) continue;
      if (!fixed && !uniform[c]) return {};  // a varying value strains its set
      if (value[c] && *value[c] != values[c]) return {};
      value[c] = values[c];
    }
    holders += (holders.empty() ? "" : ", ") + label(loads, l);
  }
  if (holders.empty()) return {};  // (no constraint: load_warnings says so where nothing acts)
  const auto text = [&](int c) { return value[c] ? shortest_text(*value[c]) : std::string("free"); };
  const bool one = holders.find("), ") == std::string::npos;
  const bool at_rest = value[0].value_or(0) == 0 && value[1].value_or(0) == 0;
  return "the constraint" + std::string(one ? " " : "s ") + holders + (one ? " prescribes" : " prescribe") +
         " the same displacement, (" + text(0) + ", " + text(1) + ") m at load factor 1, to every particle " +
         (one ? "it holds" : "they hold") + ", and no traction acts: the whole plate " +
         (at_rest ? "stays at rest" : "follows rigidly") + " and carries no load (strain energy 0 at every step); " +
         (at_rest ? "load another part of it, e.g. a displacement on the opposite edge"
                  : "hold another part of it otherwise, e.g. a load of type = \"fixed\" on the opposite edge") +
         " (docs/scenes.md, [[loads]])";
}

void check_tractions_held(const Scene& scene, const std::vector<ResolvedLoad>& loads, const ParticleSet& particles) {
  for (const char component : {'x', 'y'}) {
    double resultant = 0, magnitudes = 0;  // [N] at load factor 1
    bool held = false;
    std::string tractions;
    for (std::size_t l = 0; l < loads.size(); ++l) {
      const ResolvedLoad& load = loads[l];
      const bool given = component == 'x' ? load.spec.has_x : load.spec.has_y;
      if (!given) continue;
      if (load.constrains_motion()) held = true;
      if (load.spec.kind != LoadKind::traction) continue;
      // The resultant is exact: t L h (ResolvedLoad::edge_length).
      const double r = (component == 'x' ? load.spec.x : load.spec.y) * load.edge_length * scene.material.thickness;
      if (r == 0) continue;
      resultant += r;
      magnitudes += std::fabs(r);
      tractions += (tractions.empty() ? "" : ", ") + label(loads, l);
    }
    // Tractions that balance (a tensile test pulled at both ends) need no support.
    if (held || !(std::fabs(resultant) > 1e-9 * magnitudes)) continue;
    std::ostringstream m;
    const bool one = tractions.find("), ") == std::string::npos;
    m << scene.path << ": the traction" << (one ? " " : "s ") << tractions << (one ? " pushes" : " push")
      << " the plate along " << component << " with a resultant of " << resultant
      << " N at load factor 1, and no load holds the " << component
      << " component of any particle: the plate has no equilibrium (it would move off as a rigid body, each "
      << "minimisation running to quasi_static.max_iterations); hold it, e.g. a load of type = \"fixed\" on the "
      << "opposite edge or a pin (nearest = [x, y], type = \"fixed\"), or balance the tractions";
    throw Error(m.str());
  }

  // The turn about the z axis (before 7 December 2026 not looked for: a plate
  // pinned at one particle under a couple ran every minimisation to
  // max_iterations). Loads that hold x components only of particles at one
  // height c_y, and y components only of particles at one abscissa c_x, leave
  // the plate free to turn about (c_x, c_y); their reactions have no moment
  // about it, so the tractions' moment about it must vanish. (A held
  // component with no value for c: that turn needs none, and the moment of
  // balanced tractions is the same about every point.)
  std::optional<double> centre[2];  // c_x (from the held y components), c_y (from the held x components)
  bool turn_held = false;
  std::string holders;
  const double size = std::max(particles.xmax - particles.xmin, particles.ymax - particles.ymin);
  for (std::size_t l = 0; l < loads.size() && !turn_held; ++l) {
    const ResolvedLoad& load = loads[l];
    if (!load.constrains_motion()) continue;
    holders += (holders.empty() ? "" : ", ") + label(loads, l);
    for (const auto i : load.particles) {
      // x held at height y_i, y held at abscissa x_i.
      const bool given[2] = {load.spec.has_y, load.spec.has_x};
      const double at[2] = {particles.x[i], particles.y[i]};
      for (int c = 0; c < 2; ++c) {
        if (!given[c]) continue;
        if (!centre[c]) centre[c] = at[c];
        else if (std::fabs(at[c] - *centre[c]) > 1e-9 * size) turn_held = true;
      }
    }
  }
  if (turn_held) return;
  double moment = 0, magnitudes = 0, area = 0, cx = 0, cy = 0;  // [N m] at load factor 1
  std::string tractions;
  for (std::size_t l = 0; l < loads.size(); ++l) {
    const ResolvedLoad& load = loads[l];
    if (load.spec.kind != LoadKind::traction || (load.body_force_x == 0 && load.body_force_y == 0)) continue;
    tractions += (tractions.empty() ? "" : ", ") + label(loads, l);
    for (const auto i : load.particles) {
      area += particles.volume[i];
      cx += particles.volume[i] * particles.x[i];
      cy += particles.volume[i] * particles.y[i];
    }
  }
  if (tractions.empty()) return;
  // About the tractions' own centre where no held component fixes c (any
  // point gives the moment of balanced tractions; this one loses least to
  // round-off).
  const double c[2] = {centre[0].value_or(cx / area), centre[1].value_or(cy / area)};
  for (const auto& load : loads) {
    if (load.spec.kind != LoadKind::traction) continue;
    for (const auto i : load.particles) {
      const double h = scene.material.thickness * particles.volume[i];
      const double term = h * ((particles.x[i] - c[0]) * load.body_force_y - (particles.y[i] - c[1]) * load.body_force_x);
      moment += term;
      magnitudes += std::fabs(term);
    }
  }
  if (!(std::fabs(moment) > 1e-9 * magnitudes)) return;
  std::ostringstream m;
  const bool one = tractions.find("), ") == std::string::npos;
  m << scene.path << ": the traction" << (one ? " " : "s ") << tractions << (one ? " turns" : " turn")
    << " the plate with a moment of " << moment << " N m at load factor 1 about (" << c[0] * 1e3 << ", "
    << c[1] * 1e3 << ") mm, and ";
  if (holders.empty())
    m << "no load holds any particle";
  else {
    const bool several = holders.find("), ") != std::string::npos;
    m << "the load" << (several ? "s " : " ") << holders << " that hold" << (several ? "" : "s")
      << " the plate leave" << (several ? "" : "s") << " it free to turn about that point ("
      << (several ? "they hold" : "it holds");
    if (centre[1]) m << " x components only at y = " << *centre[1] * 1e3 << " mm";
    if (centre[0] && centre[1]) m << " and";
    if (centre[0]) m << " y components only at x = " << *centre[0] * 1e3 << " mm";
    m << ")";
  }
  m << ": the plate has no equilibrium (it would turn as a rigid body, each minimisation running to "
    << "quasi_static.max_iterations); hold a second point away from it, e.g. a load of type = \"fixed\" on an "
    << "edge, or balance the tractions' moment";
  throw Error(m.str());
}

bool beyond_plate(const ResolvedLoad& load, double largest) {
  // A tenth of the plate is a mean strain of 10 % or more: far past any brittle solid's failure.
  return load.spec.kind == LoadKind::displacement && load.plate_size > 0 && largest > 0.1 * load.plate_size;
}

double value_lost_at_factor(const ResolvedLoad& load, double factor) {
  if (factor == 0 || load.spec.kind == LoadKind::fixed) return 0;
  for (const auto* values : {load.spec.has_x ? &load.value_x : nullptr, load.spec.has_y ? &load.value_y : nullptr}) {
    if (!values) continue;
    for (const double value : *values)
      if (value != 0 && std::fabs(value * factor) < std::numeric_limits<double>::min()) return value;
  }
  return 0;
}

double largest_load_value(const ResolvedLoad& load) {
  double largest = 0;
  for (std::size_t m = 0; m < load.particles.size(); ++m)
    largest = std::max(largest, std::hypot(load.value_x.empty() ? 0.0 : load.value_x[m],
                                           load.value_y.empty() ? 0.0 : load.value_y[m]));
  return largest;
}

std::vector<std::string> load_size_warnings(const MaterialSpec& material, const std::vector<ResolvedLoad>& loads,
                                            double load_factor) {
  std::vector<std::string> warnings;
  const double modulus = material.youngs_modulus;
  const double wave_speed = material.density > 0 ? std::sqrt(modulus / material.density) : 0;  // [m/s]
  for (const auto& load : loads) {
    // The largest value the load reaches: its largest component times the
    // largest factor of its time function.
    double largest = largest_load_value(load);
    double factor = 1;
    if (load.spec.time_function.kind == TimeFunction::Kind::table) {
      factor = 0;
      for (const auto& [t, f] : load.spec.time_function.table) factor = std::max(factor, std::fabs(f));
    }
    largest *= factor;
    // A quasi-static run scales the loads by its load factors: the values
    // held to these scales are those at the largest (load_factors = [1e6]
    // with 1 um is a displacement of 1 m).
    largest *= load_factor;
    std::ostringstream m;
    m << "load '" << load.spec.name << "': ";
    if (load_factor != 1) m << "at the largest load factor, " << load_factor << ", ";
    // A traction or an initial velocity of 0 (every component given, or the
    // time table's every factor) does nothing; a velocity or a displacement
    // of 0 holds its set, which is their use (before 7 December 2026 no word).
    const bool pushes = load.spec.kind == LoadKind::traction || load.spec.kind == LoadKind::initial_velocity;
    if (pushes && largest == 0) {
      m << (load.spec.kind == LoadKind::traction ? "a traction" : "an initial velocity")
        << " of 0 everywhere has no effect (every component given is 0"
        << (factor == 0 ? ", or its time table's every factor" : "") << ")";
      warnings.push_back(m.str());
    } else if (load.spec.kind == LoadKind::traction && largest > 0 && (largest < 1e-8 * modulus || largest > modulus)) {
      m << "a traction of at most " << largest << " Pa is " << largest / modulus
        << " times Young's modulus: tractions are in Pa (1 MPa = 1e6)";
      warnings.push_back(m.str());
    } else if ((load.spec.kind == LoadKind::velocity || load.spec.kind == LoadKind::initial_velocity) &&
               wave_speed > 0 && largest > 0.1 * wave_speed) {
      m << "a velocity of up to " << largest << " m/s is " << largest / wave_speed
        << " times the wave speed sqrt(E / rho) = " << wave_speed << " m/s: velocities are in m/s (1 mm/s = 1e-3)";
      warnings.push_back(m.str());
    } else if (load.spec.kind == LoadKind::traction && load.spec.edge_length > 0 && load.set_extent > 0 &&
               (load.spec.edge_length > 3 * load.set_extent || load.spec.edge_length < load.set_extent / 3)) {
      // The resultant is traction x edge length: an edge longer than the set's
      // extent multiplies it, a shorter one divides it (1e-300 m: no load at
      // all; before 7 December 2026 no word of the shorter).
      m << "an edge length of " << load.spec.edge_length << " m is " << load.spec.edge_length / load.set_extent
        << " times the extent of the loaded set (" << load.set_extent
        << " m): the resultant is traction x edge length; lengths are in m (1 mm = 1e-3)";
      warnings.push_back(m.str());
    } else if (beyond_plate(load, largest)) {
      m << "a displacement of up to " << largest << " m is " << largest / load.plate_size
        << " times the plate's size (" << load.plate_size << " m): displacements are in m (1 mm = 1e-3)";
      warnings.push_back(m.str());
    }
  }
  return warnings;
}

}  // namespace pd::solver
