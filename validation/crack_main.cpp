// pd-validate-crack: the centre-cracked plate (docs/validation.md, "Crack
// opening"). FEM convergence of the opening at the crack centre over the
// element sizes given, then OSB quasi-static runs for the failure variants
// given (theory.md Sec. 5.8) against the finest FEM solution: per load step
// the bonds broken and the centre opening, and the opening profile along the
// crack at the last step (table and picture).
//
//   pd-validate-crack geometries/centre_crack_plate.geo --spacing 2.5mm -m 3 -o out/crack
#include <omp.h>

#include <boost/program_options.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <sstream>

#include "atomic_file.hpp"
#include "cli.hpp"
#include "crack_opening.hpp"
#include "output_folder.hpp"
#include "plate_grid.hpp"
#include "plots.hpp"
#include "tool_options.hpp"
#include "units.hpp"

namespace {

// The row nearest to the crack centre.
std::size_t centre_row(const std::vector<pd::validation::OpeningRow>& rows, double xc) {
  std::size_t best = 0;
  for (std::size_t k = 1; k < rows.size(); ++k)
    if (std::fabs(rows[k].x - xc) < std::fabs(rows[best].x - xc)) best = k;
  return best;
}

}  // namespace

int main(int argc, char** argv) {
  using namespace pd::validation;
  return pd::run_tool("pd-validate-crack", [&] {
    namespace po = boost::program_options;
    std::string spacing_text = "2.5mm", tip_text = "4mm,2mm,1mm", variant_list = "force_and_dilatation,force_only,bond_term_only";
    std::string displacement_text = "0.5mm", out = "out/crack";
    std::string factor_text = "3", fracture_energy_text = pd::shortest_text(CrackCase{}.fracture_energy),
                threads_text = "0", steps_text = "10";
    po::options_description options("Usage: pd-validate-crack PLATE.geo [options]\nOptions");
    options.add_options()("help,h", "show this help")("version", "print the version")(
        "spacing", po::value(&spacing_text), "grid spacing dx (uniform grid)")(
        "horizon-factor,m", po::value(&factor_text), "m = delta / dx")(
        "fem-tip-sizes", po::value(&tip_text), "FEM element sizes at the crack tips, coarse to fine (the last is the reference)")(
        "variants", po::value(&variant_list), "OSB failure variants (model.osb_failure values)")(
        "displacement", po::value(&displacement_text), "U: the top strip moves +U, the bottom one -U, at the last step")(
        "steps", po::value(&steps_text), "equal load steps up to U")(
        "fracture-energy", po::value(&fracture_energy_text), "G0 [J/m^2]")("no-damage", "no bond breaks (elastic)")(
        "threads", po::value(&threads_text), "OpenMP threads (0 = default)")("output,o", po::value(&out), "output folder");
    po::variables_map vm;
    if (!pd::parse_command_line(argc, argv, "pd-validate-crack", options, "geometry", vm)) return 0;
    const std::string geo =
        geometry_argument(vm, "pd-validate-crack geometries/centre_crack_plate.geo --spacing 2.5mm -m 3");
    set_threads(threads_text, "pd-validate-crack");
    const int steps = static_cast<int>(count_option(steps_text, "--steps", 1, 100000, "load steps"));
    const double factor = horizon_factor_option(factor_text);
    const double dx = spacing_option(spacing_text), horizon = factor * dx;
    CrackCase c;
    c.edge_displacement = pd::parse_positive_length(displacement_text, "--displacement");
    const auto energies = pd::plausible_range(pd::Quantity::energy_per_area);
    c.fracture_energy = number_option(fracture_energy_text, "--fracture-energy", energies.low, energies.high,
                                      "a fracture energy in J/m^2");
    const bool damage = vm.count("no-damage") == 0;
    // The FEM's element sizes, checked before the first FEM solve (before 7
    // December 2026 a bad one was found after the sizes before it, and none
    // at all ended in an opening read from an empty FEM solution).
    std::vector<double> tip_sizes;
    for (const auto& text : list_items(tip_text, "--fem-tip-sizes", "4mm,2mm,1mm"))
      tip_sizes.push_back(fem_size_option(text, "--fem-tip-sizes", dx));
    std::vector<pd::solver::OsbFailure> variants;
    for (const auto& name : list_items(variant_list, "--variants", "force_and_dilatation,force_only")) {
      bool found = false;
      for (const auto& f : pd::solver::osb_failures)
        if (name == f.name) variants.push_back(f.failure), found = true;
      if (!found) throw pd::Error("--variants: unknown variant '" + name +
                                  "' (use force_and_dilatation, force_only or bond_term_only)");
    }
    // The plate and its crack, and the grid against the memory, checked
    // before the output folder is made (before 7 December 2026 a plate with
    // holes was refused by the FEM's mesh, after it: the folder stayed,
    // empty but for fem/).
    {
      const pd::PlateGeometry plate = plate_geometry_of(geo, dx);
      check_cracked_plate(plate, crack_of(plate, c), horizon);
      check_grid_fits_memory({geo, pd::GridKind::uniform, dx, horizon, pd::Quadrature::analytic}, plate);
    }
    RunOutputFolder folder(out, "pd-validate-crack", {"fem"});

    pd::PlateGeometry geometry;
    const auto particles = make_plate_grid({geo, pd::GridKind::uniform, dx, horizon, pd::Quadrature::analytic}, &geometry);
    const FemCrack crack = crack_of(geometry, c);
    const double xc = 0.5 * (crack.x1 + crack.x2);
    const auto pairs = crack_pairs(particles, crack);
    std::cout << particles.size() << " particles, " << pairs.above.size() << " pairs over the crack\n" << std::flush;

    // FEM convergence: the face opening at the centre and the opening at the
    // central particle pair, per element size.
    std::ostringstream fem_md;
    fem_md << "| tip element size (mm) | nodes | elements | face opening at the centre (mm) | opening at the central pair "
              "(mm) | change from the previous size | ccx + gmsh (s) |\n| --- | --- | --- | --- | --- | --- | --- |\n";
    CrackFem fem;
    double previous = NAN;
    for (const double h : tip_sizes) {
      fem = solve_crack_fem(geometry, c, horizon, h, out + "/fem", "crack_h" + std::to_string(std::lround(h * 1e6)) + "um");
      const auto rows = opening_profile(particles, pairs, std::vector<double>(2 * particles.size(), 0.0), {}, fem);
      const double face = fem_face_opening(fem, crack, xc), pair = rows[centre_row(rows, xc)].fem;
      fem_md << "| " << h * 1e3 << " | " << fem.mesh.x.size() << " | " << fem.mesh.triangles.size() << " | "
             << std::setprecision(5) << face * 1e3 << " | " << pair * 1e3 << " | "
             << (std::isfinite(previous) ? std::to_string(100 * (face - previous) / face).substr(0, 6) + " %" : "-")
             << " | " << std::setprecision(3) << fem.seconds << " |\n";
      std::cout << "FEM h = " << h * 1e3 << " mm: face opening " << face * 1e3 << " mm, at the central pair "
                << pair * 1e3 << " mm (" << fem.seconds << " s)\n" << std::flush;
      previous = face;
    }

    // PD per variant: the steps, then the profile at the last step.
    std::vector<double> load_factors;
    for (int k = 1; k <= steps; ++k) load_factors.push_back(static_cast<double>(k) / steps);
    std::ostringstream steps_md, profile_csv;
    steps_md << "| variant | U (mm) | pairs broken (all steps) | opening at the centre, PD (mm) | FEM (mm) | PD / FEM |\n"
             << "| --- | --- | --- | --- | --- | --- |\n";
    std::vector<std::vector<OpeningRow>> profiles;
    std::vector<pd::post::Series> series;
    for (std::size_t v = 0; v < variants.size(); ++v) {
      const auto scene = crack_scene(geometry, c, variants[v], damage, load_factors);
      CrackPdRun run;
      try {
        run = solve_crack_pd(particles, scene);
      } catch (const pd::Error& e) {
        // A variant whose minimisation fails (theory.md Sec. 5.8: (c) with a < 0)
        // is reported, and the others still run.
        steps_md << "| " << pd::solver::to_string(variants[v]) << " | - | failed: " << e.what() << " | | | |\n";
        std::cout << pd::solver::to_string(variants[v]) << ": failed: " << e.what() << "\n" << std::flush;
        continue;
      }
      const auto rows = opening_profile(particles, pairs, run.u, run.damage, fem);
      const std::size_t centre = centre_row(rows, xc);
      for (const auto& step : run.steps)
        steps_md << "| " << pd::solver::to_string(variants[v]) << " | " << step.load_factor * c.edge_displacement * 1e3
                 << " | " << (step.broken_bonds - run.precrack_bonds) / 2 << " | "
                 << (&step == &run.steps.back() ? std::to_string(rows[centre].pd * 1e3) : std::string("")) << " | "
                 << (&step == &run.steps.back() ? std::to_string(rows[centre].fem * 1e3) : std::string("")) << " | "
                 << (&step == &run.steps.back() ? std::to_string(rows[centre].pd / rows[centre].fem) : std::string(""))
                 << " |\n";
      std::cout << pd::solver::to_string(variants[v]) << ": " << (run.steps.back().broken_bonds - run.precrack_bonds) / 2
                << " pairs broken, opening at the centre " << rows[centre].pd * 1e3 << " mm (FEM " << rows[centre].fem * 1e3
                << " mm), " << run.seconds << " s\n" << std::flush;
      profiles.push_back(rows);
      pd::post::Series s;
      s.label = std::string("PD ") + pd::solver::to_string(variants[v]);
      s.style = pd::post::branch_style(static_cast<int>(v) + 1);
      for (const auto& r : rows) s.x.push_back((r.x - xc) * 1e3), s.y.push_back(r.pd * 1e3);
      series.push_back(s);
    }
    pd::post::Series f;
    f.label = "FEM (CalculiX)";
    f.style = pd::post::branch_style(0);
    for (const auto& r : profiles.empty() ? opening_profile(particles, pairs, std::vector<double>(2 * particles.size(), 0.0), {}, fem)
                                          : profiles.front())
      f.x.push_back((r.x - xc) * 1e3), f.y.push_back(r.fem * 1e3);
    series.insert(series.begin(), f);

    // The profile table: x, FEM, then PD and its damage (above/below) per variant.
    profile_csv << "x_minus_xc_mm,fem_mm";
    for (std::size_t v = 1; v < series.size(); ++v) profile_csv << ",pd_" << series[v].label.substr(3) << "_mm";
    profile_csv << "\n" << std::setprecision(6);
    for (std::size_t k = 0; k < f.x.size(); ++k) {
      profile_csv << f.x[k] << "," << f.y[k];
      for (const auto& rows : profiles) profile_csv << "," << rows[k].pd * 1e3;
      profile_csv << "\n";
    }
    std::ostringstream title;
    title << "Crack opening, U = " << c.edge_displacement * 1e3 << " mm, dx = " << dx * 1e3 << " mm, m = " << factor
          << (damage ? "" : ", no damage");
    pd::post::draw_line_plot(series, "x - x_c (mm)", "opening u_y(above) - u_y(below) (mm)", title.str())
        .write_png(out + "/crack_opening.png");
    pd::write_atomically(out + "/fem_convergence.md", [&](std::ofstream& o) { o << fem_md.str(); });
    pd::write_atomically(out + "/steps.md", [&](std::ofstream& o) { o << steps_md.str(); });
    pd::write_atomically(out + "/crack_opening.csv", [&](std::ofstream& o) { o << profile_csv.str(); });
    folder.finished();
    std::cout << fem_md.str() << "\n" << steps_md.str() << "wrote " << out << "/crack_opening.png, crack_opening.csv\n";
    return 0;
  });
}
