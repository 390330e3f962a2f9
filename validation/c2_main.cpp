// pd-validate-c2: case C2 (plate with a hole, quasi-static fracture, [Peng,
// Chen, Bobaru 2023, Sec. 4.2]) on the three grids: the number of cracks that
// start at the hole and their initiation displacements, as a Markdown table,
// plus damage maps (docs/validation.md).
//
//   pd-validate-c2 geometries/c1_plate_hole.geo --spacing 0.1mm -m 4 -o out/c2
//
// With --count-cracks OUTDIR it runs nothing: it counts the cracks at the
// hole of a pd-solve run of C2 (OUTDIR/final_state.vtp), with the same ring.
#include <omp.h>

#include <boost/program_options.hpp>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

#include "arrival_data.hpp"
#include "atomic_file.hpp"
#include "c2_fracture.hpp"
#include "cli.hpp"
#include "gmsh_session.hpp"
#include "plate_geometry.hpp"
#include "results_format.hpp"
#include "vtp_input.hpp"
#include <vtkPolyData.h>
#include "output_folder.hpp"
#include "plate_grid.hpp"
#include "plots.hpp"
#include "tool_options.hpp"
#include "units.hpp"

int main(int argc, char** argv) {
  using namespace pd::validation;
  return pd::run_tool("pd-validate-c2", [&] {
    namespace po = boost::program_options;
    std::string spacing_text = "0.05mm", grid_list = "uniform,free,nbnug", out = "out/c2";
    std::string first_text = "0.01mm", small_text = "1e-4mm";
    std::string bond_weights = "distance_moment", quadrature = "analytic", count_cracks;
    std::string factor_text = "4", threads_text = "0", first_steps_text = "8", max_small_steps_text = "2000";
    po::options_description options("Usage: pd-validate-c2 PLATE.geo [options]\nOptions");
    options.add_options()("help,h", "show this help")("version", "print the version")(
        "spacing", po::value(&spacing_text), "grid spacing dx")("horizon-factor,m", po::value(&factor_text), "m = delta / dx")(
        "grids", po::value(&grid_list), "grids: uniform,free,nbnug")(
        "first-steps", po::value(&first_steps_text), "number of large displacement steps")(
        "first-increment", po::value(&first_text), "large step of each edge's displacement")(
        "increment", po::value(&small_text), "small step after the large ones")(
        "max-small-steps", po::value(&max_small_steps_text), "at most this many small steps")(
        "bond-weights", po::value(&bond_weights), "distance_moment (default) or partial_volume (the paper's Eq. (11))")(
        "quadrature", po::value(&quadrature), "partial-volume factors: analytic (default), hhb or full")(
        "no-surface-correction", "switch the surface correction off")(
        "threads", po::value(&threads_text), "OpenMP threads (0 = default)")("output,o", po::value(&out), "output folder")(
        "count-cracks", po::value(&count_cracks),
        "run nothing: count the cracks at the hole of the pd-solve run in this output folder (its final_state.vtp)");
    po::variables_map vm;
    if (!pd::parse_command_line(argc, argv, "pd-validate-c2", options, "geometry", vm)) return 0;
    const std::string geo = geometry_argument(vm, "pd-validate-c2 geometries/c1_plate_hole.geo --spacing 0.1mm -m 4");
    set_threads(threads_text, "pd-validate-c2");
    const double dx = spacing_option(spacing_text);
    const double factor = horizon_factor_option(factor_text);
    if (!count_cracks.empty()) {
      // The run's folder, named as pd-post names it (before 7 December 2026
      // a missing one was read as a missing final_state.vtp in it).
      pd::check_usable_path(count_cracks, "--count-cracks");
      pd::post::require_output_directory(count_cracks);
      // The hole from the geometry file; particles, damage, the load factor
      // of first damage and the horizon from the run's final state.
      pd::GmshSession session;
      const auto geometry = pd::load_plate_geometry(session, geo, 1e-3, dx);
      if (geometry.holes.empty()) throw pd::Error(geo + ": no hole");
      const auto& hole = geometry.holes.front();
      const std::string path = count_cracks + "/" + pd::results::final_state_file;
      auto poly = pd::post::read_vtp_quietly(path);
      pd::ParticleSet particles;
      pd::post::read_points(poly, path, particles.x, particles.y);
      const auto damage = pd::post::checked_damage(pd::post::read_point_array(poly, path, pd::results::damage, true), path,
                                                    pd::results::damage);
      const auto first = pd::post::read_point_array(poly, path, pd::results::damage_load_factor, false);
      // A number, finite and positive (before 7 December 2026 read as it
      // stood: a horizon of nan or -1 in an edited file found no particle
      // in the ring and counted 0 cracks, exit 0).
      const auto horizon = pd::post::read_field_number(poly, path, pd::results::field_horizon);
      if (!horizon) throw pd::Error(path + ": no field '" + pd::results::field_horizon + "'");
      if (!(*horizon > 0))
        throw pd::file_error(path, std::string("field '") + pd::results::field_horizon + "' is " +
                                       pd::shortest_text(*horizon) +
                                       ": not a positive length (pd-solve writes the run's horizon there; an edited "
                                       "or damaged file)");
      const auto cracks = cracks_at_hole(particles, damage, first,
                                         c2_ring(0.5 * (hole.xmin + hole.xmax), 0.5 * (hole.ymin + hole.ymax),
                                                 0.25 * (hole.xmax - hole.xmin + hole.ymax - hole.ymin), *horizon));
      std::cout << cracks.size() << " cracks at the hole:";
      for (const auto& c : cracks)
        std::cout << " " << std::lround(c.angle_degrees) << " deg (from load factor " << c.initiation_load_factor
                  << ")";
      std::cout << "\n";
      return 0;
    }
    C2Options c2;
    c2.first_steps = static_cast<int>(count_option(first_steps_text, "--first-steps", 0, 1000000, "load steps"));
    c2.first_increment = pd::parse_positive_length(first_text, "--first-increment");
    c2.small_increment = pd::parse_positive_length(small_text, "--increment");
    c2.max_small_steps = static_cast<int>(count_option(max_small_steps_text, "--max-small-steps", 0, 1000000, "load steps"));
    c2.surface_correction = vm.count("no-surface-correction") == 0;
    if (bond_weights != "distance_moment" && bond_weights != "partial_volume")
      throw pd::Error("--bond-weights: expected distance_moment or partial_volume, got '" + bond_weights + "'");
    c2.bond_weights = bond_weights == "partial_volume" ? pd::BondWeights::partial_volume
                                                       : pd::BondWeights::distance_moment;
    if (quadrature != "analytic" && quadrature != "hhb" && quadrature != "full")
      throw pd::Error("--quadrature: expected analytic, hhb or full, got '" + quadrature + "'");
    const pd::Quadrature quad = quadrature == "analytic" ? pd::Quadrature::analytic
                                : quadrature == "hhb"    ? pd::Quadrature::hhb
                                                         : pd::Quadrature::full;
    // Every grid named is checked before the first is solved (before 7 December 2026
    // 'uniform,nbnugg' was refused after the uniform grid's run).
    const std::vector<pd::GridKind> kinds = grids_option(grid_list);
    // The plate's hole, and every grid against the memory, checked before the
    // output folder is made (before 7 December 2026 after it, which they
    // left empty).
    {
      const pd::PlateGeometry plate = plate_geometry_of(geo, dx);
      if (plate.holes.empty())
        throw pd::Error(geo + ": no hole: C2 counts the cracks that start at the plate's hole (e.g. "
                        "geometries/c1_plate_hole.geo)");
      for (const pd::GridKind kind : kinds) check_grid_fits_memory({geo, kind, dx, factor * dx, quad}, plate);
    }
    RunOutputFolder folder(out, "pd-validate-c2", {});
    std::ostringstream md;
    md << "| grid | dx (mm) | m | particles | cracks at the hole | crack directions (deg) | initiation u per edge (mm) | "
          "first broken bond at u (mm) | peak reaction (N/m) | load steps | stop | wall (s) |\n"
       << "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |\n";
    for (const pd::GridKind kind : kinds) {
      pd::PlateGeometry geometry;
      const auto particles = make_plate_grid({geo, kind, dx, factor * dx, quad}, &geometry);
      // (Before 7 December 2026 a plate without one ended in "vector::_M_range_check"; checked above.)
      const auto& hole = geometry.holes.front();
      const double cx = 0.5 * (hole.xmin + hole.xmax), cy = 0.5 * (hole.ymin + hole.ymax);
      const double radius = 0.25 * (hole.xmax - hole.xmin + hole.ymax - hole.ymin);
      std::cout << grid_name(kind) << ": " << particles.size() << " particles\n" << std::flush;
      const auto r = run_c2(particles, cx, cy, radius, C1Material{}, c2, std::cout);
      std::ostringstream angles, loads;
      for (std::size_t k = 0; k < r.cracks.size(); ++k) {
        angles << (k ? ", " : "") << std::lround(r.cracks[k].angle_degrees);
        loads << (k ? ", " : "") << r.cracks[k].initiation_load_factor * 1e3;
      }
      md << "| " << grid_name(kind) << " | " << dx * 1e3 << " | " << factor << " | " << particles.size() << " | "
         << r.cracks.size() << " | " << angles.str() << " | " << loads.str() << " | "
         << r.first_damage_displacement * 1e3 << " | " << r.peak_reaction << " | " << r.steps.size() << " | "
         << r.stop_reason << " | " << r.seconds << " |\n";
      std::cout << grid_name(kind) << ": " << r.cracks.size() << " cracks at the hole (" << angles.str()
                << " deg), initiation at u = " << loads.str() << " mm; " << r.stop_reason << "; " << r.seconds << " s\n"
                << std::flush;
      std::vector<pd::post::Color> fill(particles.size());
      for (std::size_t i = 0; i < particles.size(); ++i) fill[i] = pd::post::colormap(r.damage[i]);
      pd::post::MapStyle bar;
      bar.title = "damage";
      bar.bar_label = "damage";
      bar.vmin = 0;
      bar.vmax = 1;
      std::string name = grid_name(kind);
      for (auto& c : name) c = c == '-' ? '_' : static_cast<char>(std::tolower(c));
      pd::post::draw_cell_map(particles, fill, {}, std::string("C2 damage, ") + grid_name(kind), &bar, {})
          .write_png(out + "/c2_damage_" + name + ".png");
    }
    pd::write_atomically(out + "/c2_cracks.md", [&](std::ofstream& f) { f << md.str(); });
    folder.finished();
    std::cout << "wrote " << out << "/c2_cracks.md\n";
    return 0;
  });
}
