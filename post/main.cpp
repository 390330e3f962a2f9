// pd-post: crack tips, branches, crack speed, pore trapping and pictures
// from a solver output directory (docs/post.md).
#include <boost/program_options.hpp>
#include <iostream>
#include <sstream>

#include "cli.hpp"
#include "error.hpp"
#include "pd/version.hpp"
#include "mesh_pictures.hpp"
#include "post_pipeline.hpp"

namespace {

std::vector<double> parse_list(const std::string& list, const std::string& option) {
  std::vector<double> values;
  std::stringstream in(list);
  std::string item;
  while (std::getline(in, item, ',')) {
    std::size_t used = 0;
    double v = 0;
    try {
      v = std::stod(item, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used == 0 || used != item.size()) throw pd::Error(option + ": '" + item + "' is not a number");
    values.push_back(v);
  }
  return values;
}

std::vector<double> parse_times(const std::string& list) {
  auto times = parse_list(list, "--times");
  for (double t : times)
    if (t < 0) throw pd::Error("--times: " + std::to_string(t) + " is not a time in seconds (e.g. --times 1.5e-4,3e-4)");
  return times;
}

}  // namespace

int main(int argc, char** argv) {
  return pd::run_tool("pd-post", [&] {
    namespace po = boost::program_options;
    pd::post::PostOptions o;
    std::string times, particles, zoom;
    po::options_description options("Usage: pd-post OUTDIR [options]\nOptions");
    options.add_options()
      ("help,h", "show this help")
      ("version", "print the version")
      ("threshold", po::value(&o.threshold)->default_value(0.35, "0.35"),
       "damage threshold that defines the crack (an arrival_time_%.2f array must exist)")
      ("window", po::value(&o.window_steps)->default_value(30), "crack-speed window in solver steps")
      ("window-time", po::value(&o.window_time), "crack-speed window in seconds (overrides --window)")
      ("boxes", po::value(&o.boxes_file), "CSV of manual branch boxes x_min_m,x_max_m,y_min_m,y_max_m")
      ("pores", po::value(&o.pores_file), "CSV of pore circles x_m,y_m,r_m (default: detect holes)")
      ("times", po::value(&times), "comma-separated times [s] for damage / strain-energy maps")
      ("output,o", po::value(&o.postdir), "post directory (default OUTDIR/post)")
      ("particles", po::value(&particles),
       "instead of OUTDIR: draw a particle file's cells by region and by volume (PNG into -o, default .)")
      ("zoom", po::value(&zoom), "with --particles: window x0,x1,y0,y1 in mm");
    po::variables_map vm;
    if (!pd::parse_command_line(argc, argv, "pd-post", options, "outdir", vm)) return 0;
    if (vm.count("outdir")) o.outdir = vm["outdir"].as<std::string>();
    if (!particles.empty()) {
      const auto zoom_mm = zoom.empty() ? std::vector<double>{} : parse_list(zoom, "--zoom");
      for (const auto& path : pd::post::write_mesh_pictures(particles, o.postdir.empty() ? "." : o.postdir, zoom_mm))
        std::cout << "wrote " << path << "\n";
      return 0;
    }
    if (o.outdir.empty()) throw pd::Error("missing OUTDIR (the solver output directory); see --help");
    if (!times.empty()) o.map_times = parse_times(times);

    const auto r = pd::post::run_post(o);
    for (const auto& note : r.notes) std::cerr << "pd-post: note: " << note << "\n";
    std::cout << "branches: " << r.network.branches.size() << ", branching events: "
              << r.network.branchings.size() << ", pore visits: " << r.pore_visits.size()
              << ", c_R = " << r.rayleigh_speed << " m/s\n";
    std::cout << "main picture: " << r.main_picture << "\n";
    std::cout << "crack speed table: " << r.speed_table << "\n";
    return 0;
  });
}
