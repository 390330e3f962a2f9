#include "quasi_static_data.hpp"

#include <vtkPolyData.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "arrival_data.hpp"
#include "error.hpp"
#include "neighbor_search.hpp"
#include "results_format.hpp"
#include "statistics.hpp"
#include "vtp_input.hpp"

namespace fs = std::filesystem;

namespace pd::post {
namespace {

bool ends_with(const std::string& s, const std::string& tail) {
  return s.size() >= tail.size() && s.compare(s.size() - tail.size(), tail.size(), tail) == 0;
}

void read_load_steps(QuasiStaticData& q) {
  std::ifstream in(q.load_steps_path);
  if (!in) throw file_error(q.load_steps_path, "file not found (a quasi-static run writes it after every load step)");
  std::string line;
  if (!std::getline(in, line)) throw file_error(q.load_steps_path, "empty: no header line");
  const auto header = split_csv_line(line);
  auto column = [&](const std::string& name) {
    const auto it = std::find(header.begin(), header.end(), name);
    if (it == header.end()) throw file_error(q.load_steps_path, "no column '" + name + "' in the header");
    return static_cast<std::size_t>(it - header.begin());
  };
  const std::size_t step = column("step"), factor = column("load_factor"), damage = column("max_damage");
  std::vector<std::size_t> reaction_columns;
  for (std::size_t c = 0; c < header.size(); ++c)
    if (ends_with(header[c], "_reaction_x_N") || ends_with(header[c], "_reaction_y_N")) {
      reaction_columns.push_back(c);
      q.reactions.push_back({header[c], {}});
    }
  int line_no = 1;
  while (std::getline(in, line)) {
    ++line_no;
    if (line.empty()) continue;
    const auto fields = split_csv_line(line);
    if (fields.size() != header.size())
      throw file_error(q.load_steps_path, row_length_text(line_no, fields.size(), header.size()));
    auto value = [&](std::size_t c) {
      std::size_t used = 0;
      double v = 0;
      try {
        v = std::stod(fields[c], &used);
      } catch (const std::exception&) {
        used = 0;
      }
      if (used == 0 || used != fields[c].size() || !std::isfinite(v))
        throw file_error(q.load_steps_path, "line " + std::to_string(line_no) + ": column '" + header[c] +
                                                "' is '" + fields[c] + "', not a number");
      return v;
    };
    // A whole number that an int holds (reactions.csv writes it again):
    // before 7 December 2026 1.5 was taken as 1, and 1e20 cast to an int
    // out of its range.
    const double number = value(step);
    if (!(number >= 0 && number <= 2147483646.0 && number == std::floor(number)))
      throw file_error(q.load_steps_path, "line " + std::to_string(line_no) + ": column 'step' is '" + fields[step] +
                                              "', not a load step number (pd-solve numbers them 1, 2, 3, ...; the "
                                              "file was edited)");
    q.steps.push_back(static_cast<int>(number));
    // pd-solve writes the table whole from load step 1, after a restart too
    // (its checkpoint keeps the earlier rows): another first step is rows
    // taken out, which a run without summary.json has no count to show.
    if (q.steps.size() == 1 && q.steps.back() != 1)
      throw file_error(q.load_steps_path, "line " + std::to_string(line_no) + ": the first load step is " +
                                              fields[step] + ", and pd-solve numbers them from 1: the rows before "
                                              "it are missing (the file was cut or edited)");
    // pd-solve numbers the load steps 1, 2, 3, ...: a gap is a row taken out.
    if (q.steps.size() > 1 && q.steps.back() != q.steps[q.steps.size() - 2] + 1)
      throw file_error(q.load_steps_path, "line " + std::to_string(line_no) + ": load step " +
                                              std::to_string(q.steps.back()) + " after load step " +
                                              std::to_string(q.steps[q.steps.size() - 2]) +
                                              ": a row is missing or repeated (the file was cut or edited)");
    q.load_factors.push_back(value(factor));
    const double d = value(damage);
    if (d < -1e-6 || d > 1 + 1e-6)
      throw file_error(q.load_steps_path, "line " + std::to_string(line_no) + ": max_damage " + fields[damage] +
                                              " is outside [0, 1]");
    q.max_damage.push_back(std::clamp(d, 0.0, 1.0));
    for (std::size_t r = 0; r < reaction_columns.size(); ++r) q.reactions[r].values.push_back(value(reaction_columns[r]));
  }
}

// The state of `path`: final_state.vtp, or the last snapshot `listed` in the collection.
void read_state(QuasiStaticData& q, const std::string& path, bool final_state, const SnapshotEntry* listed = nullptr) {
  auto poly = read_vtp_quietly(path, listed ? snapshot_role(*listed)
                                            : "the run's final state, which pd-post reads; give the folder that "
                                              "pd-solve -o wrote");
  q.state_path = path;
  q.final_state = final_state;
  read_points(poly, path, q.x, q.y);
  q.damage = checked_damage(read_point_array(poly, path, results::damage, true), path, results::damage);
  if (!read_vector_array(poly, path, results::displacement, q.ux, q.uy))
    throw file_error(path, std::string("no point array '") + results::displacement + "'");
  q.strain_energy_density = read_point_array(poly, path, results::strain_energy_density, false);
  q.cell_size = checked_sizes(read_point_array(poly, path, results::cell_size, false), path, results::cell_size);
  if (q.cell_size.empty()) {
    // final_state.vtp has the volumes: square cells of that area.
    for (double v : checked_sizes(read_point_array(poly, path, results::volume, false), path, results::volume, true))
      q.cell_size.push_back(std::sqrt(v));
  }
  check_positions_resolved(path, q.x, q.y, q.cell_size);
  // Checked (before 7 December 2026 a load factor of NaN passed the
  // comparison with load_steps.csv's last row and titled the maps "load
  // factor nan", and a spacing or horizon of 0 or NaN was said to be missing).
  const auto factor = read_field_number(poly, path, results::field_load_factor);
  // A snapshot is of the load factor its collection lists; one that records
  // another is another run's (before 7 December 2026 the last snapshot was
  // drawn with its own, unchecked, and one without the field took the
  // table's last load factor, another step's where snapshots are sparser).
  if (listed != nullptr && factor) check_snapshot_time(*listed, *factor, true);
  q.state_load_factor =
      factor ? *factor : listed != nullptr ? listed->time : q.load_factors.empty() ? 0.0 : q.load_factors.back();
  const LengthFields lengths = read_length_fields(poly, path, q.cell_size);
  q.spacing = lengths.spacing.value_or(0.0);
  q.horizon = lengths.horizon.value_or(0.0);
  q.run_id = read_field_text(poly, results::field_run_id);
}

// Median over up to 1000 particles (evenly picked) of the distance to the
// nearest other particle: the lattice spacing of a square lattice.
double median_neighbour_distance(const std::vector<double>& x, const std::vector<double>& y) {
  if (x.size() < 2) return 1.0;
  double xmin = *std::min_element(x.begin(), x.end()), xmax = *std::max_element(x.begin(), x.end());
  double ymin = *std::min_element(y.begin(), y.end()), ymax = *std::max_element(y.begin(), y.end());
  const double start = std::max(std::hypot(xmax - xmin, ymax - ymin), 1e-300) / std::sqrt(static_cast<double>(x.size()));
  NeighborSearch search(x, y);
  std::vector<std::uint32_t> near;
  std::vector<double> nearest;
  const std::size_t stride = std::max<std::size_t>(1, x.size() / 1000);
  for (std::size_t i = 0; i < x.size(); i += stride) {
    for (double r = start;; r *= 2) {
      search.within(x[i], y[i], r, near);
      if (near.size() < 2) continue;
      double best = 1e300;
      for (auto j : near)
        if (j != i) best = std::min(best, std::hypot(x[j] - x[i], y[j] - y[i]));
      nearest.push_back(best);
      break;
    }
  }
  return median(nearest);
}

}  // namespace

QuasiStaticData read_quasi_static_data(const std::string& outdir) {
  require_output_directory(outdir);
  QuasiStaticData q;
  q.outdir = outdir;
  q.load_steps_path = (fs::path(outdir) / results::load_steps_file).string();
  read_load_steps(q);
  // (pd-solve writes the header alone when its first load step fails.)
  if (q.load_factors.empty())
    throw file_error(q.load_steps_path,
                     "no load step in it: the quasi-static run stopped before its first load step ended (pd-solve's "
                     "error line says why: e.g. a first minimisation that did not converge), or is still in it; "
                     "nothing to post-process yet");

  const std::string final_path = (fs::path(outdir) / results::final_state_file).string();
  const auto snapshots = list_snapshots(outdir, RunKind::quasi_static);
  if (fs::exists(final_path)) {
    read_state(q, final_path, true);
  } else if (!snapshots.empty()) {
    read_state(q, snapshots.back().file, false, &snapshots.back());
    q.warnings.push_back("no " + final_path + " (written at the end of a run): the maps show the last snapshot, " +
                         snapshots.back().file + ", at load factor " + std::to_string(q.state_load_factor));
  } else {
    q.warnings.push_back("no " + final_path + " and no snapshots: no maps, only the reactions of load_steps.csv");
  }
  if (!q.state_path.empty()) {
    if (!(q.spacing > 0)) {
      // Snapshots carry neither volumes nor the spacing.
      q.spacing = q.cell_size.empty() ? median_neighbour_distance(q.x, q.y) : median(q.cell_size);
      q.notes.push_back("no 'spacing' field in " + q.state_path + ": the median " +
                        (q.cell_size.empty() ? "distance to the nearest particle" : "cell size") + " is used");
    }
    if (!(q.spacing > 0)) throw file_error(q.state_path, "particles on top of each other: no spacing");
    if (q.cell_size.empty()) q.cell_size.assign(q.size(), q.spacing);
    if (!(q.horizon > 0)) {
      q.horizon = 3 * q.spacing;
      q.notes.push_back("no 'horizon' field in " + q.state_path + ": 3 x spacing is used");
    }
  }
  return q;
}

}  // namespace pd::post
