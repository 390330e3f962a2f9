// pd-post: crack tips, branches, crack speed, pore trapping and pictures
// from a dynamic solver output directory; maps, reactions and line profiles
// from a quasi-static one (docs/post.md).
#include <boost/program_options.hpp>
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <limits>
#include <sstream>
#include <utility>

#include "atomic_file.hpp"
#include "cli.hpp"
#include "error.hpp"
#include "mesh_pictures.hpp"
#include "particle_file.hpp"
#include "pd/version.hpp"
#include "post_pipeline.hpp"
#include "quasi_static_pipeline.hpp"
#include "solver_summary.hpp"
#include "units.hpp"

namespace {

// A value given twice (--times 1us,1us, or 1us,1000ns, equal to round-off)
// is kept once: its maps were drawn twice over, every note on them printed twice.
void add_once(std::vector<double>& values, double v) {
  const auto same = [v](double a) { return std::abs(a - v) <= 1e-12 * std::max(std::abs(a), std::abs(v)); };
  if (std::none_of(values.begin(), values.end(), same)) values.push_back(v);
}

// The numbers of a comma-separated list option (--times, --load-factors),
// each read as every tool's number options are (number_as_typed), a bad
// item named by its place and text: "--load-factors abc: item 2 of
// '0.5,abc' is not a finite number: give ..." (before 7 December 2026 in
// words of their own, "--load-factors: 'abc' is not a decimal number", the
// item's place unsaid, and an empty item after the last comma dropped).
// `times`: an item may carry its unit (2us), read as --window-time's is.
// `give` says what the option takes, with an example.
std::vector<double> parse_number_list(const std::string& list, const std::string& option, const std::string& give,
                                      bool times, bool non_negative) {
  const std::vector<std::string> items = pd::comma_items(list);
  std::vector<double> values;
  for (std::size_t k = 0; k < items.size(); ++k) {
    const std::string& item = items[k];
    const std::string place = "item " + std::to_string(k + 1) + " of '" + pd::clipped(list) + "'";
    if (item.empty())
      throw pd::Error(option + " " + pd::clipped(list) + ": " + place + " is empty: " + give);
    // A number followed by letters is a time with its unit: its unit's errors are parse_time's.
    char* end = nullptr;
    std::strtod(item.c_str(), &end);
    while (end != item.c_str() && *end == ' ') ++end;
    const bool with_unit = times && end != item.c_str() && *end != '\0' &&
                           (std::isalpha(static_cast<unsigned char>(*end)) || static_cast<unsigned char>(*end) >= 0x80);
    double v = 0;
    if (with_unit) {
      // The unit's fault in the list's words, ending as every item's does
      // (before 7 December 2026 parse_time's own ending, without `give`).
      try {
        v = pd::parse_time(item, option);
      } catch (const pd::Error& e) {
        std::string reason = e.what();
        if (reason.compare(0, option.size() + 2, option + ": ") == 0) reason.erase(0, option.size() + 2);
        throw pd::Error(option + " " + pd::clipped(item) + ": " + place + " is not a time: " + reason + ": " + give);
      }
    } else {
      v = pd::finite_number_as_typed(item, option, place + " is not a finite number: " + give);
    }
    if (non_negative && v < 0)
      throw pd::Error(option + " " + pd::clipped(item) + ": " + place + " is negative: " + give);
    add_once(values, v);
  }
  return values;
}

// A number option's value, read here and not by Boost, whose "the argument
// ('abc') for option '--threshold' is invalid" said neither what the option
// takes nor what to do (before 7 December 2026), in the words of every
// tool's number options ("--threshold abc: give ...").
double number_option(const std::string& text, const std::string& option, const std::string& give) {
  return pd::finite_number_as_typed(text, option, give);
}

void print_messages(const std::vector<std::string>& warnings, const std::vector<std::string>& notes) {
  for (const auto& w : warnings) std::cerr << "pd-post: warning: " << w << "\n";
  for (const auto& n : notes) std::cerr << "pd-post: note: " << n << "\n";
}

}  // namespace

int main(int argc, char** argv) {
  return pd::run_tool("pd-post", [&] {
    namespace po = boost::program_options;
    pd::post::PostOptions o;
    std::string times, load_factors, particles, zoom, angle_length, line, line_offset, band, window_time;
    std::string threshold, window, damage_level;
    po::options_description options("Usage: pd-post OUTDIR [options]\nOptions");
    options.add_options()
      ("help,h", "show this help")
      ("version", "print the version")
      ("threshold", po::value(&threshold)->default_value("0.35"),
       "damage threshold that defines the crack (one of the scene's output.damage_thresholds: its arrival_time_ array must exist)")
      ("window", po::value(&window),
       "crack-speed window in solver steps (default: the time a tip at the Rayleigh speed needs to cross 15 cells)")
      ("window-time", po::value(&window_time), "crack-speed window, in s or with a unit, e.g. 2us (overrides --window)")
      ("angle-length", po::value(&angle_length),
       "branching angles: lines fitted over this length from the branching point (default 2mm)")
      ("boxes", po::value(&o.boxes_file), "CSV of manual branch boxes x_min_m,x_max_m,y_min_m,y_max_m")
      ("pores", po::value(&o.pores_file), "CSV of pore circles x_m,y_m,r_m (default: detect holes)")
      ("times", po::value(&times), "comma-separated times for damage / strain-energy maps, in s or with a unit (150us)")
      ("load-factors", po::value(&load_factors), "quasi-static runs: comma-separated load factors for maps")
      ("line", po::value(&line),
       "values along the segment x0,y0,x1,y1 (lengths with units, e.g. 10mm,12.5mm,40mm,12.5mm): line_profile.csv")
      ("line-offset", po::value(&line_offset), "with --line: one-sided fits from this distance (default: the horizon)")
      ("reference", po::value(&o.reference_dir),
       "another run's output directory (e.g. the fine run of the same plate): count this run's damaged particles "
       "farther than --band from every damaged particle of it (summary.json \"comparison\")")
      ("band", po::value(&band), "with --reference: half-width of the band around its damage (default: two horizons, "
       "the larger of the two runs')")
      ("damage-level", po::value(&damage_level)->default_value("0.2"),
       "with --reference: a particle is damaged at this final damage or more")
      ("output,o", po::value(&o.postdir), "post directory (default OUTDIR/post)")
      ("particles", po::value(&particles),
       "instead of OUTDIR: draw a particle file's cells by region, by volume and (where it varies) by horizon (PNG into -o, default .)")
      ("zoom", po::value(&zoom), "with --particles: window x0,x1,y0,y1 (lengths with units, e.g. 4mm,12mm,4mm,12mm)");
    po::variables_map vm;
    if (!pd::parse_command_line(argc, argv, "pd-post", options, "outdir", vm)) return 0;
    if (vm.count("outdir")) o.outdir = vm["outdir"].as<std::string>();
    // A path the system cannot use (longer than PATH_MAX) is named by its option.
    pd::check_usable_path(o.outdir, "");
    pd::check_usable_path(o.postdir, "-o");
    pd::check_usable_path(particles, "--particles");
    pd::check_usable_path(o.boxes_file, "--boxes");
    pd::check_usable_path(o.pores_file, "--pores");
    pd::check_usable_path(o.reference_dir, "--reference");
    // A folder whose name ends in white space that exists is taken, the space unseen: said.
    for (const auto& [path, option] : {std::pair<std::string, std::string>{o.outdir, ""}, {o.postdir, "-o"}})
      if (const std::string w = pd::white_space_name_warning(path, option); !w.empty())
        std::cerr << "pd-post: warning: " << w << "\n";
    if (!particles.empty()) {
      // The options of a run's results would be dropped without a word: refused, as OUTDIR is.
      for (const char* name : {"threshold", "window", "window-time", "angle-length", "boxes", "pores", "times",
                               "load-factors", "line", "line-offset", "reference", "band", "damage-level"})
        if (vm.count(name) && !vm[name].defaulted())
          throw pd::Error(std::string("--") + name + " is for a run's results (pd-post OUTDIR ...); --particles " +
                          particles + " draws a particle file's cells and takes only --zoom and -o: leave --" +
                          name + " out");
      if (!o.outdir.empty())
        throw pd::Error("give either OUTDIR (a run's results) or --particles FILE (a particle file's cells), not both "
                        "(OUTDIR " + o.outdir + ", --particles " + particles + ")");
      std::vector<double> window;  // [m]
      for (const auto& item : pd::comma_items(zoom)) window.push_back(pd::parse_length(item, "--zoom"));
      const auto pictures = pd::post::write_mesh_pictures(particles, o.postdir.empty() ? "." : o.postdir, window);
      print_messages(pictures.warnings, {});
      for (const auto& path : pictures.written) std::cout << "wrote " << path << "\n";
      return 0;
    }
    if (!zoom.empty()) throw pd::Error("--zoom is a window of --particles' pictures; give --particles FILE with it");
    if (o.outdir.empty()) throw pd::Error("missing OUTDIR (the solver output directory); see --help");
    // A particle file given for OUTDIR: its pictures come with --particles.
    if (std::filesystem::is_regular_file(o.outdir) && pd::begins_as_particle_file(o.outdir))
      throw pd::Error(o.outdir + ": a particle file, not a solver output directory; for pictures of its grid "
                      "give it as --particles " + o.outdir + " (see --help)");
    o.threshold = number_option(threshold, "--threshold",
                                "give one of the run's damage thresholds (its output.damage_thresholds), e.g. "
                                "--threshold 0.35");
    o.damage_level = number_option(damage_level, "--damage-level", "give a damage in (0, 1], e.g. --damage-level 0.2");
    if (vm.count("window")) {
      const std::string example = "e.g. --window 30, or the window as a time, e.g. --window-time 2us";
      const double steps = number_option(window, "--window", "give a whole number of solver steps, " + example);
      if (steps < 1) throw pd::Error("--window " + window + ": must be at least 1 solver step");
      if (steps != std::floor(steps) || steps > std::numeric_limits<int>::max())
        throw pd::Error("--window " + window + ": not a whole number of solver steps from 1 to " +
                        std::to_string(std::numeric_limits<int>::max()) + ": " + example);
      o.window_steps = static_cast<int>(steps);
    }
    if (vm.count("window-time")) {
      o.window_time = pd::parse_time(window_time, "--window-time");
      if (!(o.window_time > 0))
        throw pd::Error("--window-time must be a positive number of seconds (or a time with its unit), got " +
                        window_time);
    }
    if (!times.empty())
      o.map_times = parse_number_list(times, "--times",
                                      "give times from 0, in s or with their unit, comma-separated, e.g. --times "
                                      "1.5e-4,300us",
                                      true, true);
    // (Load factors may be negative: a run that unloads, or pushes.)
    if (!load_factors.empty())
      o.map_load_factors = parse_number_list(load_factors, "--load-factors",
                                             "give load factors, comma-separated, e.g. --load-factors 0.5,1", false,
                                             false);
    o.threshold_given = !vm["threshold"].defaulted();
    o.angle_length_given = !angle_length.empty();
    if (!angle_length.empty()) o.angle_length = pd::parse_positive_length(angle_length, "--angle-length");
    if (!line.empty()) o.line = pd::post::parse_sample_line(line, "--line");
    if (!line_offset.empty()) o.line_offset = pd::parse_positive_length(line_offset, "--line-offset");
    if (!line_offset.empty() && line.empty())
      throw pd::Error("--line-offset " + line_offset + " needs --line (the line whose profile it fits)");
    if (!band.empty()) o.band = pd::parse_positive_length(band, "--band");
    if ((!band.empty() || !vm["damage-level"].defaulted()) && o.reference_dir.empty())
      throw pd::Error("--band and --damage-level need --reference (the run to compare with)");

    const auto kind = pd::post::detect_run_kind(o.outdir, pd::post::read_solver_summary(o.outdir));
    if (kind == pd::post::RunKind::quasi_static) {
      if (!o.reference_dir.empty())
        throw pd::Error(o.outdir + ": --reference compares the damage of dynamic runs; this is a quasi-static run");
      const auto r = pd::post::run_quasi_static_post(o);
      print_messages(r.warnings, r.notes);
      const auto& q = r.data;
      std::cout << "quasi-static run: " << q.load_factors.size() << (q.load_factors.size() == 1 ? " load step" : " load steps");
      if (!q.max_damage.empty()) std::cout << ", max damage at the last step " << q.max_damage.back();
      if (!q.state_path.empty())
        std::cout << "; maps of " << (q.final_state ? "the final state" : "the last snapshot") << " (load factor "
                  << q.state_load_factor << ", max damage " << r.max_damage << ")";
      std::cout << "\n";
      std::cout << "main picture: " << r.main_picture << "\n";
      std::cout << "reaction table: " << r.reaction_table << "\n";
      return 0;
    }
    const auto r = pd::post::run_post(o);
    print_messages(r.warnings, r.notes);
    std::cout << "branches: " << r.network.branches.size();
    // (Listed in summary.json's damage_spots: a few particles at the threshold that never grew.)
    if (!r.network.spots.empty())
      std::cout << " (and " << r.network.spots.size() << " damage spot" << (r.network.spots.size() > 1 ? "s" : "")
                << " of fewer than 3 particles that never grew)";
    std::cout << ", branching events: " << r.network.branchings.size() << ", pores: " << r.pores.size()
              << ", pore visits: " << r.pore_visits.size()
              << ", c_R = " << r.rayleigh_speed << " m/s (plane " << pd::post::to_string(r.model.plane)
              << ", model Poisson ratio " << r.model.poisson_ratio << "), window " << r.window_steps << " steps\n";
    std::cout << "main picture: " << r.main_picture << "\n";
    std::cout << "crack speed table: " << r.speed_table << "\n";
    if (r.comparison && r.comparison->damaged == 0)
      std::cout << "against " << r.comparison->reference << ": nothing to compare, no particle of this run has "
                << "damage >= " << r.comparison->damage_level << " (its largest is " << r.max_damage << ")\n";
    else if (r.comparison)
      std::cout << "against " << r.comparison->reference << ": " << r.comparison->outside << " of "
                << r.comparison->damaged << " damaged particles (damage >= " << r.comparison->damage_level
                << ") lie farther than " << r.comparison->band * 1e3 << " mm from its damage ("
                << r.comparison->area_outside * 1e6 << " mm^2)\n";
    return 0;
  });
}
