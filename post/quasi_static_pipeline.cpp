#include "quasi_static_pipeline.hpp"

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "atomic_file.hpp"
#include "error.hpp"
#include "plots.hpp"
#include "report.hpp"
#include "pd/version.hpp"
#include "units.hpp"

namespace fs = std::filesystem;

namespace pd::post {
namespace {

// 6 significant digits: a load factor of 0.30000000000000004 reads 0.3.
std::string number_text(double value) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", value);
  return buf;
}

std::string factor_text(double load_factor) { return "load factor " + number_text(load_factor); }

MapStyle linear_style(const std::vector<double>& values, const std::string& title, const std::string& bar) {
  MapStyle s;
  s.title = title;
  s.bar_label = bar;
  s.vmin = *std::min_element(values.begin(), values.end());
  s.vmax = *std::max_element(values.begin(), values.end());
  if (!(s.vmax > s.vmin)) s.vmax = s.vmin + 1;  // a uniform field
  return s;
}

std::vector<double> in_micrometres(const std::vector<double>& metres) {
  std::vector<double> um(metres.size());
  std::transform(metres.begin(), metres.end(), um.begin(), [](double v) { return v * 1e6; });
  return um;
}

// reactions.csv: the load steps' load factors and reactions, as in load_steps.csv.
void write_reaction_table(const std::string& path, const QuasiStaticData& q) {
  write_atomically(path, [&](std::ofstream& out) {
    out << "step,load_factor";
    for (const auto& c : q.reactions) out << ',' << c.name;
    out << '\n';
    for (std::size_t k = 0; k < q.load_factors.size(); ++k) {
      // As written: the shortest text that reads back to the same double.
      out << q.steps[k] << ',' << shortest_text(q.load_factors[k]);
      for (const auto& c : q.reactions) out << ',' << shortest_text(c.values[k]);
      out << '\n';
    }
  });
}

void write_quasi_static_summary(const std::string& path, const QuasiStaticPostResult& r) {
  const auto& q = r.data;
  write_atomically(path, [&](std::ofstream& out) {
    // `tool` first, as in the dynamic summary: pd-solve recognises pd-post's
    // folder by it when a fresh run clears the earlier run's results.
    out << "{\n  \"tool\": " << json_string(std::string("pd-post ") + pd::version_string) << ",\n";
    out << "  \"mode\": \"quasi_static\",\n";
    out << "  \"input\": " << json_string(q.outdir) << ",\n";
    out << "  \"run\": {\"complete\": " << (r.solver.present ? "true" : "false")
        << ", \"solver_summary\": " << (r.solver.present ? json_string(r.solver.path) : "null")
        << ", \"stop_reason\": " << (r.solver.stop_reason.empty() ? "null" : json_string(r.solver.stop_reason))
        << ", \"load_steps\": " << q.load_factors.size()
        << ", \"last_load_factor\": " << (q.load_factors.empty() ? "null" : json_number(q.load_factors.back()))
        << ", \"last_max_damage\": " << (q.max_damage.empty() ? "null" : json_number(q.max_damage.back()))
        << "},\n";
    out << "  \"state\": {\"file\": " << (q.state_path.empty() ? "null" : json_string(q.state_path))
        << ", \"final_state\": " << (q.final_state ? "true" : "false")
        << ", \"load_factor\": " << json_number(q.state_load_factor)
        << ", \"max_damage\": " << json_number(r.max_damage)
        << ", \"strain_energy_density\": " << (q.strain_energy_density.empty() ? "false" : "true") << "},\n";
    out << "  \"reactions\": [";
    for (std::size_t c = 0; c < q.reactions.size(); ++c) {
      const auto& v = q.reactions[c].values;
      const auto peak = std::max_element(v.begin(), v.end(), [](double a, double b) { return std::abs(a) < std::abs(b); });
      out << (c ? "," : "") << "\n    {\"column\": " << json_string(q.reactions[c].name) << ", \"peak_N\": "
          << (v.empty() ? "null" : json_number(*peak)) << ", \"peak_load_factor\": "
          << (v.empty() ? "null" : json_number(q.load_factors[peak - v.begin()])) << "}";
    }
    out << "\n  ],\n  \"maps\": [";
    for (std::size_t m = 0; m < r.maps.size(); ++m)
      out << (m ? ", " : "") << "{\"requested_load_factor\": " << json_number(r.maps[m].requested)
          << ", \"load_factor\": " << json_number(r.maps[m].used) << ", \"source\": " << json_string(r.maps[m].source)
          << "}";
    out << "],\n";
    write_summary_tail(out, r);
  });
}

// Whether a value of final_state.vtp and the same value in load_steps.csv
// differ by more than single-precision (Float32) rounding: relative 2^-24 for
// each of the two, 4 x FLT_EPSILON with margin. pd-solve writes the state in
// Float64 and the table to 12 significant digits, which differ by far less;
// the looser bound also passes a state file saved again in single precision
// (as the snapshots are stored, or by a viewer), where a refusal would be
// wrong, while the last rows of two runs of other load steps or damage
// differ far beyond it.
bool differ_beyond_float32(double a, double b) {
  return std::abs(a - b) > 4 * FLT_EPSILON * std::max(std::abs(a), std::abs(b));
}

std::string recorded_text(double value) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.12g", value);
  return buf;
}

// final_state.vtp is the state of load_steps.csv's last row: its load factor
// (field 'load_factor') is that row's, and its largest damage that row's
// max_damage. A table of a run before 7 December 2026 carries no run
// identifier, and another run's with the same number of rows passed the row
// count against summary.json (before 6 December 2026 its reactions were
// drawn as this run's, exit 0).
void check_table_ends_at_final_state(const QuasiStaticData& q) {
  if (differ_beyond_float32(q.state_load_factor, q.load_factors.back()))
    throw mixed_runs_error(q.load_steps_path, "ends at load factor " + recorded_text(q.load_factors.back()) +
                                                  " (column 'load_factor', load step " + std::to_string(q.steps.back()) +
                                                  "), and " + q.state_path + " is of load factor " +
                                                  recorded_text(q.state_load_factor) + " (field 'load_factor')");
  const double largest = q.damage.empty() ? 0.0 : *std::max_element(q.damage.begin(), q.damage.end());
  if (differ_beyond_float32(largest, q.max_damage.back()))
    throw mixed_runs_error(q.load_steps_path, "ends at max_damage " + recorded_text(q.max_damage.back()) +
                                                  " (column 'max_damage', load step " + std::to_string(q.steps.back()) +
                                                  "), and the largest damage of " + q.state_path + " is " +
                                                  recorded_text(largest) + " (point array 'damage')");
}

}  // namespace

QuasiStaticPostResult run_quasi_static_post(const PostOptions& o) {
  QuasiStaticPostResult r;
  r.solver = read_solver_summary(o.outdir);
  r.data = read_quasi_static_data(o.outdir);
  const QuasiStaticData& q = r.data;
  check_same_run_id(r.solver.path, r.solver.run_id, "\"run_id\"", q.state_path, q.run_id);
  // The table and the collection against the state (summary.json where there
  // is none), before their contents: another run's table is named as such.
  if (!q.run_id.empty())
    check_run_tables(o.outdir, q.state_path, q.run_id);
  else
    check_run_tables(o.outdir, r.solver.path, r.solver.run_id);
  // A finished run's table holds every load step it made: fewer rows are a cut or edited file.
  if (r.solver.load_steps >= 0 && static_cast<std::size_t>(r.solver.load_steps) != q.steps.size())
    throw file_error(q.load_steps_path, "has " + std::to_string(q.steps.size()) + " load steps, " + r.solver.path +
                                            " says the run made " + std::to_string(r.solver.load_steps) +
                                            ": the table was cut or edited (pd-solve writes both whole)");
  if (q.final_state) check_table_ends_at_final_state(q);
  r.notes = q.notes;
  r.warnings = q.warnings;
  if (!r.solver.present) {
    char covers[160];
    std::snprintf(covers, sizeof covers, "load_steps.csv has %zu load steps%s", q.load_factors.size(),
                  q.load_factors.empty() ? "" : (", the last at " + factor_text(q.load_factors.back())).c_str());
    r.warnings.insert(r.warnings.begin(), incomplete_run_warning(o.outdir, covers));
  }
  if (!o.map_times.empty()) r.notes.push_back("--times is for dynamic runs; a quasi-static run takes --load-factors");
  // The crack analysis of dynamic runs: say so rather than drop its options without a word.
  std::vector<std::string> crack_options;
  if (o.threshold_given) crack_options.push_back("--threshold");
  if (o.window_steps != 0) crack_options.push_back("--window");
  if (o.window_time > 0) crack_options.push_back("--window-time");
  if (o.angle_length_given) crack_options.push_back("--angle-length");
  if (!o.boxes_file.empty()) crack_options.push_back("--boxes");
  if (!o.pores_file.empty()) crack_options.push_back("--pores");
  if (!crack_options.empty()) {
    std::string list;
    for (std::size_t k = 0; k < crack_options.size(); ++k)
      list += (k == 0 ? "" : k + 1 == crack_options.size() ? " and " : ", ") + crack_options[k];
    r.notes.push_back(list + (crack_options.size() == 1 ? " is" : " are") +
                      " for crack tracking in dynamic runs: not used" +
                      (r.solver.damage_off ? std::string(" (the run had damage off)")
                                           : " (a quasi-static run's damage is in damage_final.png and in "
                                             "load_steps.csv's max_damage)"));
  }
  // Sampled before any file is written, so that a line off the plate is refused with nothing half-done.
  if (o.line) {
    if (q.state_path.empty()) throw file_error(q.load_steps_path, "--line needs a state: no final_state.vtp, no snapshot");
    add_line_profile(r, {q.x, q.y, q.ux, q.uy, q.damage}, *o.line, q.spacing, o.line_offset, q.horizon);
  }
  if (!q.damage.empty()) r.max_damage = *std::max_element(q.damage.begin(), q.damage.end());

  r.postdir = make_post_directory(o, r.notes);
  auto out = [&](const std::string& name) { return (fs::path(r.postdir) / name).string(); };
  auto picture = [&](const Canvas& c, const std::string& name) {
    c.write_png(out(name));
    r.pictures.push_back(out(name));
  };

  // Maps of one state: displacement components, damage, strain energy density.
  auto draw_state = [&](const std::vector<double>& ux, const std::vector<double>& uy,
                        const std::vector<double>& damage, const std::vector<double>& sed, double load_factor,
                        const std::string& source, const std::string& tag) {
    const MapParticles particles{q.x, q.y, q.cell_size};
    const std::string at = " at " + factor_text(load_factor) + source;
    picture(draw_particle_map(particles, in_micrometres(ux), linear_style(in_micrometres(ux), "u_x" + at, "u_x um"),
                              {}, 0, {}),
            "displacement_x_" + tag + ".png");
    picture(draw_particle_map(particles, in_micrometres(uy), linear_style(in_micrometres(uy), "u_y" + at, "u_y um"),
                              {}, 0, {}),
            "displacement_y_" + tag + ".png");
    picture(draw_particle_map(particles, damage, damage_style("damage" + at), {}, 0, {}), "damage_" + tag + ".png");
    if (!sed.empty())
      picture(draw_particle_map(particles, sed, strain_energy_style(sed, "strain energy density" + at), {}, 0, {}),
              "strain_energy_" + tag + ".png");
  };

  // A dynamic run with damage off is refused (no crack to track); a
  // quasi-static one still has its maps, whose damage says less than usual.
  if (r.solver.damage_off && !q.state_path.empty())
    r.notes.push_back(std::string("the run had damage off (the scene's effects.damage = false): no bond broke "
                                  "under load; ") +
                      (r.max_damage > 0 ? "the damage maps show the pre-cracks' cut bonds only"
                                        : "the damage maps are 0 everywhere"));
  if (!q.state_path.empty()) {
    draw_state(q.ux, q.uy, q.damage, q.strain_energy_density, q.state_load_factor,
               q.final_state ? "" : " (last snapshot)", "final");
    r.main_picture = out("displacement_y_final.png");
    if (q.strain_energy_density.empty())
      r.notes.push_back("no 'strain_energy_density' in " + q.state_path +
                        " (pd-solve does not write it for quasi-static runs): no strain-energy map; the "
                        "displacement maps and damage_final.png show the state instead");
  }

  const auto snapshots = list_snapshots(o.outdir, RunKind::quasi_static);
  if (!o.map_load_factors.empty() && snapshots.empty())
    r.notes.push_back("no snapshots: no maps at the given load factors");
  // The load factors the run went through, from the unloaded start (0): a
  // map asked for outside them shows a state the run never reached.
  double run_min = 0, run_max = 0;
  for (double lf : q.load_factors) run_min = std::min(run_min, lf), run_max = std::max(run_max, lf);
  for (const auto& e : snapshots) run_min = std::min(run_min, e.time), run_max = std::max(run_max, e.time);
  // Load factors are written to 17 digits: those of one step differ by round-off only (0.30000000000000004).
  const double same = 1e-9 * std::max(std::abs(run_min), std::abs(run_max));
  for (double lf : o.map_load_factors) {
    if (snapshots.empty()) break;
    const auto nearest = &nearest_snapshot(snapshots, lf);
    // A run that unloads passes a load factor more than once: say which snapshot is drawn.
    std::string others;
    for (const auto& e : snapshots)
      if (&e != nearest && e.time == nearest->time) others += (others.empty() ? "" : ", ") + e.file;
    if (!others.empty())
      r.notes.push_back(factor_text(nearest->time) + " is in more than one snapshot: the map shows " +
                        nearest->file + " (the first), not " + others);
    const SnapshotFields s = read_snapshot(*nearest, {q.state_path, q.x, q.y, q.cell_size});
    check_same_run_id(nearest->file, s.run_id, std::string("field '") + results::field_run_id + "'", q.state_path,
                      q.run_id);
    if (s.ux.empty()) throw file_error(nearest->file, "no point array 'displacement'");
    r.maps.push_back({lf, s.time, "snapshot " + nearest->file});
    // As for --times: the map is named by the load factor drawn; say when it is not the one asked for.
    const std::string drawn = nearest->file + ", at " + factor_text(s.time);
    if (lf < run_min - same || lf > run_max + same)
      r.warnings.push_back("--load-factors " + number_text(lf) + " is outside the run's load factors (" +
                           number_text(run_min) + " to " + number_text(run_max) +
                           "): the maps show the nearest snapshot, " + drawn);
    else if (std::abs(s.time - lf) > same)
      r.notes.push_back("--load-factors " + number_text(lf) + ": no snapshot at that load factor; the maps show "
                        "the nearest, " + drawn);
    draw_state(s.ux, s.uy, s.damage, s.strain_energy_density, s.time, " (snapshot)", load_factor_tag(s.time));
  }

  r.reaction_table = out("reactions.csv");
  write_reaction_table(r.reaction_table, q);
  // Every reaction column that is not zero throughout (a free direction).
  std::vector<Series> series;
  for (const auto& c : q.reactions) {
    if (std::all_of(c.values.begin(), c.values.end(), [](double v) { return v == 0; })) continue;
    series.push_back({c.name, branch_style(static_cast<int>(series.size())), q.load_factors, c.values});
  }
  picture(draw_line_plot(series, "load factor", "reaction (N)", "reactions against load factor"), "reactions.png");
  if (r.main_picture.empty()) r.main_picture = out("reactions.png");

  if (o.line) {
    write_line_profile(out("line_profile.csv"), r.line);
    picture(draw_line_profile(r.line, "jump of displacement across the line at " + factor_text(q.state_load_factor)),
            "line_profile.png");
  }
  write_quasi_static_summary(out("summary.json"), r);
  return r;
}

}  // namespace pd::post
