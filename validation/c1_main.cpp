// pd-validate-c1: case C1 (plate with a hole, static, [Peng, Chen, Bobaru
// 2023, Sec. 4.1]) against a CalculiX plane-stress reference, for a list of
// grids, spacings and horizon factors; writes a CSV and a Markdown table of
// the differences and, with --maps, PNG maps of them, with --hole-stress the
// hoop stress around the hole (docs/validation.md).
//
//   pd-validate-c1 geometries/c1_plate_hole.geo --spacing 0.05mm -m 4 --variants --fem-refinement --maps -o out/c1
#include <omp.h>

#include <algorithm>
#include <boost/program_options.hpp>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <limits>
#include <map>
#include <sstream>

#include "atomic_file.hpp"
#include "c1_comparison.hpp"
#include "cli.hpp"
#include "hole_stress.hpp"
#include "output_folder.hpp"
#include "plate_grid.hpp"
#include "plots.hpp"
#include "tool_options.hpp"
#include "units.hpp"

namespace {

using namespace pd::validation;

struct Run {
  pd::GridKind grid;
  pd::Quadrature quadrature;
  bool surface_correction;
  double spacing, factor;
  int box_refinement = 1;  // NB-NUG boxes meshed at dx / box_refinement
  bool dual_horizon = false;  // the linear dual-horizon solution (no surface correction)
};

std::string run_label(const Run& r) {
  std::string s = grid_name(r.grid);
  if (r.quadrature == pd::Quadrature::hhb) s += " hhb";
  if (!r.surface_correction) s += " no-sc";
  if (r.box_refinement > 1) s += " box dx/" + std::to_string(r.box_refinement);
  if (r.dual_horizon) s += " dual-horizon";
  return s;
}

// |difference| / reference as a map over the cells, colour scale [0, vmax].
void write_map(const std::string& path, const pd::ParticleSet& p, const std::vector<double>& values, double vmax,
               const std::string& title, const std::string& bar_label, bool signed_scale) {
  std::vector<pd::post::Color> fill(p.size());
  const double vmin = signed_scale ? -vmax : 0.0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    const double v = signed_scale ? values[i] : std::fabs(values[i]);
    fill[i] = pd::post::colormap(std::clamp((v - vmin) / (vmax - vmin), 0.0, 1.0));
  }
  pd::post::MapStyle bar;
  bar.title = title;
  bar.bar_label = bar_label;
  bar.vmin = vmin;
  bar.vmax = vmax;
  pd::post::draw_cell_map(p, fill, {}, title, &bar, {}).write_png(path);
}

std::string fixed(double v, int digits = 4) {
  std::ostringstream o;
  o << std::setprecision(digits) << v;
  return o.str();
}

// The first ring of particles around the hole (r - R <= dx): one row per
// particle in `rows` and one line per run in `summary` (reactions, and the
// FEM hoop stress on the hole edge itself at theta = 90 and 270 deg).
void write_hole_stress_rows(std::ostream& rows, std::ostream& summary, const std::string& run_columns,
                            const pd::ParticleSet& particles, const PdSolution& pd, const pd::PlateGeometry& geometry,
                            const HoleCircle& hole, double spacing, const std::vector<const FemReference*>& fems,
                            const C1Material& material) {
  const double nu = FemLoadCase{}.poisson_ratio;
  const auto samples = hole_stress_samples(particles, pd, hole, spacing, fems, material.youngs_modulus, nu);
  rows << std::setprecision(8);
  for (const auto& s : samples) {
    rows << run_columns << "," << s.theta * 180 / M_PI << "," << s.distance * 1e3 << "," << s.pd_hoop << ","
         << s.pd_energy_density;
    for (std::size_t f = 0; f < fems.size(); ++f) rows << "," << s.fem_hoop[f] << "," << s.fem_energy_density[f];
    rows << "\n";
  }
  summary << std::setprecision(8) << run_columns << "," << hole.radius * 1e3 << ","
          << (geometry.ymax - geometry.ymin) * 1e3 << "," << samples.size() << "," << pd.reaction_x;
  for (const auto* fem : fems) {
    const FemInterpolator interpolate(fem->mesh);
    summary << "," << fem->mesh_size * 1e3 << "," << fem->solution.right_reaction_x;
    for (const double theta : {M_PI / 2, 3 * M_PI / 2}) {
      const double x = hole.cx + hole.radius * std::cos(theta), y = hole.cy + hole.radius * std::sin(theta);
      const auto g = fem_displacement_gradient(interpolate, fem->solution, x, y);
      summary << "," << hoop_component(plane_stress(g, material.youngs_modulus, nu), theta);
    }
  }
  summary << "\n";
}

}  // namespace

int main(int argc, char** argv) {
  return pd::run_tool("pd-validate-c1", [&] {
    namespace po = boost::program_options;
    std::string spacing_list = "0.05mm", factor_list = "4", grid_list = "uniform,free,nbnug", out = "out/c1";
    std::string fem_size_text = "0.05mm", bond_weights = "distance_moment", loading_text = "strips", box_list,
                near_hole_text, tolerance_text = "1e-9", threads_text = "0";
    po::options_description options("Usage: pd-validate-c1 PLATE.geo [options]\nOptions");
    options.add_options()("help,h", "show this help")("version", "print the version")(
        "spacing", po::value(&spacing_list), "grid spacings dx, comma-separated (e.g. 0.1mm,0.05mm)")(
        "horizon-factor,m", po::value(&factor_list), "horizon factors m = delta / dx, comma-separated")(
        "grids", po::value(&grid_list), "grids: uniform,free,nbnug")(
        "variants", "also NB-NUG with hhb partial volumes and NB-NUG without surface correction")(
        "box-refinement", po::value(&box_list),
        "F1,F2,...: also NB-NUG with its boxes meshed at dx / F (pd-mesh --box-spacing; F = 2, 4, ...), "
        "solved with dual-horizon PD (as --dual-horizon)")(
        "near-hole-band", po::value(&near_hole_text),
        "width of the band around the hole for the near-hole differences (default: 2 delta of each run); one "
        "width for all runs compares grids whose horizons differ on the same particles' region")(
        "dual-horizon", "solve every run with the linear dual-horizon solution (theory.md Sec. 6.5) instead of the "
        "NCG minimisation; needs --no-surface-correction")(
        "fem-size", po::value(&fem_size_text), "FEM element size at the hole (4x that far away)")(
        "fem-refinement", "also solve the FEM with half the element size and report the difference")(
        "tolerance", po::value(&tolerance_text), "relative residual of the PD minimisation")(
        "bond-weights", po::value(&bond_weights), "distance_moment (default) or partial_volume (the paper's Eq. (11))")(
        "no-surface-correction", "main runs without surface correction (the variants are unchanged)")(
        "loading", po::value(&loading_text), "strips (default: the in-body sets left/right; the FEM clamps them) or "
        "layers (loading layers beyond the left and right edges; the FEM moves its edges)")(
        "hole-stress", "write the hoop stress and strain energy density at the particles of the first ring around "
        "the hole, PD and FEM (c1_hole_stress.csv, c1_hole_summary.csv)")(
        "maps", "write PNG maps of the differences")("threads", po::value(&threads_text), "OpenMP threads (0 = default)")(
        "output,o", po::value(&out), "output folder");
    po::variables_map vm;
    if (!pd::parse_command_line(argc, argv, "pd-validate-c1", options, "geometry", vm)) return 0;
    const std::string geo = geometry_argument(vm, "pd-validate-c1 geometries/c1_plate_hole.geo --spacing 0.1mm -m 4");
    set_threads(threads_text, "pd-validate-c1");
    const double tolerance = number_option(tolerance_text, "--tolerance", std::numeric_limits<double>::epsilon(), 0.5,
                                           "a relative residual");
    // One band for all runs, checked before the first solve (before 7
    // December 2026 read after it).
    const double near_hole_band =
        near_hole_text.empty() ? 0.0 : pd::parse_positive_length(near_hole_text, "--near-hole-band");
    if (bond_weights != "distance_moment" && bond_weights != "partial_volume")
      throw pd::Error("--bond-weights: expected distance_moment or partial_volume, got '" + bond_weights + "'");
    const auto weights = bond_weights == "partial_volume" ? pd::BondWeights::partial_volume
                                                          : pd::BondWeights::distance_moment;
    if (loading_text != "strips" && loading_text != "layers")
      throw pd::Error("--loading: expected strips or layers, got '" + loading_text + "'");
    const auto loading = loading_text == "layers" ? C1Loading::layers : C1Loading::strips;
    if (vm.count("dual-horizon") && !vm.count("no-surface-correction"))
      throw pd::Error("--dual-horizon needs --no-surface-correction (the dual-horizon bonds have no surface correction)");
    std::vector<double> spacings, factors;
    for (const auto& s : list_items(spacing_list, "--spacing", "0.1mm,0.05mm")) spacings.push_back(spacing_option(s));
    for (const auto& m : list_items(factor_list, "--horizon-factor", "3,4")) factors.push_back(horizon_factor_option(m));
    const double fem_size =
        fem_size_option(fem_size_text, "--fem-size", *std::min_element(spacings.begin(), spacings.end()));
    const std::vector<pd::GridKind> grids = grids_option(grid_list);
    std::vector<int> box_factors;
    if (vm.count("box-refinement"))
      for (const auto& f : list_items(box_list, "--box-refinement", "2,4")) {
        const long box_factor = count_option(f, "--box-refinement", 2, 64, "refinements");
        if ((box_factor & (box_factor - 1)) != 0)
          throw pd::Error("--box-refinement: '" + f + "' in '" + box_list + "' is not a power of two from 2 to 64");
        box_factors.push_back(static_cast<int>(box_factor));
      }
    std::vector<Run> runs;
    for (const double dx : spacings)
      for (const double factor : factors) {
        for (const auto kind : grids)
          runs.push_back({kind, pd::Quadrature::analytic, vm.count("no-surface-correction") == 0, dx, factor, 1,
                          vm.count("dual-horizon") > 0});
        for (const int box_factor : box_factors)
          runs.push_back({pd::GridKind::nbnug, pd::Quadrature::analytic, false, dx, factor, box_factor, true});
        if (vm.count("variants")) {
          runs.push_back({pd::GridKind::nbnug, pd::Quadrature::hhb, true, dx, factor});
          runs.push_back({pd::GridKind::nbnug, pd::Quadrature::analytic, false, dx, factor});
        }
      }
    // The plate, and every run's grid against the memory, checked before
    // the output folder is made (before 7 December 2026 after it: a plate
    // without exactly one hole, or a grid beyond the memory, left it empty).
    {
      const pd::PlateGeometry plate = plate_geometry_of(geo, *std::max_element(spacings.begin(), spacings.end()));
      if (plate.holes.size() != 1)
        throw pd::Error(geo + ": C1 expects exactly one hole, and the plate has " + std::to_string(plate.holes.size()) +
                        ": give a plate with one (e.g. geometries/c1_plate_hole.geo)");
      // The band from the finest spacing (a narrower one may hold no
      // particle) to the plate's diagonal (a wider one is the whole plate):
      // before 7 December 2026 1e300mm was taken, a unit gone wrong.
      if (!near_hole_text.empty())
        pd::check_length_in_range(near_hole_band, "--near-hole-band",
                                  *std::min_element(spacings.begin(), spacings.end()), "finest --spacing",
                                  std::hypot(plate.xmax - plate.xmin, plate.ymax - plate.ymin), "plate's diagonal",
                                  "the finest spacing to the plate's diagonal", "1mm");
      for (const auto& run : runs)
        check_grid_fits_memory(
            {geo, run.grid, run.spacing, run.spacing * run.factor, run.quadrature, run.box_refinement}, plate);
    }
    RunOutputFolder folder(out, "pd-validate-c1", {"fem"});

    const C1Material material;
    // One FEM solution per clamp width (= horizon; 0 with loading layers), in nm; and at h / 2 with --fem-refinement.
    std::map<long, FemReference> fem_by_clamp, fem_fine_by_clamp;
    std::ostringstream hole_csv, hole_summary_csv;
    hole_csv << "grid,spacing_mm,horizon_factor,loading,theta_deg,distance_mm,pd_hoop_Pa,pd_sed_J_per_m3";
    hole_summary_csv << "grid,spacing_mm,horizon_factor,loading,hole_radius_mm,plate_height_mm,samples,"
                        "pd_reaction_N_per_m";
    for (const std::string suffix : {"", "_fine"}) {
      if (!suffix.empty() && !vm.count("fem-refinement")) continue;
      hole_csv << ",fem" << suffix << "_hoop_Pa,fem" << suffix << "_sed_J_per_m3";
      hole_summary_csv << ",fem" << suffix << "_size_mm,fem" << suffix << "_reaction_N_per_m,fem" << suffix
                       << "_edge_hoop_90_Pa,fem" << suffix << "_edge_hoop_270_Pa";
    }
    hole_csv << "\n";
    hole_summary_csv << "\n";
    std::ostringstream csv, md, refinement_md;
    csv << "grid,quadrature,surface_correction,spacing_mm,horizon_factor,particles,directed_bonds,"
           "ncg_iterations,setup_s,solve_s,ux_max_rel,ux_rms_rel,uy_max_rel,uy_rms_rel,ux_near_max_rel,"
           "ux_near_rms_rel,uy_near_max_rel,uy_near_rms_rel,pd_reaction_N_per_m,fem_reaction_N_per_m,fem_size_mm,loading\n";
    md << "| grid | dx (mm) | m | particles | NCG iterations | solve (s) | u_x max | u_x RMS | u_y max | u_y RMS | "
          "u_x max near hole | u_x RMS near hole | reaction PD / FEM - 1 |\n"
       << "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |\n";
    // The tables so far, rewritten after every run: a long study that is stopped
    // (Ctrl-C, killed) keeps what it finished; one that fails takes them back
    // with the folder (RunOutputFolder).
    const auto write_tables = [&] {
      if (vm.count("hole-stress")) {
        pd::write_atomically(out + "/c1_hole_stress.csv", [&](std::ofstream& f) { f << hole_csv.str(); });
        pd::write_atomically(out + "/c1_hole_summary.csv", [&](std::ofstream& f) { f << hole_summary_csv.str(); });
      }
      pd::write_atomically(out + "/c1_errors.csv", [&](std::ofstream& f) { f << csv.str(); });
      pd::write_atomically(out + "/c1_errors.md", [&](std::ofstream& f) {
        f << "Differences PD - FEM divided by U = " << material.edge_displacement << " m; near hole = within 2 delta of "
          << "the hole; bond weights " << bond_weights << ".\n\n"
          << md.str();
        if (!refinement_md.str().empty())
          f << "\nFEM refinement (differences at the particles, divided by U):\n\n"
            << "| clamp width | h at hole | nodes | max du_x | max du_y | reaction ratio - 1 |\n"
            << "| --- | --- | --- | --- | --- | --- |\n"
            << refinement_md.str();
      });
    };
    for (const auto& run : runs) {
      const double horizon = run.spacing * run.factor;
      pd::PlateGeometry geometry;
      const auto all_particles = c1_particles(
          {geo, run.grid, run.spacing, horizon, run.quadrature, run.box_refinement}, loading, &geometry);
      const auto& hole = geometry.holes[0];
      const double cx = 0.5 * (hole.xmin + hole.xmax), cy = 0.5 * (hole.ymin + hole.ymax);
      const double radius = 0.25 * (hole.xmax - hole.xmin + hole.ymax - hole.ymin);
      PdOptions pd_options;
      pd_options.surface_correction = run.surface_correction;
      pd_options.bond_weights = weights;
      pd_options.tolerance = tolerance;
      pd_options.loading = loading;
      pd_options.dual_horizon = run.dual_horizon;
      const auto pd_all = solve_c1_pd(all_particles, material, pd_options);
      // The FEM knows only the plate: compare on its particles.
      const auto plate = plate_only(all_particles, pd_all, geometry);
      const auto& particles = plate.particles;
      const auto& pd = plate.pd;
      // Strips: the FEM clamps the same strips, one horizon wide; layers: it moves the edge nodes.
      const double clamp = loading == C1Loading::layers ? 0.0 : horizon;
      const long key = std::lround(clamp * 1e9);
      if (!fem_by_clamp.count(key)) {
        const std::string job = "fem_clamp_" + std::to_string(key) + "nm";
        fem_by_clamp[key] = solve_c1_fem(geometry, material, clamp, fem_size, out + "/fem", job);
        const auto& f = fem_by_clamp[key];
        std::cout << "FEM (clamp " << pd::format_mm(clamp) << ", h = " << pd::format_mm(fem_size) << "): "
                  << f.mesh.x.size() << " nodes, " << f.mesh.triangles.size() << " CPS6, ccx " << fixed(f.solution.seconds, 3)
                  << " s, reaction " << f.solution.right_reaction_x << " N/m\n";
        if (vm.count("fem-refinement")) {
          fem_fine_by_clamp[key] = solve_c1_fem(geometry, material, clamp, fem_size / 2, out + "/fem", job + "_fine");
          const auto& fine = fem_fine_by_clamp[key];
          const auto a = fem_at_particles(f, particles), b = fem_at_particles(fine, particles);
          double largest = 0, reference = 0, dy = 0;
          for (std::size_t i = 0; i < particles.size(); ++i) {
            largest = std::max(largest, std::fabs(a.ux[i] - b.ux[i]));
            dy = std::max(dy, std::fabs((a.uy[i] - a.uy[0]) - (b.uy[i] - b.uy[0])));
            reference = std::max(reference, std::fabs(b.ux[i]));
          }
          std::ostringstream line;
          line << "| " << pd::format_mm(clamp) << " | " << pd::format_mm(fem_size) << " / " << pd::format_mm(fem_size / 2)
               << " | " << f.mesh.x.size() << " / " << fine.mesh.x.size() << " | " << fixed(largest / reference, 3) << " | "
               << fixed(dy / reference, 3) << " | " << fixed(f.solution.right_reaction_x / fine.solution.right_reaction_x - 1, 3)
               << " |\n";
          refinement_md << line.str();
          std::cout << "FEM refinement: max |du_x| / U = " << largest / reference << ", max |du_y| / U = " << dy / reference
                    << ", reaction ratio - 1 = " << f.solution.right_reaction_x / fine.solution.right_reaction_x - 1 << "\n";
        }
      }
      const auto& fem = fem_by_clamp[key];
      const auto at = fem_at_particles(fem, particles);
      const double band = near_hole_text.empty() ? 2 * horizon : near_hole_band;
      const auto e = compare_with_fem(particles, pd, at, cx, cy, radius, band);
      if (vm.count("hole-stress")) {
        std::vector<const FemReference*> fems = {&fem};
        if (fem_fine_by_clamp.count(key)) fems.push_back(&fem_fine_by_clamp[key]);
        write_hole_stress_rows(hole_csv, hole_summary_csv,
                               run_label(run) + "," + fixed(run.spacing * 1e3, 6) + "," + fixed(run.factor, 4) + "," +
                                   to_string(loading),
                               all_particles, pd_all, geometry, {cx, cy, radius}, run.spacing, fems, material);
      }
      const double reaction_error = pd.reaction_x / fem.solution.right_reaction_x - 1;
      csv << (run.box_refinement > 1 || run.dual_horizon ? run_label(run) : grid_name(run.grid)) << ","
          << pd::to_string(run.quadrature) << "," << (run.surface_correction ? 1 : 0) << ","
          << run.spacing * 1e3 << "," << run.factor << "," << all_particles.size() << "," << all_particles.bond_count() << ","
          << pd.iterations << "," << pd.setup_seconds << "," << pd.solve_seconds << "," << e.ux.max_rel << ","
          << e.ux.rms_rel << "," << e.uy.max_rel << "," << e.uy.rms_rel << "," << e.ux_near_hole.max_rel << ","
          << e.ux_near_hole.rms_rel << "," << e.uy_near_hole.max_rel << "," << e.uy_near_hole.rms_rel << ","
          << pd.reaction_x << "," << fem.solution.right_reaction_x << "," << fem_size * 1e3 << "," << to_string(loading)
          << "\n";
      md << "| " << run_label(run) << " | " << run.spacing * 1e3 << " | " << run.factor << " | " << all_particles.size() << " | "
         << pd.iterations << " | " << fixed(pd.solve_seconds, 3) << " | " << fixed(e.ux.max_rel, 3) << " | "
         << fixed(e.ux.rms_rel, 3) << " | " << fixed(e.uy.max_rel, 3) << " | " << fixed(e.uy.rms_rel, 3) << " | "
         << fixed(e.ux_near_hole.max_rel, 3) << " | " << fixed(e.ux_near_hole.rms_rel, 3) << " | " << fixed(reaction_error, 3)
         << " |\n";
      std::cout << run_label(run) << " dx " << pd::format_mm(run.spacing) << " m " << run.factor << ": " << all_particles.size()
                << " particles, " << pd.iterations << " iterations, " << fixed(pd.solve_seconds, 3) << " s; u_x max "
                << e.ux.max_rel << " RMS " << e.ux.rms_rel << "; u_y max " << e.uy.max_rel << " RMS " << e.uy.rms_rel
                << "; near hole u_x max " << e.ux_near_hole.max_rel << "; reaction " << reaction_error << "\n"
                << std::flush;
      if (vm.count("maps")) {
        std::string base = run_label(run);
        for (auto& c : base) c = (c == ' ' || c == '-') ? '_' : static_cast<char>(std::tolower(c));
        base = out + "/c1_" + base + "_dx" + std::to_string(std::lround(run.spacing * 1e6)) + "um_m" +
               fixed(run.factor, 2);
        std::vector<double> relx(particles.size()), rely(particles.size());
        for (std::size_t i = 0; i < particles.size(); ++i) relx[i] = e.dux[i] / e.reference, rely[i] = e.duy[i] / e.reference;
        // One colour scale for all grids (the largest NB-NUG difference seen so far would differ per grid).
        write_map(base + "_dux.png", particles, relx, 0.02, "|u_x(PD) - u_x(FEM)| / U, " + run_label(run),
                  "/ U", false);
        write_map(base + "_duy.png", particles, rely, 0.02, "|u_y(PD) - u_y(FEM)| / U, " + run_label(run),
                  "/ U", false);
        std::vector<double> fem_ux(particles.size());
        for (std::size_t i = 0; i < particles.size(); ++i) fem_ux[i] = at.ux[i] / e.reference;
        if (run.grid == pd::GridKind::nbnug && run.quadrature == pd::Quadrature::analytic && run.surface_correction)
          write_map(base + "_fem_ux.png", particles, fem_ux, 1.0, "u_x(FEM) / U at the particles", "/ U", true);
      }
      write_tables();
    }
    folder.finished();
    std::cout << "wrote " << out << "/c1_errors.csv and c1_errors.md"
              << (vm.count("hole-stress") ? ", c1_hole_stress.csv and c1_hole_summary.csv\n" : "\n");
    return 0;
  });
}
