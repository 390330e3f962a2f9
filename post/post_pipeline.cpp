#include "post_pipeline.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <optional>

#include "atomic_file.hpp"
#include "error.hpp"
#include "plots.hpp"
#include "report.hpp"
#include "results_format.hpp"
#include "run_lock.hpp"
#include "statistics.hpp"
#include "units.hpp"

namespace fs = std::filesystem;

namespace pd::post {
namespace {

std::string time_text(double seconds) {
  char buf[48];
  std::snprintf(buf, sizeof buf, "%.4g us", seconds * 1e6);
  return buf;
}

// How far arrival.vtp goes when the run has not ended. pd-solve writes it at
// the start of the time steps, at every checkpoint and, stopping as
// unstable, with the last good state: at step 0 it is the start's (a run
// killed before its first checkpoint, or run without checkpoints).
std::string arrival_reach(const ArrivalData& d) {
  const bool start = d.end_step == 0 || (d.end_step < 0 && d.end_time == 0);
  char buf[256];
  std::snprintf(buf, sizeof buf, "arrival.vtp is from t = %.4g us%s (%s)", d.end_time * 1e6,
                d.end_step >= 0 ? (", step " + std::to_string(d.end_step)).c_str() : "",
                start ? "the start of the run: it stopped before any checkpoint"
                      : "the last checkpoint, or the last good state of a run stopped as unstable");
  return buf;
}

// What the output directory covers when the run has not ended.
std::string arrival_coverage(const ArrivalData& d) {
  return arrival_reach(d) + ", so the crack is tracked up to then";
}

}  // namespace

void create_output_folder(const std::string& dir, const std::string& shown, const std::string& what) {
  std::error_code ec;
  // (create_directories would only say "Not a directory" for a file of that name.)
  if (fs::exists(dir, ec) && !fs::is_directory(dir, ec)) throw Error(shown + ": a file, not a folder (" + what + ")");
  fs::create_directories(dir, ec);
  if (ec || !fs::is_directory(dir, ec))
    throw Error(shown + ": cannot create " + what + (ec ? ": " + ec.message() : std::string()));
}

namespace {
void refuse_folder_of_other_results(const std::string& dir, const std::string& shown) {
  // A solver run's folder (another run's, given to -o) or a summary.json that
  // is not pd-post's (a user's): pd-post's files would replace them, or sit
  // beside them and make the folder read as pd-post's (before the second
  // sitting of 5 December 2026, `pd-post A -o B` replaced run B's summary.json).
  // Looked for in the resolved folder: "RUN/new/.." is RUN once -o's
  // folders are made, though RUN/new/../summary.json does not exist before.
  const fs::path folder = resolved_path(dir);
  std::error_code ec;
  for (const char* name : {results::energy_file, results::arrival_file, results::load_steps_file,
                           results::final_state_file, results::snapshot_collection, "checkpoint.bin"})
    if (fs::exists(folder / name, ec))
      throw Error(shown + " holds a solver run's results (" + (fs::path(dir) / name).string() +
                  "): pd-post's summary.json and tables would replace or sit beside them; give a folder of its own");
  const fs::path summary = fs::path(dir) / results::summary_file;
  if (fs::exists(folder / results::summary_file, ec) && results::post_outputs_in(folder.string()).empty())
    throw Error(shown + ": " + summary.string() + " is not pd-post's (it does not name pd-post as its tool): pd-post "
                "would replace it; give a folder of its own, or move the file");
}
}  // namespace

namespace {
// The first of pd-solve's result files in `folder` (load_steps.csv,
// final_state.vtp, its checkpoint, a summary.json that names pd-solve as its
// tool), none if it holds none: pd-post's own summary.json there is not one.
std::optional<fs::path> solver_file_in(const fs::path& folder) {
  std::error_code ec;
  for (const char* name : {results::load_steps_file, results::final_state_file, "checkpoint.bin"})
    if (fs::exists(folder / name, ec)) return folder / name;
  if (results::summary_by_solver(folder / results::summary_file)) return folder / results::summary_file;
  return std::nullopt;
}
}  // namespace

namespace {
// The cell size where the crack runs: the median cell of the particles that
// reached the threshold. The speed window spans a number of such cells at
// c_R; a refined run's particle file gives its coarse spacing, while its
// time step is the finest level's and its crack runs in the finest cells
// (before the second sitting of 5 December 2026 its window was 2^levels
// times too long: 1,926 steps for a 95-step run at six levels). Elsewhere
// the file's spacing, as the crack's cells are its squares.
double crack_path_spacing(const ArrivalData& d, std::vector<std::string>& notes) {
  std::vector<double> cells;
  for (std::size_t i = 0; i < d.arrival.size() && i < d.cell_size.size(); ++i)
    if (d.arrival[i] >= 0) cells.push_back(d.cell_size[i]);
  if (cells.empty()) return d.spacing;
  const double path = median(cells);
  if (path >= 0.9 * d.spacing) return d.spacing;
  char text[240];
  std::snprintf(text, sizeof text,
                "speed window sized by the cells the crack crossed, %.4g mm (their median), not the particle file's "
                "spacing %.4g mm: a refined run's crack runs in its fine cells",
                path * 1e3, d.spacing * 1e3);
  notes.push_back(text);
  return path;
}
}  // namespace

std::string make_post_directory(const PostOptions& o, std::vector<std::string>& notes) {
  const std::string dir = o.postdir.empty() ? (fs::path(o.outdir) / "post").string() : o.postdir;
  // pd-post's summary.json and tables would replace the solver's files.
  if (same_path(dir, o.outdir))
    throw Error("-o " + dir + " is the run's own folder: pd-post's summary.json would replace the solver's; "
                "give a folder of its own (default: " + (fs::path(o.outdir) / "post").string() + ")");
  // The run's snapshots/ (docs/formats.md): pd-post's files would sit among
  // its snapshots and pass for the solver's (before 6 December 2026, -o
  // OUTDIR/snapshots wrote summary.json there, exit 0).
  const std::string default_dir = (fs::path(o.outdir) / results::post_folder).string();
  const std::string snapshots = (fs::path(o.outdir) / results::snapshot_folder).string();
  if (path_within(dir, snapshots))
    throw Error("-o " + clipped(dir) + " is inside the run's " + results::snapshot_folder + "/ folder (" +
                clipped(snapshots) + "), which pd-solve writes: pd-post's summary.json and pictures would sit among "
                "the run's files; give a folder of its own (default: " + default_dir + ")");
  // OUTDIR/quasi_static, where pd-solve writes a switching run's
  // quasi-static part. Where it holds pd-solve's results, that part is a run
  // of its own for pd-post: this run's files would sit among that part's, or
  // in its pd-post folder (quasi_static/post), and pass for them. The folder
  // itself in any run: a fresh pd-solve run into OUTDIR removes the results
  // there and stops at a summary.json it did not write, as pd-post's. A
  // folder inside it where no part is (a plain quasi-static or dynamic run)
  // is pd-post's to use (before 6 December 2026 every folder inside was
  // refused, as one pd-solve writes).
  const fs::path part = fs::path(o.outdir) / results::quasi_static_part_folder;
  if (path_within(dir, part.string())) {
    if (const auto file = solver_file_in(part))
      throw Error("-o " + clipped(dir) + " is inside " + clipped(part.string()) + ", which holds pd-solve's results (" +
                  clipped(file->string()) + "; a switching run writes its quasi-static part there), a run of its own "
                  "for pd-post (pd-post " + clipped(part.string()) + " writes its files in " +
                  clipped((part / results::post_folder).string()) + "): this run's summary.json and pictures would "
                  "pass for that run's; give a folder of its own (default: " + default_dir + ")");
    if (same_path(dir, part.string()))
      throw Error("-o " + clipped(dir) + " is the folder where pd-solve writes a switching run's quasi-static part: "
                  "pd-post's summary.json there would stop the next pd-solve run into " + clipped(o.outdir) +
                  " (a file of a result's name that pd-solve did not write); give a folder of its own (default: " +
                  default_dir + ")");
  }
  const std::string shown = o.postdir.empty() ? clipped(dir) : "-o " + clipped(dir);
  refuse_folder_of_other_results(dir, shown);
  create_output_folder(dir, shown, "the post directory");
  // A killed pd-post leaves its temporary files here (.tmp.PID.NAME), which nothing else would remove.
  const std::size_t stale = remove_stale_temporaries(dir).size();
  if (stale > 0)
    notes.push_back("removed " + std::to_string(stale) + " temporary file" + (stale == 1 ? "" : "s") +
                    " left by a killed run in " + dir);
  // pd-post's files of an earlier run of pd-post here: the new ones replace
  // most of them, but maps of other --times or --load-factors, or a line
  // profile this run does not draw, would stay and pass for this run's.
  // summary.json goes first, and is written last: until then the folder is
  // not a finished pd-post folder.
  auto earlier = pd::results::post_outputs_in(dir);
  std::stable_partition(earlier.begin(), earlier.end(),
                        [](const fs::path& f) { return f.filename() == pd::results::summary_file; });
  for (const auto& file : earlier) {
    std::error_code ec;
    fs::remove(file, ec);
    if (ec) throw Error(file.string() + ": cannot remove this file of an earlier pd-post run: " + ec.message());
  }
  return dir;
}

std::string time_tag(double seconds) {
  char buf[48];
  std::snprintf(buf, sizeof buf, "%gus", seconds * 1e6);
  return buf;
}

std::string load_factor_tag(double load_factor) {
  char buf[48];
  std::snprintf(buf, sizeof buf, "lf%g", load_factor);
  return buf;
}

PostResult analyse(const PostOptions& o) {
  // A run measured against itself has no damage outside the band whatever its
  // grid shows: the comparison would report 0 as a finding (before 6 December
  // 2026 it did, with no word). Compared resolved: OUTDIR/. or a link to it.
  if (!o.reference_dir.empty() && same_path(o.reference_dir, o.outdir))
    throw Error("--reference " + clipped(o.reference_dir) + " is this run's own folder (OUTDIR " + clipped(o.outdir) +
                "): a run compared with itself has no damage outside the band; give another run of the same plate "
                "(e.g. the fine run), or leave --reference out");
  PostResult r;
  r.solver = read_solver_summary(o.outdir);
  const fs::path arrival = fs::path(o.outdir) / results::arrival_file;
  if (fs::is_directory(o.outdir) && !fs::exists(arrival) && !r.solver.present) {
    // A run that has not reached its first step has its lock (while it runs)
    // or its quasi-static rows; a folder with none of pd-solve's files is
    // another folder (a run's snapshots/, its post/: before the second
    // sitting of 5 December 2026 said to be a run that had not started).
    // A switching scene (quasi_static.then = "dynamic") whose dynamic part
    // has not begun holds its quasi-static part only, in its own folder
    // (before, without a surface-correction cache beside it, said to be no
    // run's folder at all).
    // (pd-solve's files there, not pd-post's own summary.json: before 7
    // December 2026 any summary.json made the folder a switching run's.)
    const fs::path part = fs::path(o.outdir) / results::quasi_static_part_folder;
    if (solver_file_in(part))
      throw file_error(arrival.string(),
                       "file not found: this switching run's dynamic part stopped (or has not begun) before its "
                       "first time step; its quasi-static part is in " + part.string() + ": run pd-post on that folder");
    bool run_files = false;
    for (const char* name : {run_lock_file, results::energy_file, results::load_steps_file,
                             results::snapshot_collection, "checkpoint.bin"})
      run_files = run_files || fs::exists(fs::path(o.outdir) / name);
    // The surface-correction cache alone: a run was refused after its
    // set-up made it (a time step above the stable limit into a folder that
    // existed), which is no run that stopped (before 7 December 2026 said to be one).
    if (!run_files && fs::exists(fs::path(o.outdir) / "surface_correction.cache"))
      throw file_error(o.outdir, "no run's results: the folder holds pd-solve's surface-correction cache only (kept "
                                 "for the next run of the same plate), which a run refused at its set-up leaves; "
                                 "its log says why it was refused: run pd-solve into this folder again once that is "
                                 "mended");
    if (!run_files) {
      const fs::path parent = fs::absolute(o.outdir).lexically_normal().parent_path();
      const bool parent_is_run = fs::exists(parent / results::arrival_file) || fs::exists(parent / results::summary_file);
      throw file_error(o.outdir, "not a solver output directory: none of pd-solve's files (arrival.vtp, summary.json, "
                                 "energy.csv) is there" +
                                     (parent_is_run ? "; the folder above it, " + parent.string() + ", is a run's"
                                                    : std::string("; give the folder that pd-solve -o wrote")));
    }
    // The lock tells a run still setting up from one that stopped (before 7
    // December 2026 both were "stopped (or is still setting up)").
    const RunLockStatus lock = run_lock_status(o.outdir);
    const std::string state =
        lock.state == RunLockStatus::State::held
            ? unfinished_run_state(lock) + " and has not reached its first time step: run pd-post again once it has"
        : lock.state == RunLockStatus::State::unknown
            ? "the run stopped (or is still setting up) before its first time step"
            : "the run stopped before its first time step (killed, or failed)";
    throw file_error(arrival.string(), "file not found: pd-solve writes it when the time steps start, at every "
                                       "checkpoint and at the end, and there is no summary.json either: " + state);
  }
  r.data = read_arrival_data(o.outdir, o.threshold);
  const ArrivalData& d = r.data;
  check_same_run(r.solver, d);
  check_run_tables(o.outdir, d.path, d.run_id);
  r.notes = d.notes;
  if (!r.solver.present) r.warnings.push_back(incomplete_run_warning(o.outdir, arrival_coverage(d)));
  // A run stopped before its crack started: say so, rather than only that
  // the crack is empty (which, for a finished run, means a load too small).
  const bool no_crack = std::none_of(d.arrival.begin(), d.arrival.end(), [](double t) { return t >= 0; });
  if (!r.solver.present && no_crack)
    throw file_error(d.path, "no particle has reached the damage threshold yet (array '" +
                                 results::arrival_array_name(d.threshold) + "' is -1 everywhere) in this " +
                                 incomplete_run_warning(o.outdir, arrival_reach(d)) +
                                 ": no crack to track yet; run pd-post again once the run has gone further "
                                 "(a run with checkpoints continues with pd-solve --restart)");
  // Likewise a run without damage: not a load too small.
  if (r.solver.damage_off && no_crack)
    throw file_error(r.solver.path, "\"effects\": {\"damage\": false}: the run had damage off (the scene's "
                                    "effects.damage = false), so no bond broke and there is no crack to track");
  r.max_damage = d.damage.empty() ? 0.0 : *std::max_element(d.damage.begin(), d.damage.end());

  // The line first: one off the plate is refused before the crack analysis.
  if (o.line) {
    if (d.ux.empty()) throw file_error(d.path, "no point array 'displacement' for the values along --line");
    add_line_profile(r, {d.x, d.y, d.ux, d.uy, d.damage}, *o.line, d.spacing, o.line_offset, d.horizon);
  }

  r.model = simulated_model(d, r.solver, r.notes);
  r.rayleigh = rayleigh_speed(r.model);
  r.rayleigh_speed = r.rayleigh.speed;
  if (d.material_poisson_ratio)
    r.material_rayleigh = rayleigh_speed(d.youngs_modulus, d.density, *d.material_poisson_ratio, r.model.plane);
  r.window = choose_speed_window(d.time_step, crack_path_spacing(d, r.notes), r.rayleigh_speed, o.window_steps,
                                 o.window_time, r.warnings, d.path);
  r.window_steps = r.window.steps;
  r.window_seconds = r.window.seconds;
  if (r.window.requested && d.end_time > 0 && r.window_seconds > d.end_time) {
    char text[200];
    std::snprintf(text, sizeof text,
                  "the speed window (%.3g us) is longer than the run (%.3g us): no tip path spans one, so no "
                  "crack speed is measured (crack_speed.csv has no rows)",
                  r.window_seconds * 1e6, d.end_time * 1e6);
    // Given in time, most likely in another unit (--window-time 2 for 2 us),
    // as a time of --times past the end.
    r.warnings.push_back(text + std::string(o.window_time > 0 ? "; --window-time is in s, or give the unit "
                                                                "(--window-time 2us)"
                                                              : ""));
  }
  if (!(o.angle_length > 0))
    throw Error("--angle-length " + shortest_text(o.angle_length * 1e3) + " mm: must be a positive length");
  if (o.angle_length_given && !d.x.empty()) {
    // From the spacing (a shorter fit holds no particle but the branching
    // point's) to the plate's diagonal (a longer one is the same fit over
    // each child's whole length): before 7 December 2026 1e-300m and 1e300m
    // were taken, most likely a unit gone wrong.
    const PlateExtent plate = plate_extent(d);
    const double diagonal = std::hypot(plate.x_max - plate.x_min, plate.y_max - plate.y_min);
    const double shortest = std::min(d.spacing, diagonal);
    check_length_in_range(o.angle_length, "--angle-length", shortest, "run's particle spacing", diagonal,
                          "plate's diagonal", "the spacing to the plate's diagonal", "2mm");
  }
  r.angle_length = o.angle_length;

  if (!o.pores_file.empty()) {
    r.pores = read_pores_csv(o.pores_file);
    r.pore_source = "file " + o.pores_file;
    check_pore_file(o.pores_file, r.pores, d, r.warnings);
    if (r.pores.empty()) r.warnings.push_back(o.pores_file + " lists no pore: no pore visits are looked for");
  } else {
    std::vector<Pore> ignored;
    r.pores = detect_pores(d, &ignored, &r.warnings);
    if (!ignored.empty()) {
      double smallest = ignored.front().radius, largest = smallest;
      for (const auto& p : ignored) smallest = std::min(smallest, p.radius), largest = std::max(largest, p.radius);
      char radii[64], place[96], text[440];
      if (largest > smallest * 1.001)
        std::snprintf(radii, sizeof radii, "%.3g to %.3g", smallest * 1e3, largest * 1e3);
      else
        std::snprintf(radii, sizeof radii, "%.3g", smallest * 1e3);
      const bool one = ignored.size() == 1;
      std::snprintf(place, sizeof place, one ? "at (%.4g, %.4g) mm" : "(first at (%.4g, %.4g) mm)",
                    ignored.front().x * 1e3, ignored.front().y * 1e3);
      std::snprintf(text, sizeof text,
                    "%zu hole%s of radius %s mm %s %s not counted as %s: below %g cell sizes in radius, too few "
                    "cells across to tell from a gap of the grid; give --pores FILE to count %s, or use a finer grid",
                    ignored.size(), one ? "" : "s", radii, place, one ? "is" : "are", one ? "a pore" : "pores",
                    smallest_pore_cells, one ? "it" : "them");
      r.notes.push_back(text);
    }
    r.pore_source =
        "detected from the particle layout (holes: round ones as circles of equal area, others by their outline)";
  }

  const BranchSettings settings = default_branch_settings(d, r.window_seconds, o.angle_length);
  if (!o.boxes_file.empty()) {
    r.network = branches_from_boxes(d, read_boxes_csv(o.boxes_file), o.boxes_file, r.warnings);
    r.notes.push_back("branches from the boxes in " + o.boxes_file);
  } else {
    r.network = find_branches(d, r.pores, settings);
  }
  // Within a few horizons of the branching point the damage of the two
  // children is one blob: a fit over so short a length measures the blob.
  if (!r.network.branchings.empty() && o.angle_length < 4 * d.horizon) {
    char text[240];
    std::snprintf(text, sizeof text,
                  "branching angles are fitted over %.3g mm, %.1f horizons: that close to the branching point "
                  "the children's damage overlaps; --angle-length of at least 4 horizons (%.3g mm) measures "
                  "the branches",
                  o.angle_length * 1e3, o.angle_length / d.horizon, 4 * d.horizon * 1e3);
    r.warnings.push_back(text);
  }
  r.tips = track_tips(r.network, d);
  r.pore_visits = find_pore_visits(r.network.branches, r.tips, r.pores, d, settings.pore_ring);
  // A tip that jumped across a pore moves 2R in one window: flag those
  // windows so that they do not count as crack speed.
  for (const auto& v : r.pore_visits) {
    auto& restarts = r.network.branches[v.branch].pore_restart_times;
    if (v.jumped && std::find(restarts.begin(), restarts.end(), v.restart_time) == restarts.end())
      restarts.push_back(v.restart_time);
  }
  for (std::size_t b = 0; b < r.network.branches.size(); ++b) {
    auto s = crack_speeds(r.tips[b], r.network.branches[b], r.window_steps, d.horizon);
    r.speeds.insert(r.speeds.end(), s.begin(), s.end());
  }
  // A crack without a single speed window (summary.json's speeds are then
  // null, not 0 m/s): why, and what measures it.
  if (!r.network.branches.empty() && speed_stats(r.speeds).samples == 0) {
    std::size_t longest = 0;
    for (const auto& tip : r.tips) longest = std::max(longest, tip.time.size());
    r.warnings.push_back(
        "no crack speed measured: " +
        (longest <= static_cast<std::size_t>(r.window_steps)
             ? "the longest tip path spans " + std::to_string(longest > 0 ? longest - 1 : 0) +
                   " steps, fewer than the speed window of " + std::to_string(r.window_steps) + " steps"
             : std::string("every speed window crosses a pore or a tip jump")) +
        "; a shorter --window or --window-time measures speeds over fewer cells");
  }

  if (!o.reference_dir.empty()) {
    const SolverSummary reference_summary = read_solver_summary(o.reference_dir);
    // A quasi-static run has no arrival.vtp: before 7 December 2026 it was
    // "REF/arrival.vtp: file not found (pd-post needs the solver's arrival-time file)".
    if (detect_run_kind(o.reference_dir, reference_summary) == RunKind::quasi_static)
      throw Error("--reference " + clipped(o.reference_dir) + " is a quasi-static run: --reference compares the "
                  "damage of dynamic runs (their arrival.vtp); give a dynamic run of the same plate");
    const ArrivalData reference = read_arrival_data(o.reference_dir, o.threshold);
    check_same_run(reference_summary, reference);
    check_run_tables(o.reference_dir, reference.path, reference.run_id);
    // The same plate at another resolution: the particles' extents agree to
    // about a cell (the cells' centres lie half a cell inside the edges).
    const auto extent = [](const ArrivalData& a) {
      return std::array<double, 4>{*std::min_element(a.x.begin(), a.x.end()), *std::max_element(a.x.begin(), a.x.end()),
                                   *std::min_element(a.y.begin(), a.y.end()), *std::max_element(a.y.begin(), a.y.end())};
    };
    const auto e = extent(d), e_ref = extent(reference);
    const double tolerance = std::max(d.spacing, reference.spacing);
    for (int k = 0; k < 4; ++k)
      if (std::abs(e[k] - e_ref[k]) > tolerance) {
        char text[400];
        std::snprintf(text, sizeof text,
                      "--reference: not the same plate: its particles span x %g to %g m, y %g to %g m, this run's "
                      "x %g to %g m, y %g to %g m",
                      e_ref[0], e_ref[1], e_ref[2], e_ref[3], e[0], e[1], e[2], e[3]);
        throw Error(text);
      }
    const double band = o.band > 0 ? o.band : 2 * std::max(d.horizon, reference.horizon);
    r.comparison = compare_damage(d, reference, band, o.damage_level);
    // A reference that is not the whole of a finished run's crack makes this
    // run's damage beyond it look spurious.
    if (!reference_summary.present)
      r.warnings.push_back("--reference: " + incomplete_run_warning(o.reference_dir, arrival_reach(reference)) +
                           ", so its damage is compared as it was then");
    // Nothing of this run at the level: "0 of 0 damaged particles lie
    // farther than the band" read as a finding (before 7 December 2026).
    if (r.comparison->damaged == 0) {
      char text[240];
      std::snprintf(text, sizeof text,
                    ") has damage %g or more (its largest is %g): there is nothing to compare; a lower "
                    "--damage-level counts its fainter damage",
                    o.damage_level, r.max_damage);
      r.warnings.push_back("--reference: no particle of this run (" + d.path + text);
    }
    if (r.comparison->reference_damaged == 0) {
      char text[200];
      std::snprintf(text, sizeof text,
                    " has damage %g or more (its largest is %g): every damaged particle of this run counts as "
                    "outside the band",
                    o.damage_level, *std::max_element(reference.damage.begin(), reference.damage.end()));
      r.warnings.push_back("--reference: no particle of " + reference.path + text);
    }
    if (std::abs(reference.end_time - d.end_time) > 0.1 * d.end_time) {
      char text[200];
      std::snprintf(text, sizeof text,
                    " ends at t = %.4g us, this run at %.4g us (more than 10 %% apart): the two cracks are compared "
                    "at different times",
                    reference.end_time * 1e6, d.end_time * 1e6);
      r.warnings.push_back("--reference: " + reference.path + text);
    }
  }
  if (!o.map_load_factors.empty())
    r.notes.push_back("--load-factors is for quasi-static runs; a dynamic run takes --times (in s, or with a unit)");
  // A time past the run's end is most likely in another unit (--times 5 for 5 us).
  for (double t : o.map_times)
    if (d.end_time > 0 && t > 1.5 * d.end_time) {
      r.warnings.push_back("--times " + time_text(t) + " is after the run's end at " + time_text(d.end_time) +
                           ": times are in s, or give the unit (--times 5us)");
      break;
    }
  return r;
}

PostResult run_post(const PostOptions& o) {
  PostResult r = analyse(o);
  const ArrivalData& d = r.data;
  r.postdir = make_post_directory(o, r.notes);
  auto out = [&](const std::string& name) { return (fs::path(r.postdir) / name).string(); };

  const double forever = std::numeric_limits<double>::infinity();
  char threshold_text[32];
  std::snprintf(threshold_text, sizeof threshold_text, "%.2f", d.threshold);
  auto picture = [&](const Canvas& c, const std::string& name) {
    c.write_png(out(name));
    r.pictures.push_back(out(name));
  };

  r.main_picture = out("damage_final.png");
  picture(draw_particle_map(d, d.damage,
                            damage_style("damage at " + time_text(d.end_time) + ", tips at damage " +
                                         threshold_text),
                            r.tips, forever, r.pores),
          "damage_final.png");
  if (!d.strain_energy_density.empty())
    picture(draw_particle_map(d, d.strain_energy_density,
                              strain_energy_style(d.strain_energy_density,
                                           "strain energy density at " + time_text(d.end_time)),
                              {}, forever, r.pores),
            "strain_energy_final.png");
  else
    r.notes.push_back("no 'strain_energy_density' in " + d.path + ": no strain_energy_final.png");
  // Cells of more than one size (a refined run, NB-NUG boxes): where the
  // set is fine, beside the crack's path.
  const auto [smallest_cell, largest_cell] = std::minmax_element(d.cell_size.begin(), d.cell_size.end());
  if (!d.cell_size.empty() && *largest_cell > *smallest_cell * (1 + 1e-9)) {
    MapStyle style;
    style.title = "cell size at " + time_text(d.end_time) + ", tips at damage " + threshold_text;
    style.bar_label = "cell mm";
    style.vmin = *smallest_cell * 1e3;
    style.vmax = *largest_cell * 1e3;
    std::vector<double> cell_mm(d.cell_size.size());
    for (std::size_t i = 0; i < cell_mm.size(); ++i) cell_mm[i] = d.cell_size[i] * 1e3;
    picture(draw_particle_map(d, cell_mm, style, r.tips, forever, r.pores), "cell_size_final.png");
  }

  const auto snapshots = list_snapshots(o.outdir, RunKind::dynamic);
  if (!o.map_times.empty() && snapshots.empty())
    r.notes.push_back("no snapshots: damage maps at given times are rebuilt from the arrival "
                      "times; strain-energy maps only for the final state");
  for (double t : o.map_times) {
    if (snapshots.empty()) {
      picture(draw_particle_map(d, damage_at_time(d, t),
                                damage_style("damage at " + time_text(t) + " (from arrival times)"),
                                r.tips, t, r.pores),
              "damage_t" + time_tag(t) + ".png");
      r.maps.push_back({t, t, "arrival times"});
      continue;
    }
    const auto nearest = &nearest_snapshot(snapshots, t);
    const SnapshotFields s = read_snapshot(*nearest, {d.path, d.x, d.y, d.cell_size}, true);
    check_same_run_id(nearest->file, s.run_id, std::string("field '") + results::field_run_id + "'", d.path, d.run_id);
    // A refined run's snapshot has its own particles (the set of its time).
    const MapParticles particles = s.x.empty() ? MapParticles{d.x, d.y, d.cell_size} : MapParticles{s.x, s.y, s.cell_size};
    // Named by the time drawn, which is the snapshot's, not the one asked for.
    r.maps.push_back({t, s.time, "snapshot " + nearest->file});
    if (std::abs(s.time - t) > 0.5 * d.time_step)
      r.notes.push_back("maps for " + time_text(t) + " show the nearest snapshot, at " + time_text(s.time));
    picture(draw_particle_map(particles, s.damage, damage_style("damage at " + time_text(s.time) + " (snapshot)"),
                              r.tips, s.time, r.pores),
            "damage_t" + time_tag(s.time) + ".png");
    if (s.strain_energy_density.empty()) {
      r.notes.push_back(nearest->file + " has no 'strain_energy_density': no strain-energy map at " +
                        time_text(s.time));
      continue;
    }
    picture(draw_particle_map(particles, s.strain_energy_density,
                              strain_energy_style(s.strain_energy_density,
                                           "strain energy density at " + time_text(s.time) + " (snapshot)"),
                              r.tips, s.time, r.pores),
            "strain_energy_t" + time_tag(s.time) + ".png");
  }

  char cr[64];
  std::snprintf(cr, sizeof cr, "c_R = %.0f m/s, window %d steps", r.rayleigh_speed, r.window_steps);
  picture(draw_speed_plot(r.speeds, r.rayleigh_speed, SpeedAxis::time, r.pores, r.pore_visits,
                          std::string("crack speed per branch, ") + cr),
          "speed_vs_time.png");
  picture(draw_speed_plot(r.speeds, r.rayleigh_speed, SpeedAxis::tip_x, r.pores, r.pore_visits,
                          std::string("crack speed per branch, ") + cr),
          "speed_vs_x.png");
  if (o.line) {
    write_line_profile(out("line_profile.csv"), r.line);
    picture(draw_line_profile(r.line, "jump of displacement across the line, final state"), "line_profile.png");
  }

  r.speed_table = out("crack_speed.csv");
  write_tip_table(out("crack_tips.csv"), r);
  write_speed_table(r.speed_table, r);
  write_branch_table(out("branches.csv"), r);
  write_pore_table(out("pore_trapping.csv"), r);
  write_branching_table(out("branching_events.csv"), r);
  write_summary_json(out("summary.json"), r);
  return r;
}

}  // namespace pd::post
