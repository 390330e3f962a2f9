#include "arrival_data.hpp"

#include <vtkPointData.h>
#include <vtkPolyData.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <regex>
#include <sstream>
#include <utility>

#include "error.hpp"
#include "results_format.hpp"
#include "statistics.hpp"
#include "units.hpp"
#include "vtp_input.hpp"

namespace fs = std::filesystem;

namespace pd::post {
namespace {

double required_field(vtkPolyData* poly, const std::string& path, const char* name) {
  const auto v = read_field_values(poly, name);
  if (v.empty()) throw file_error(path, std::string("no field data '") + name + "'");
  return v.front();
}

// A Poisson ratio field, checked against what pd-solve writes: the PMB
// model's 1/3 or 1/4, or the scene's material.poisson_ratio, which its scene
// reader bounds to (0, 0.5). An isotropic solid's (-1, 0) is no run's here
// (before 7 December 2026 -0.5 passed, and the Rayleigh speed was of it).
std::optional<double> poisson_field(vtkPolyData* poly, const std::string& path, const char* name) {
  const auto v = read_field_values(poly, name);
  if (v.empty()) return std::nullopt;
  if (!(v.front() > 0.0 && v.front() < 0.5))
    throw file_error(path, std::string("field '") + name + "' = " + shortest_text(v.front()) +
                               " is not a Poisson ratio pd-solve writes, in (0, 0.5) (an edited or damaged file)");
  return v.front();
}

// The shear wave speed of every Poisson ratio the Rayleigh speed may be
// computed with, against the bounds of solids (arrival_data.hpp): outside
// them the fields are edited, and the speed window's step count, the
// cells a tip at c_R crosses in a window over its time, leaves any range
// (before 7 December 2026 a youngs_modulus of 1e-300 Pa cast it to int
// far beyond its range).
void check_wave_speed(const ArrivalData& d, const std::string& path) {
  std::vector<std::pair<double, std::string>> ratios;
  if (d.model_poisson_ratio)
    ratios.emplace_back(*d.model_poisson_ratio, std::string("field '") + results::field_poisson_ratio + "'");
  else  // the field absent: the bond-based PMB model's, in plane stress and plane strain
    ratios = {{1.0 / 3.0, "the PMB model's"}, {1.0 / 4.0, "the PMB model's"}};
  if (d.material_poisson_ratio)
    ratios.emplace_back(*d.material_poisson_ratio,
                        std::string("field '") + results::field_material_poisson_ratio + "'");
  for (const auto& [nu, source] : ratios) {
    const double speed = std::sqrt(d.youngs_modulus / (2.0 * (1.0 + nu)) / d.density);
    if (speed >= min_shear_wave_speed && speed <= max_shear_wave_speed) continue;
    char text[480];
    std::snprintf(text, sizeof text,
                  "fields 'youngs_modulus' = %g Pa and 'density' = %g kg/m^3 give, with a Poisson ratio of %.4g "
                  "(%s), a shear wave speed of %.3g m/s, outside the %g to %g m/s of solids (about 1 m/s in the "
                  "softest gels, 1.3e4 m/s in diamond): an edited or damaged file; pd-solve writes the scene's "
                  "material",
                  d.youngs_modulus, d.density, nu, source.c_str(), speed, min_shear_wave_speed,
                  max_shear_wave_speed);
    throw file_error(path, text);
  }
}

}  // namespace

std::string PlateExtent::text() const {
  char buf[160];
  std::snprintf(buf, sizeof buf, "x %g to %g m, y %g to %g m", x_min, x_max, y_min, y_max);
  return buf;
}

PlateExtent plate_extent(const ArrivalData& d) {
  // The centres widened by half the largest cell: a lattice plate's own
  // edges (a whole cell read x -9.5e-05 m on a plate from 0).
  const double margin = 0.5 * *std::max_element(d.cell_size.begin(), d.cell_size.end());
  const auto [x_min, x_max] = std::minmax_element(d.x.begin(), d.x.end());
  const auto [y_min, y_max] = std::minmax_element(d.y.begin(), d.y.end());
  return {*x_min - margin, *x_max + margin, *y_min - margin, *y_max + margin};
}

void require_output_directory(const std::string& outdir) {
  if (fs::is_directory(outdir)) return;
  if (fs::exists(outdir))
    throw file_error(outdir, "a file, not a solver output directory: pd-post reads the folder that pd-solve -o wrote "
                             "(with --particles FILE it draws a particle file's cells)");
  throw file_error(outdir, "solver output directory not found");
}

ArrivalData read_arrival_data(const std::string& outdir, double threshold) {
  require_output_directory(outdir);
  const std::string path = (fs::path(outdir) / results::arrival_file).string();
  if (!fs::exists(path)) throw file_error(path, "file not found (pd-post needs the solver's arrival-time file)");
  auto poly = read_vtp_quietly(path, "the run's arrival-time file, which pd-post reads; give the folder that "
                                     "pd-solve -o wrote");

  ArrivalData d;
  d.path = path;
  read_points(poly, path, d.x, d.y);
  // A cell of size 0 (an edited file) would be drawn as a dot and count no area.
  d.cell_size = checked_sizes(read_point_array(poly, path, results::cell_size, false), path, results::cell_size);
  if (d.cell_size.empty()) {
    // Square cells of the particle volume are the next best estimate.
    const auto volume =
        checked_sizes(read_point_array(poly, path, results::volume, true), path, results::volume, true);
    for (double v : volume) d.cell_size.push_back(std::sqrt(v));
    d.notes.push_back("no 'cell_size' array: cell sizes taken as sqrt(volume)");
  }
  check_positions_resolved(path, d.x, d.y, d.cell_size);
  d.damage = checked_damage(read_point_array(poly, path, results::damage, true), path, results::damage);
  d.strain_energy_density = read_point_array(poly, path, results::strain_energy_density, false);
  read_vector_array(poly, path, results::displacement, d.ux, d.uy);

  // Every arrival array present, so damage maps at given times can be rebuilt.
  std::vector<std::string> available;
  vtkPointData* point_data = poly->GetPointData();
  const std::string prefix = results::arrival_prefix;
  for (int k = 0; k < point_data->GetNumberOfArrays(); ++k) {
    const char* name = point_data->GetArrayName(k);
    if (name == nullptr || std::string(name).rfind(prefix, 0) != 0) continue;
    available.push_back(name);
    ArrivalField f;
    f.threshold = std::atof(name + prefix.size());
    f.array = name;
    f.time = read_point_array(poly, path, name, true);
    d.arrivals.push_back(std::move(f));
  }
  std::sort(d.arrivals.begin(), d.arrivals.end(),
            [](const ArrivalField& a, const ArrivalField& b) { return a.threshold < b.threshold; });

  const std::string wanted = results::arrival_array_name(threshold);
  if (!point_data->GetArray(wanted.c_str())) {
    // Name the thresholds the run recorded: the user picks one of them, or reruns with the one wanted.
    std::string thresholds, arrays;
    for (const auto& a : available) {
      thresholds += (thresholds.empty() ? "" : ", ") + shortest_text(std::atof(a.c_str() + prefix.size()));
      arrays += (arrays.empty() ? "" : ", ") + a;
    }
    const bool in_range = threshold > 0 && threshold <= 1;
    throw file_error(path, "--threshold " + shortest_text(threshold) + ": no point array '" + wanted + "'; " +
                               (available.empty() ? std::string("the run recorded no arrival times at all")
                                                  : "the run recorded the damage thresholds " + thresholds +
                                                        " (arrays " + arrays + ")") +
                               ", those of the scene's output.damage_thresholds: give one of them" +
                               (in_range ? "" : " (a damage threshold is in (0, 1])") +
                               ", or add it to output.damage_thresholds and run pd-solve again");
  }
  d.arrival = read_point_array(poly, path, wanted.c_str(), true);
  d.threshold = threshold;

  d.youngs_modulus = required_field(poly, path, results::field_youngs_modulus);
  d.density = required_field(poly, path, results::field_density);
  d.time_step = required_field(poly, path, results::field_time_step);
  const auto positive = [](double v) { return v > 0 && std::isfinite(v); };
  if (!(positive(d.youngs_modulus) && positive(d.density) && positive(d.time_step)))
    throw file_error(path, "youngs_modulus, density and time_step must be positive and finite, found " +
                               shortest_text(d.youngs_modulus) + ", " + shortest_text(d.density) + ", " +
                               shortest_text(d.time_step));
  d.model_poisson_ratio = poisson_field(poly, path, results::field_poisson_ratio);
  // The solver writes -1 when the scene gives no material Poisson ratio;
  // any other value is checked (before 7 December 2026 every negative one,
  // -5 of an edited file, was read as none, without a word).
  const auto material_nu = read_field_values(poly, results::field_material_poisson_ratio);
  if (!material_nu.empty() && material_nu.front() != -1)
    d.material_poisson_ratio = poisson_field(poly, path, results::field_material_poisson_ratio);
  // pd-solve writes 1 (plane strain) or 0 (plane stress); before 7 December
  // 2026 any other value (0.5, NaN) was read as plane strain, exit 0.
  if (const auto plane_strain = read_field_number(poly, path, results::field_plane_strain)) {
    if (*plane_strain != 0 && *plane_strain != 1)
      throw file_error(path, std::string("field '") + results::field_plane_strain + "' = " +
                                 shortest_text(*plane_strain) + " is neither 1 (plane strain) nor 0 (plane stress), "
                                 "the values pd-solve writes (an edited or damaged file)");
    d.plane_strain = *plane_strain == 1;
  }
  check_wave_speed(d, path);

  const double max_arrival = *std::max_element(d.arrival.begin(), d.arrival.end());
  const auto end = read_field_values(poly, results::field_end_time);
  d.end_time = end.empty() ? max_arrival : end.front();
  if (!std::isfinite(d.end_time)) throw file_error(path, "field 'end_time' is not finite");
  // Before 7 December 2026 a negative one was refused only through the
  // arrival times after it, or as a run without a crack.
  if (!end.empty() && d.end_time < 0)
    throw file_error(path, "field 'end_time' = " + shortest_text(d.end_time) +
                               " s is negative: pd-solve writes the time the run reached, from 0 on (an edited or "
                               "damaged file)");
  // The tip is followed at every step (crack_tips.csv has a row per step
  // and branch): a time step that makes the run more steps than that can
  // hold is an edited field (before 7 December 2026 a time_step of 1e-300 s
  // made step counts cast to int and long far beyond their range).
  if (d.end_time / d.time_step > max_tracked_steps) {
    char text[320];
    std::snprintf(text, sizeof text,
                  "field 'time_step' = %g s makes the run to its end at %g s %.3g steps, more than the %g pd-post "
                  "follows a crack tip through, one step at a time (an edited or damaged file)",
                  d.time_step, d.end_time, d.end_time / d.time_step, max_tracked_steps);
    throw file_error(path, text);
  }
  // pd-solve records a time the run has reached (or -1 for never): a later
  // one is an edited file or another run's array (before 7 December 2026
  // read as it was: a crack grown after the run's end). Without the field
  // end_time is the chosen threshold's last arrival: no bound.
  for (const auto& field : d.arrivals)
    for (std::size_t i = 0; i < field.time.size(); ++i) {
      // Only -1 means never reached: another negative time is an edit
      // (before 7 December 2026 read as never reached, exit 0).
      if (field.time[i] < 0 && field.time[i] != -1)
        throw file_error(path, "point array '" + field.array + "' is " + shortest_text(field.time[i]) +
                                   " at particle " + std::to_string(i) + ": a time before the run's start; "
                                   "pd-solve writes -1 for a particle never reached and times from 0 otherwise "
                                   "(an edited or damaged file)");
      if (!end.empty() && field.time[i] > d.end_time * (1 + 1e-12))
        throw file_error(path, "point array '" + field.array + "' is " + shortest_text(field.time[i]) +
                                   " at particle " + std::to_string(i) + ": after the run's end at " +
                                   shortest_text(d.end_time) + " s (field 'end_time'); pd-solve records the times "
                                   "a run reached (an edited file, or another run's array)");
    }
  const auto step = read_field_values(poly, results::field_step);
  if (!step.empty() && !(step.front() >= 0 && step.front() < 9e15 && step.front() == std::floor(step.front())))
    throw file_error(path, "field 'step' = " + shortest_text(step.front()) + " is not a step number");
  d.end_step = step.empty() ? -1 : std::lround(step.front());
  const LengthFields lengths = read_length_fields(poly, path, d.cell_size);
  d.spacing = lengths.spacing.value_or(median(d.cell_size));
  if (!lengths.spacing) d.notes.push_back("no 'spacing' field: median cell size used");
  d.horizon = lengths.horizon.value_or(3.0 * d.spacing);
  if (!lengths.horizon) d.notes.push_back("no 'horizon' field: 3 x spacing used");
  d.run_id = read_field_text(poly, results::field_run_id);
  return d;
}

std::vector<double> damage_at_time(const ArrivalData& data, double time) {
  std::vector<double> damage(data.size(), 0.0);
  for (const auto& field : data.arrivals)  // ascending thresholds: the last hit wins
    for (std::size_t i = 0; i < damage.size(); ++i)
      if (field.time[i] >= 0 && field.time[i] <= time) damage[i] = field.threshold;
  return damage;
}

bool recorded_values_differ(double a, double b) {
  return std::isfinite(a) && std::isfinite(b) && std::abs(a - b) > 1e-9 * std::max(std::abs(a), std::abs(b));
}

Error mixed_runs_error(const std::string& path, const std::string& what) {
  return file_error(path, what + ": the two files are from different runs (a folder mixed by copying or moving "
                                 "files); give the folder that one pd-solve run wrote whole, or run pd-solve again");
}

void check_same_run_id(const std::string& path, const std::string& run_id, const std::string& key,
                       const std::string& other_path, const std::string& other_run_id) {
  if (run_id.empty() || other_run_id.empty() || run_id == other_run_id) return;
  throw mixed_runs_error(path, "is of run " + run_id + " (" + key + "), and " + other_path + " of run " + other_run_id);
}

std::vector<std::string> split_csv_line(const std::string& line) {
  std::vector<std::string> fields;
  std::stringstream in(line);
  std::string f;
  while (std::getline(in, f, ',')) fields.push_back(f);
  if (!line.empty() && line.back() == ',') fields.emplace_back();
  return fields;
}

std::string row_length_text(int line_no, std::size_t found, std::size_t expected) {
  return "line " + std::to_string(line_no) + ": found " + std::to_string(found) + (found == 1 ? " value" : " values") +
         ", expected " + std::to_string(expected) + ", one for each column of the header";
}

void check_run_tables(const std::string& outdir, const std::string& run_path, const std::string& run_id) {
  if (run_id.empty()) return;
  const auto trimmed = [](std::string line) {  // (a table saved again with CR LF line ends)
    if (!line.empty() && line.back() == '\r') line.pop_back();
    return line;
  };
  for (const char* name : {results::energy_file, results::load_steps_file}) {
    const std::string path = (fs::path(outdir) / name).string();
    std::ifstream in(path);
    std::string line;
    if (!in || !std::getline(in, line)) continue;
    const auto header = split_csv_line(trimmed(line));
    const auto column = std::find(header.begin(), header.end(), results::field_run_id);
    if (column == header.end()) continue;
    const auto c = static_cast<std::size_t>(column - header.begin());
    for (int line_no = 2; std::getline(in, line); ++line_no) {
      const auto cells = split_csv_line(trimmed(line));
      if (cells.empty()) continue;  // a blank line
      // pd-solve writes the table whole (a new file moved over the old one,
      // after a restart too: its checkpoint holds the rows), never a row at
      // a time, so a killed run leaves no row cut short: a row of another
      // length, or without the identifier, was cut or edited. Before 7
      // December 2026 such a row was passed over, its identifier unread.
      if (cells.size() != header.size())
        throw file_error(path, row_length_text(line_no, cells.size(), header.size()) +
                                   ": pd-solve writes every row whole (the file was cut or edited)");
      if (cells[c].empty())
        throw file_error(path, "line " + std::to_string(line_no) + ": column '" + results::field_run_id +
                                   "' is empty: pd-solve writes the run's identifier on every row (the file was cut "
                                   "or edited)");
      check_same_run_id(path, cells[c], std::string("column '") + results::field_run_id + "', line " +
                                            std::to_string(line_no),
                        run_path, run_id);
    }
  }
  const std::string pvd = (fs::path(outdir) / results::snapshot_collection).string();
  std::ifstream in(pvd);
  if (!in) return;
  std::stringstream text;
  text << in.rdbuf();
  const std::string s = text.str();
  std::smatch m;
  const std::regex attribute(std::string(R"re(<Collection\b[^>]*\b)re") + results::field_run_id + R"re(="([^"]*)")re");
  if (std::regex_search(s, m, attribute))
    check_same_run_id(pvd, m[1].str(), std::string("attribute '") + results::field_run_id + "' of its Collection",
                      run_path, run_id);
}

std::vector<SnapshotEntry> list_snapshots(const std::string& outdir, RunKind kind) {
  const fs::path pvd = fs::path(outdir) / results::snapshot_collection;
  std::vector<SnapshotEntry> entries;
  std::ifstream in(pvd);
  if (!in) return entries;
  std::stringstream text;
  text << in.rdbuf();
  const std::string s = text.str();
  // The collection is written by pd::write_pvd (atomically): one DataSet
  // element per line, then the closing tags. A file cut short, or an entry
  // whose time is not a number, is another file's or damaged: refused, not
  // read as a shorter series (before the second sitting of 5 December 2026 a
  // map asked for at 10 us was drawn from the last entry left, at 5 us).
  const std::string closing = "</VTKFile>";
  const auto last = s.find_last_not_of(" \t\r\n");
  if (last == std::string::npos || last + 1 < closing.size() ||
      s.compare(last + 1 - closing.size(), closing.size(), closing) != 0)
    throw file_error(pvd.string(), "does not end with </VTKFile>: cut short or not pd-solve's snapshot collection");
  const std::regex dataset(R"re(<DataSet[^>]*timestep="([^"]+)"[^>]*file="([^"]+)")re");
  std::size_t elements = 0;
  for (auto at = s.find("<DataSet"); at != std::string::npos; at = s.find("<DataSet", at + 1)) ++elements;
  for (auto it = std::sregex_iterator(s.begin(), s.end(), dataset); it != std::sregex_iterator();
       ++it) {
    SnapshotEntry e;
    const std::string time = (*it)[1].str();
    char* end = nullptr;
    e.time = std::strtod(time.c_str(), &end);
    if (end == time.c_str() || *end != '\0' || !std::isfinite(e.time))
      throw file_error(pvd.string(), "a DataSet's timestep=\"" + time + "\" is not a finite number");
    if (kind == RunKind::dynamic && e.time < 0)
      throw file_error(pvd.string(), "the DataSet of file=\"" + (*it)[2].str() + "\" has timestep=\"" + time +
                                         "\", a negative time: a dynamic run's snapshots are at t >= 0 (an edited "
                                         "or another program's collection); give the collection pd-solve wrote");
    e.file = (pvd.parent_path() / (*it)[2].str()).string();
    e.collection = pvd.string();
    entries.push_back(e);
  }
  if (entries.size() != elements)
    throw file_error(pvd.string(), std::to_string(elements - entries.size()) + " of its " + std::to_string(elements) +
                                       " DataSet elements lack a timestep or a file");
  std::sort(entries.begin(), entries.end(),
            [](const SnapshotEntry& a, const SnapshotEntry& b) { return a.time < b.time; });
  return entries;
}

std::string snapshot_role(const SnapshotEntry& entry) {
  return "a snapshot " + (entry.collection.empty() ? std::string("the run's collection") : entry.collection) +
         " lists; give the collection pd-solve wrote";
}

const SnapshotEntry& nearest_snapshot(const std::vector<SnapshotEntry>& entries, double time) {
  // By the entries on either side of `time`, not by the least |t_i - time|:
  // far beyond the run (--times 1e300) every difference rounds to the same
  // number, and before 7 December 2026 the first snapshot was drawn.
  const auto earlier = [](const SnapshotEntry& e, double t) { return e.time < t; };
  const auto after = std::lower_bound(entries.begin(), entries.end(), time, earlier);
  if (after == entries.begin()) return *after;
  // Of several snapshots at one time (a run that unloads), the first.
  const auto before = std::lower_bound(entries.begin(), after, std::prev(after)->time, earlier);
  if (after == entries.end()) return *before;
  return after->time - time < time - before->time ? *after : *before;
}

void check_snapshot_time(const SnapshotEntry& entry, double recorded, bool by_load_factor) {
  // Both written by the run to 17 digits: a snapshot copied in from another
  // run at the same step file name shows another time (before 6 December
  // 2026 its time was taken and the collection's ignored).
  if (!recorded_values_differ(recorded, entry.time)) return;
  const auto value = [&](double v) {
    return by_load_factor ? "load factor " + shortest_text(v) : "t = " + shortest_text(v) + " s";
  };
  throw mixed_runs_error(entry.file, std::string("is of ") + value(recorded) + " (field '" +
                                         (by_load_factor ? results::field_load_factor : results::field_time) +
                                         "'), and " + (entry.collection.empty() ? "the collection" : entry.collection) +
                                         " lists it at " + value(entry.time));
}

SnapshotFields read_snapshot(const SnapshotEntry& entry, const RunParticles& run, bool own_particles) {
  auto poly = read_vtp_quietly(entry.file, snapshot_role(entry));
  SnapshotFields s;
  const auto count = static_cast<std::size_t>(poly->GetNumberOfPoints());
  const std::size_t expected_points = run.x.size();
  // A refined run's set only grows: a snapshot of more particles than its
  // final state is another run's.
  if (count > expected_points && own_particles)
    throw mixed_runs_error(entry.file, "has " + std::to_string(count) + " particles, and the run's final state has " +
                                           std::to_string(expected_points) +
                                           " (a refined run's particles only grow in number)");
  if (count != expected_points) {
    // A refined run's snapshot: drawn with its own particles.
    if (own_particles)
      s.cell_size = checked_sizes(read_point_array(poly, entry.file, results::cell_size, false), entry.file,
                                  results::cell_size);
    if (s.cell_size.empty())
      throw file_error(entry.file, "has " + std::to_string(count) + " particles, the run's final state has " +
                                       std::to_string(expected_points) +
                                       (own_particles ? std::string(" (and the snapshot has no '") +
                                                            results::cell_size + "' array to draw its own particles with)"
                                                      : std::string()));
    read_points(poly, entry.file, s.x, s.y);
    check_positions_resolved(entry.file, s.x, s.y, s.cell_size);
  } else {
    // Drawn at the run's positions: pd-solve writes every file's particles
    // in the particle file's order, at the same reference positions. A
    // snapshot of them in another order (saved again by another program, or
    // of another plate of as many particles) would put each value at
    // another particle's place (before 7 December 2026 drawn so, exit 0).
    std::vector<double> x, y;
    read_points(poly, entry.file, x, y);
    for (std::size_t i = 0; i < count; ++i)
      if (std::hypot(x[i] - run.x[i], y[i] - run.y[i]) > 1e-3 * run.cell_size[i]) {
        char text[300];
        std::snprintf(text, sizeof text, "particle %zu is at (%.9g, %.9g) m, and in %s at (%.9g, %.9g) m", i, x[i],
                      y[i], run.path.c_str(), run.x[i], run.y[i]);
        throw file_error(entry.file, std::string(text) +
                                         ": its particles are in another order, or of another plate (the file saved "
                                         "again by another program, or another run's); give the snapshot pd-solve "
                                         "wrote with the run, or run pd-solve again");
      }
  }
  // (A NaN, refused here, would pass the comparison below and name the map "damage_tnanus.png".)
  auto t = read_field_number(poly, entry.file, results::field_time);
  const bool by_load_factor = !t;
  if (by_load_factor) t = read_field_number(poly, entry.file, results::field_load_factor);
  s.time = t.value_or(entry.time);
  check_snapshot_time(entry, s.time, by_load_factor);
  s.damage = checked_damage(read_point_array(poly, entry.file, results::damage, true), entry.file, results::damage);
  s.strain_energy_density = read_point_array(poly, entry.file, results::strain_energy_density, false);
  read_vector_array(poly, entry.file, results::displacement, s.ux, s.uy);
  s.run_id = read_field_text(poly, results::field_run_id);
  return s;
}

}  // namespace pd::post
