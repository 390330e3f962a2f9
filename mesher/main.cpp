// pd-mesh: a gmsh geometry file -> a particle file (docs/mesher.md).
//
//   pd-mesh plate.geo --spacing 0.05mm --horizon 0.2mm -o plate.pdp [--vtk plate.vtp]
#include <algorithm>
#include <boost/program_options.hpp>
#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <numeric>
#include <sstream>
#include <utility>
#include <vector>

#include "atomic_file.hpp"
#include "boundary_sets.hpp"
#include "box_spacing.hpp"
#include "cli.hpp"
#include "families.hpp"
#include "family_size_estimate.hpp"
#include "feature_sizes.hpp"
#include "gmsh_session.hpp"
#include "input_file.hpp"
#include "graded_spacing.hpp"
#include "grids.hpp"
#include "horizon_smoothing.hpp"
#include "json_text.hpp"
#include "loading_layer.hpp"
#include "material_boundary.hpp"
#include "mesh_summary.hpp"
#include "mesh_worker.hpp"
#include "particle_file.hpp"
#include "pd/version.hpp"
#include "plate_geometry.hpp"
#include "plate_pieces.hpp"
#include "refinement.hpp"
#include "resource_estimate.hpp"
#include "small_free_cells.hpp"
#include "units.hpp"
#include "vtk_output.hpp"

namespace po = boost::program_options;

namespace {

struct Options {
  std::string geometry, output, vtk, spacing_text, horizon_text, padding_text, grid = "nbnug",
                                                                              quadrature = "analytic", geo_unit = "mm";
  std::string bonds_across_voids = "cut", max_memory_text, loading_layer_text, loading_layer_depth_text;
  std::vector<std::string> loading_layers;
  std::string refine_region_text, horizon_smoothing_text, box_spacing_text;
  double box_spacing = 0;  // DXB [m]; 0: the boxes are meshed at dx
  std::string graded_spacing_text;
  pd::GradedSpacing graded;  // not enabled: the free grid at dx everywhere
  std::string refine_factor_text;
  double horizon_smoothing = 0;  // L_s [m]; 0: the horizon jumps at the region's edge
  pd::RefinementRegion refinement;  // factor 1: none
  double loading_layer_depth = 0;
  std::string horizon_factor_text, gmsh_time_limit_text;  // as typed
  double gmsh_time_limit = 300;
  double horizon_factor = 0;
  double spacing = 0, horizon = 0, padding = 0;
  pd::GridKind grid_kind = pd::GridKind::nbnug;
  pd::Quadrature quadrature_kind = pd::Quadrature::analytic;
};

pd::GridKind parse_grid(const std::string& s) {
  if (const auto kind = pd::grid_kind_named(s)) return *kind;
  throw pd::Error("--grid: unknown grid '" + s + "' (use nbnug, uniform or free)");
}

pd::Quadrature parse_quadrature(const std::string& s) {
  if (s == "analytic") return pd::Quadrature::analytic;
  if (s == "hhb") return pd::Quadrature::hhb;
  if (s == "full") return pd::Quadrature::full;
  throw pd::Error("--quadrature: unknown quadrature '" + s + "' (use analytic, hhb or full)");
}

std::string provenance(const Options& o) {
  using pd::json_number;
  std::ostringstream json;
  json << "{\"tool\": \"pd-mesh\", \"version\": " << pd::json_string(pd::version_string)
       << ", \"geometry\": " << pd::json_string(o.geometry) << ", \"geometry_hash\": \""
       << pd::file_hash_hex(o.geometry) << "\", ";
  json << "\"options\": {\"spacing_m\": " << json_number(o.spacing) << ", \"horizon_m\": " << json_number(o.horizon)
       << ", \"padding_m\": " << json_number(o.padding) << ", ";
  json << "\"grid\": " << pd::json_string(o.grid) << ", \"quadrature\": " << pd::json_string(o.quadrature)
       << ", \"geo_unit\": " << pd::json_string(o.geo_unit)
       << ", \"bonds_across_voids\": " << pd::json_string(o.bonds_across_voids);
  if (!o.loading_layers.empty()) {
    json << ", \"loading_layer\": [";
    for (std::size_t k = 0; k < o.loading_layers.size(); ++k) json << (k ? ", " : "") << pd::json_string(o.loading_layers[k]);
    json << "], \"loading_layer_depth_m\": " << json_number(o.loading_layer_depth);
  }
  if (o.refinement.factor > 1)
    json << ", \"refine_region_m\": [" << json_number(o.refinement.x0) << ", " << json_number(o.refinement.y0) << ", "
         << json_number(o.refinement.x1) << ", " << json_number(o.refinement.y1)
         << "], \"refine_factor\": " << o.refinement.factor;
  if (!o.horizon_smoothing_text.empty()) json << ", \"horizon_smoothing_m\": " << json_number(o.horizon_smoothing);
  if (o.box_spacing > 0) json << ", \"box_spacing_m\": " << json_number(o.box_spacing);
  if (o.graded.enabled())
    json << ", \"graded_spacing_m\": " << json_number(o.graded.fine) << ", \"grading_length_m\": "
         << json_number(o.graded.length);
  json << "}}";
  return json.str();
}

// A grid too coarse for its plate still meshes, but its particles without a
// bond take no part in a run, and a horizon of half the plate's width or more
// leaves it no interior: said on stderr after the summary (the file is written).
void warn_about_coarse_grid(const pd::ParticleSet& p) {
  std::size_t lonely = 0, example = 0;
  double widest = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    widest = std::max(widest, p.horizon[i]);
    if (p.family_offsets[i + 1] == p.family_offsets[i] && lonely++ == 0) example = i;
  }
  if (lonely > 0)
    std::fprintf(stderr,
                 "pd-mesh: warning: %zu particle%s no bond (e.g. particle %zu at (%.4g, %.4g) mm, area / dx^2 "
                 "%.3g): it takes no part in a run; a smaller --spacing resolves the plate\n",
                 lonely, lonely == 1 ? " has" : "s have", example, p.x[example] * 1e3, p.y[example] * 1e3,
                 p.volume[example] / (p.spacing * p.spacing));
  // A whole family needs a particle a horizon away from both edges.
  const double narrow_side = std::min(p.xmax - p.xmin, p.ymax - p.ymin);
  if (2 * widest >= narrow_side)
    std::fprintf(stderr,
                 "pd-mesh: warning: the horizon %.4g mm is at least half the plate's narrower side (%.4g mm): no "
                 "particle has a whole family; a smaller --spacing or --horizon resolves the plate\n",
                 widest * 1e3, narrow_side * 1e3);
}

// A smoothing length longer than the finer cells lie deep is accepted
// (still a valid grid), but those cells then never reach the fine horizon
// they were made for: `depth_from` names the distance measured, `cells` the
// cells, `inner` those a shorter length would leave at the fine horizon.
void warn_if_no_fine_horizon_left(const std::string& file, const std::string& option_text, double smoothing_length,
                                  const pd::SmoothingReport& s, double nominal_horizon, const char* depth_from,
                                  const char* cells, const char* inner) {
  if (!s.keeps_no_fine_horizon(smoothing_length)) return;
  std::fprintf(stderr,
               "pd-mesh: warning: %s: --horizon-smoothing %s is longer than the %.4g mm from %s: no %s keeps the "
               "fine horizon %.4g mm (the smallest is %.4g mm, the coarse one %.4g mm); a smoothing length below "
               "%.4g mm leaves %s at the fine horizon\n",
               file.c_str(), option_text.c_str(), s.deepest * 1e3, depth_from, cells, s.fine_horizon * 1e3,
               s.smallest_horizon * 1e3, nominal_horizon * 1e3, s.deepest * 1e3, inner);
}

// The ramp runs towards squares of side dx; with none beside the finer cells
// (a refinement region over the whole plate) it smooths nothing, which the
// summary's horizons alone do not say.
void warn_if_nothing_to_ramp_to(const std::string& file, const std::string& option_text, const pd::SmoothingReport& s,
                                const char* cells, const char* why) {
  if (!s.nothing_to_ramp_to()) return;
  std::fprintf(stderr,
               "pd-mesh: warning: %s: --horizon-smoothing %s smooths no %s: %s; their horizons stay m x their own "
               "size (the ramp runs only towards squares of side dx)\n",
               file.c_str(), option_text.c_str(), cells, why);
}

// Free cells far below their target size (around holes narrower than the
// spacing) give their particles many times the usual bonds: said with the
// families as built, once the features are measured.
void warn_about_small_free_cells(const std::string& file, const pd::ParticleSet& p,
                                 const std::vector<pd::NarrowVoid>& narrow, const std::vector<std::string>& remedies,
                                 double box_spacing) {
  std::vector<double> family_sizes(p.size());
  for (std::size_t i = 0; i < p.size(); ++i)
    family_sizes[i] = static_cast<double>(p.family_offsets[i + 1] - p.family_offsets[i]);
  const auto small_cells = pd::find_small_free_cells(p, family_sizes, box_spacing);
  if (!small_cells.forced()) return;
  const auto built = pd::resources_of(static_cast<double>(p.size()), static_cast<double>(p.bond_count()));
  std::fprintf(stderr, "pd-mesh: warning: %s\n",
               pd::small_free_cells_warning(file, small_cells, p, narrow, built, remedies).c_str());
}

// The uniform grid is a comparison grid with a staircase boundary by design,
// so material it drops is a warning, not an error; but a ligament narrower
// than the spacing that holds no cell centre changes the plate's shape (a hole
// becomes a notch, two holes one), which the area check alone hides.
void warn_about_lost_ligaments(const std::string& file, const std::vector<pd::LostLigament>& ligaments,
                               double spacing) {
  for (const auto& l : ligaments)
    std::fprintf(stderr,
                 "pd-mesh: warning: %s: the uniform grid has no particle in the material between %s near "
                 "(%.6g, %.6g) mm, %.4g mm wide (%.3g dx), narrower than the spacing %.4g mm: the grid joins the "
                 "two voids there (%s); --grid nbnug keeps it (its cells follow the boundary), or give the "
                 "uniform grid a --spacing below %.4g mm\n",
                 file.c_str(), l.between.c_str(), l.where.x * 1e3, l.where.y * 1e3, l.width * 1e3, l.width / spacing,
                 spacing * 1e3,
                 l.to_outer_boundary ? "the hole becomes a notch open to the boundary" : "the two holes become one",
                 l.width * 1e3);
}

// The geometry is one plane surface, so a grid whose bonds leave it in
// several pieces dropped material: a neck of the outer boundary or a
// ligament narrower than the spacing that holds no cell centre (the uniform
// grid keeps whole cells only). pd-solve warns again in its plan; pieces
// of one particle are the particles without a bond, warned about above.
void warn_about_pieces(const std::string& file, const pd::ParticleSet& p, const std::string& grid) {
  const auto root = pd::piece_roots(p.size(), [&](std::uint32_t i, auto&& join) {
    for (auto b = p.family_offsets[i]; b < p.family_offsets[i + 1]; ++b) join(p.neighbors[b]);
  });
  struct Piece {
    std::size_t particles = 0;
    double xmin = INFINITY, xmax = -INFINITY, ymin = INFINITY, ymax = -INFINITY;
  };
  std::vector<Piece> pieces(p.size());
  for (std::size_t i = 0; i < p.size(); ++i) {
    Piece& q = pieces[root[i]];
    ++q.particles;
    q.xmin = std::min(q.xmin, p.x[i]), q.xmax = std::max(q.xmax, p.x[i]);
    q.ymin = std::min(q.ymin, p.y[i]), q.ymax = std::max(q.ymax, p.y[i]);
  }
  pieces.erase(std::remove_if(pieces.begin(), pieces.end(), [](const Piece& q) { return q.particles < 2; }),
               pieces.end());
  if (pieces.size() < 2) return;
  std::sort(pieces.begin(), pieces.end(), [](const Piece& a, const Piece& b) { return a.particles > b.particles; });
  std::ostringstream list;
  for (std::size_t k = 0; k < std::min<std::size_t>(3, pieces.size()); ++k) {
    char buf[160];
    std::snprintf(buf, sizeof buf, "%s%zu particles in x %.4g to %.4g mm, y %.4g to %.4g mm", k ? "; " : "",
                  pieces[k].particles, pieces[k].xmin * 1e3, pieces[k].xmax * 1e3, pieces[k].ymin * 1e3,
                  pieces[k].ymax * 1e3);
    list << buf;
  }
  std::fprintf(stderr,
               "pd-mesh: warning: %s: the particles fall into %zu pieces that no bond joins (%s%s), but the geometry "
               "is one piece: material between them narrower than the spacing holds no particle (a neck of the "
               "boundary or a thin ligament); %s\n",
               file.c_str(), pieces.size(), list.str().c_str(), pieces.size() > 3 ? "; ..." : "",
               // (Before 7 December 2026 the NB-NUG and free grids were
               // advised to take --grid nbnug too.)
               grid == "uniform" ? "a smaller --spacing, or --grid nbnug, keeps it" : "a smaller --spacing may keep it");
}

// The name a particle file written as -o OUTPUT was most likely meant to
// have, or "" where OUTPUT ends in .pdp (in any case: pd-solve reads any
// name). A name with another ending after .pdp (plate.pdp.tmp) is meant up
// to it, and one ending in part of .pdp (plate., plate.pd) is meant with it
// whole: before 7 December 2026 both were told to add .pdp after all of it
// (plate.pdp.tmp.pdp, plate..pdp), and a name .pdp was said not to end in it.
std::string meant_particle_file_name(const std::string& output) {
  const std::string name = std::filesystem::path(output).filename().string();
  const std::string folder = output.substr(0, output.size() - name.size());
  std::string lower = name;
  for (auto& ch : lower) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
  const auto ends_in = [&](const std::string& tail) {
    return lower.size() >= tail.size() && lower.compare(lower.size() - tail.size(), tail.size(), tail) == 0;
  };
  if (ends_in(".pdp")) return "";
  if (const auto at = lower.rfind(".pdp."); at != std::string::npos) return folder + name.substr(0, at + 4);
  for (const std::string part : {".pd", ".p", "."})
    if (ends_in(part) && lower.size() > part.size()) return folder + name.substr(0, name.size() - part.size()) + ".pdp";
  return output + ".pdp";
}

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

int main(int argc, char** argv) {
  if (argc == 2 && std::string(argv[1]) == pd::mesh_worker_argument) return pd::run_mesh_worker();
  return pd::run_tool("pd-mesh", [&] {
    Options o;
    po::options_description visible(
        "pd-mesh: turn a 2D gmsh geometry (.geo) into a particle file\n\n"
        "Usage: pd-mesh GEOMETRY.geo --spacing DX (--horizon DELTA | --horizon-factor M) -o OUT.pdp [options]\n"
        "GEOMETRY.geo: the plate, a gmsh geometry file (in mm unless --geo-unit says otherwise).\n"
        "Lengths take a unit: 0.05mm, 50um, 5e-5m.\n\nOptions");
    visible.add_options()("help,h", "show this help")("version", "print the version")(
        "spacing", po::value(&o.spacing_text),
        "grid spacing dx (required); must divide the plate's width (height) where straight edges lie along both sides")(
        "horizon", po::value(&o.horizon_text), "horizon delta (>= dx)")(
        "horizon-factor,m", po::value(&o.horizon_factor_text), "horizon as a multiple of dx (delta = m dx), instead of --horizon")(
        "grid", po::value(&o.grid)->default_value("nbnug"), "nbnug | uniform | free")(
        "quadrature", po::value(&o.quadrature)->default_value("analytic"),
        "partial-volume factors: analytic (exact cell-disk areas) | hhb | full")(
        "padding", po::value(&o.padding_text), "NB-NUG box padding around each hole (default: one horizon; >= horizon)")(
        "geo-unit", po::value(&o.geo_unit)->default_value("mm"), "length unit of the geometry file: m, cm, mm, um")(
        "bonds-across-voids", po::value(&o.bonds_across_voids)->default_value("cut"),
        "cut: no bond whose segment leaves the material (default) | keep: bonds by distance only, for comparison")(
        "max-memory", po::value(&o.max_memory_text),
        "memory pd-mesh may use, e.g. 64GB (default: what the machine has available); larger grids are refused")(
        "gmsh-time-limit", po::value(&o.gmsh_time_limit_text)->default_value("300"),
        "seconds gmsh may take to read the geometry, and to mesh the free regions (plus 10 ms per expected cell)")(
        "loading-layer", po::value(&o.loading_layer_text),
        "EDGE[,EDGE...]: add a fictitious loading layer of lattice squares outside the plate beyond these sides "
        "(left, right, bottom, top), with a set loading_layer_EDGE each")(
        "loading-layer-depth", po::value(&o.loading_layer_depth_text),
        "depth of the loading layers (default: one horizon; rounded up to whole rows of the spacing)")(
        "refine-region", po::value(&o.refine_region_text),
        "X0,Y0,X1,Y1: a rectangle (snapped outward to whole dx cells) whose squares are split into "
        "squares of dx / --refine-factor, each with the horizon m x its own side")(
        "refine-factor", po::value(&o.refine_factor_text), "2, 4, 8, ... (with --refine-region)")(
        "box-spacing", po::value(&o.box_spacing_text),
        "DXB: mesh the NB-NUG boxes and bands around boundaries off the lattice with target size DXB = dx / 2^k "
        "(k = 0 ... 6) instead of dx; their cells get the horizon m x DXB (--grid nbnug only)")(
        "graded-spacing", po::value(&o.graded_spacing_text),
        "DXF[,L]: grade the global free grid's cells from the target size DXF (< dx) at the curved boundaries "
        "linearly to dx at distance L from them (default L: 3 horizons); each cell gets the horizon m x the "
        "target size at its centroid (--grid free only)")(
        "horizon-smoothing", po::value(&o.horizon_smoothing_text),
        "L_s: the refined squares' horizon grows linearly from m x their side, L_s inside the region, to m dx "
        "at its edges that face coarse squares; with --box-spacing, the boxes' cells' horizon likewise from "
        "m x DXB, L_s inside the box, to m dx where the box meets squares of side dx (smoothed variable "
        "horizon; with --refine-region or --box-spacing; default 0)")(
        "output,o", po::value(&o.output), "particle file to write (.pdp)")(
        "vtk", po::value(&o.vtk), "also write the particles as VTK PolyData (.vtp) for ParaView");
    po::variables_map vm;
    if (!pd::parse_command_line(argc, argv, "pd-mesh", visible, "geometry", vm)) return 0;
    // The geometry file is the command's one argument, as in every command
    // of the docs and the scenes (the frame also takes it as --geometry, as
    // pd-solve takes --scene: a second spelling that the help leaves out).
    // Before 7 December 2026 both errors said "no geometry file given
    // (pd-mesh --help shows the usage)", and an empty name (an unset shell
    // variable) was called none.
    const std::string example = "e.g. pd-mesh plate.geo --spacing 0.05mm --horizon 0.2mm -o plate.pdp";
    if (!vm.count("geometry"))
      throw pd::Error("no geometry file given: give the plate's .geo file as the command's one argument, " + example);
    o.geometry = vm["geometry"].as<std::string>();
    if (o.geometry.empty())
      throw pd::Error("the geometry file's name is empty (''; an unset shell variable?): give the plate's .geo file, " +
                      example);
    pd::check_usable_path(o.geometry, "");
    pd::require_regular_input(o.geometry, "the geometry file");
    if (o.output.empty()) throw pd::Error("no output file given: add -o OUT.pdp");
    // The particle file is pd-mesh's binary format; a VTK view is --vtk, PolyData (.vtp).
    const auto extension_of = [](const std::string& path) {
      std::string e = std::filesystem::path(path).extension().string();
      for (auto& ch : e) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
      return e;
    };
    for (const char* vtk : {".vtp", ".vtk", ".vtu", ".pvd"})
      if (extension_of(o.output) == vtk)
        throw pd::Error("-o " + o.output + ": the particle file is binary (.pdp, docs/formats.md), not VTK; write it "
                        "as -o NAME.pdp and the ParaView view with --vtk NAME.vtp");
    // A path the system cannot use (longer than PATH_MAX) is refused before the meshing, by its option.
    pd::check_usable_path(o.output, "-o");
    pd::check_usable_path(o.vtk, "--vtk");
    // A file whose name ends in white space that exists is replaced, the space unseen: said.
    for (const auto& [path, option] : {std::pair<std::string, std::string>{o.output, "-o"}, {o.vtk, "--vtk"}})
      if (const std::string w = pd::white_space_name_warning(path, option); !w.empty())
        std::fprintf(stderr, "pd-mesh: warning: %s\n", w.c_str());
    // A name ending in a separator, '.' or '..' is a folder's, existing or not
    // (out/new/.. through a folder yet to be made): the particle file's folder
    // would be made, the grid meshed, and only the write refused (before 7
    // December 2026, after the meshing, "is a folder, not a file").
    {
      const std::string last = std::filesystem::path(o.output).filename().string();
      if (last.empty() || last == "." || last == "..") {
        const std::string folder = pd::clipped(o.output) + (last.empty() ? "" : "/");
        throw pd::Error("-o " + pd::clipped(o.output) + ": names a folder (it ends in '" + (last.empty() ? "/" : last) +
                        "'), not the particle file: give the file's name in it, e.g. -o " + folder + "plate.pdp");
      }
    }
    pd::check_replaceable_file(o.output, "-o");
    pd::check_replaceable_file(o.vtk, "--vtk");
    // A folder it cannot write in is said now, not after the meshing (which
    // may take hours).
    pd::check_writable_folder_for(o.output, "-o");
    if (!o.vtk.empty()) pd::check_writable_folder_for(o.vtk, "--vtk");
    if (pd::same_path(o.output, o.geometry))
      throw pd::Error("-o " + o.output + " is the geometry file: the particle file would replace it");
    if (std::filesystem::is_regular_file(o.output) && !pd::begins_as_particle_file(o.output))
      throw pd::Error("-o " + o.output + ": the file exists and is not a particle file; pd-mesh replaces only a "
                      "particle file of an earlier run (another file could be yours): name a new file");
    if (!o.vtk.empty() && pd::same_path(o.vtk, o.geometry))
      throw pd::Error("--vtk " + o.vtk + " is the geometry file: the VTK file would replace it");
    if (!o.vtk.empty() && pd::same_path(o.vtk, o.output))
      throw pd::Error("--vtk " + o.vtk + " and -o name the same file: give the VTK view a name of its own (.vtp)");
    if (!o.vtk.empty() && extension_of(o.vtk) != ".vtp")
      throw pd::Error("--vtk " + o.vtk + ": a VTK view is written as NAME.vtp (VTK PolyData); another name "
                      "could be a file of yours");
    // (Before 7 December 2026 any file of that name was replaced: a run's
    // arrival.vtp or snapshot, or a file of the user's named .vtp.)
    if (!o.vtk.empty() && std::filesystem::is_regular_file(o.vtk) && !pd::is_particle_view(o.vtk))
      throw pd::Error("--vtk " + o.vtk + ": the file exists and is not a particle view of pd-mesh (a run's "
                      "arrival.vtp or snapshot, or a file of yours); pd-mesh replaces only a view of an earlier "
                      "run: name a new file");
    if (o.spacing_text.empty()) throw pd::Error("--spacing is required (e.g. --spacing 0.05mm)");
    o.spacing = pd::parse_spacing(o.spacing_text, "--spacing", "0.05mm");
    if (!o.horizon_text.empty() && vm.count("horizon-factor"))
      throw pd::Error("give either --horizon or --horizon-factor, not both");
    if (!o.horizon_text.empty()) {
      o.horizon = pd::parse_length(o.horizon_text, "--horizon");
    } else if (vm.count("horizon-factor")) {
      const std::string& m = o.horizon_factor_text;
      const bool a_length = [&] {
        try {
          return pd::parse_length(m, "--horizon-factor") > 0;
        } catch (const pd::Error&) {
          return false;
        }
      }();
      o.horizon_factor = pd::number_as_typed(m, "--horizon-factor",
                                         a_length ? "a factor is a number of spacings, without a unit (delta = m dx, "
                                                    "e.g. -m 3); a horizon as a length is --horizon " + m
                                                  : "expected a number of spacings (delta = m dx, e.g. -m 3)");
      if (!std::isfinite(o.horizon_factor))
        throw pd::Error("--horizon-factor " + pd::shortest_text(o.horizon_factor) + ": must be a finite number (e.g. 3)");
      o.horizon = o.horizon_factor * o.spacing;
    } else {
      throw pd::Error("--horizon (or --horizon-factor) is required (e.g. --horizon 0.2mm)");
    }
    if (!(o.horizon > 0))
      throw pd::Error((o.horizon_text.empty() ? "--horizon-factor " + pd::shortest_text(o.horizon_factor)
                                              : "--horizon " + o.horizon_text) +
                      ": the horizon must be positive, got " + pd::format_mm(o.horizon));
    if (o.horizon < o.spacing * (1 - 1e-12))
      throw pd::Error("the horizon " + pd::format_mm(o.horizon) + " is smaller than the spacing " +
                      pd::format_mm(o.spacing) + " (delta >= dx is required)");
    // The particle file holds horizons of at most 64 spacings (docs/formats.md).
    // Said before the geometry is read: a larger factor (1e9, a slip) made the
    // size estimate count its family cell by cell, (2m + 3)^2 cells, for minutes.
    if (o.horizon > pd::max_horizon_factor * o.spacing * (1 + 1e-12)) {
      const std::string given = o.horizon_text.empty() ? "--horizon-factor " + pd::shortest_text(o.horizon_factor)
                                                       : "--horizon " + o.horizon_text;
      char spacings[32];
      std::snprintf(spacings, sizeof spacings, "%.4g", o.horizon / o.spacing);
      throw pd::Error(given + ": the horizon " + pd::format_mm(o.horizon) + " is " + spacings + " spacings of " +
                      pd::format_mm(o.spacing) +
                      ", more than the 64 a particle file holds (docs/formats.md; 64 is already 12,000 bonds per "
                      "particle); a horizon is a few spacings (--horizon-factor 3 or 4 is usual)");
    }
    o.grid_kind = parse_grid(o.grid);
    // Only NB-NUG has boxes to pad: the other grids would drop it without a word.
    if (!o.padding_text.empty() && o.grid_kind != pd::GridKind::nbnug)
      throw pd::Error("--padding " + o.padding_text + " needs --grid nbnug (the " + o.grid +
                      " grid has no boxes around holes to pad)");
    o.padding = o.padding_text.empty() ? o.horizon : pd::parse_length(o.padding_text, "--padding");
    if (!(o.padding >= o.horizon * (1 - 1e-12)))
      throw pd::Error("--padding " + pd::format_mm(o.padding) + " is less than one horizon (" +
                      pd::format_mm(o.horizon) + "): the free cells next to the boxes' edges would see squares "
                      "inside their horizon on one side only");
    o.quadrature_kind = parse_quadrature(o.quadrature);
    if (o.bonds_across_voids != "cut" && o.bonds_across_voids != "keep")
      throw pd::Error("--bonds-across-voids: unknown value '" + o.bonds_across_voids + "' (use cut or keep)");
    o.gmsh_time_limit = pd::number_as_typed(o.gmsh_time_limit_text, "--gmsh-time-limit",
                                        "expected a number of seconds (e.g. 600 for ten minutes; the default is 300)");
    if (!(o.gmsh_time_limit > 0) || !std::isfinite(o.gmsh_time_limit))
      throw pd::Error("--gmsh-time-limit " + pd::shortest_text(o.gmsh_time_limit) +
                      ": must be a positive number of seconds");
    if (o.gmsh_time_limit < pd::GmshSession::shortest_time_limit)
      throw pd::Error("--gmsh-time-limit " + pd::shortest_text(o.gmsh_time_limit) + ": less than " +
                      pd::shortest_text(pd::GmshSession::shortest_time_limit) +
                      " s, the shortest limit taken: gmsh reads even a small geometry in tens to hundreds of ms, as "
                      "loaded as the machine is, so a shorter limit would stop some runs and not others; give at "
                      "least 1 (the default is 300)");
    if (o.gmsh_time_limit > pd::GmshSession::longest_time_limit)
      throw pd::Error("--gmsh-time-limit " + pd::shortest_text(o.gmsh_time_limit) + ": more than a year (" +
                      std::to_string(static_cast<long>(pd::GmshSession::longest_time_limit)) +
                      " s); the limit is in seconds, and gmsh takes minutes (default 300)");
    if (vm.count("loading-layer"))  // (an empty list included: it would make no layer without a word)
      o.loading_layers = pd::parse_loading_layer_edges(o.loading_layer_text, "--loading-layer");
    if (!o.loading_layer_depth_text.empty() && o.loading_layers.empty())
      throw pd::Error("--loading-layer-depth " + o.loading_layer_depth_text + " needs --loading-layer EDGE[,EDGE...]");
    o.loading_layer_depth = o.loading_layer_depth_text.empty()
                                ? o.horizon
                                : pd::parse_length(o.loading_layer_depth_text, "--loading-layer-depth");
    if (!(o.loading_layer_depth >= o.spacing * (1 - 1e-12)) || !std::isfinite(o.loading_layer_depth))
      throw pd::Error("--loading-layer-depth " + o.loading_layer_depth_text + " is less than the spacing " +
                      pd::format_mm(o.spacing) + " (at least one row of squares)");
    // A layer completes the horizons of the particles at its edge: deeper
    // than one horizon it only adds particles (a depth in the wrong unit
    // would add millions of them).
    if (o.loading_layer_depth > 10 * o.horizon * (1 + 1e-12))
      throw pd::Error("--loading-layer-depth " + o.loading_layer_depth_text + " is more than 10 horizons (" +
                      pd::format_mm(10 * o.horizon) + "): a layer one horizon deep (the default) gives the edge's "
                      "particles their whole horizon; a deeper one only adds particles");
    if (o.refine_region_text.empty() != (vm.count("refine-factor") == 0))
      throw pd::Error("--refine-region and --refine-factor go together (e.g. --refine-region 0mm,0mm,5mm,5mm "
                      "--refine-factor 2)");
    if (!o.refine_region_text.empty())
      o.refinement = pd::parse_refinement_region(o.refine_region_text, o.refine_factor_text, "--refine-region",
                                                 "--refine-factor");
    // A free mesh has no lattice squares to split.
    if (!o.refine_region_text.empty() && o.grid_kind == pd::GridKind::free)
      throw pd::Error("--refine-region " + o.refine_region_text + " needs --grid nbnug or uniform (it splits lattice "
                      "squares; a free mesh has none: give it a smaller --spacing, or --graded-spacing)");
    if (!o.box_spacing_text.empty()) {
      o.box_spacing = pd::parse_box_spacing(o.box_spacing_text, o.spacing, "--box-spacing");
      if (o.grid_kind != pd::GridKind::nbnug)
        throw pd::Error("--box-spacing " + o.box_spacing_text + " needs --grid nbnug (the " + o.grid +
                        " grid has no boxes; for a finer free grid use --grid free with a smaller --spacing)");
    }
    if (!o.horizon_smoothing_text.empty()) {
      const bool finer_boxes = o.box_spacing > 0 && o.box_spacing < o.spacing * (1 - 1e-9);
      if (o.refine_region_text.empty() && !finer_boxes)
        throw pd::Error("--horizon-smoothing " + o.horizon_smoothing_text +
                        (o.box_spacing_text.empty()
                             ? std::string("")
                             : " with --box-spacing " + o.box_spacing_text + " (= the spacing: no finer boxes)") +
                        " needs --refine-region and --refine-factor, or --box-spacing finer than the spacing (it "
                        "smooths the horizon where a finer region meets squares of side dx)");
      o.horizon_smoothing = pd::parse_smoothing_length(o.horizon_smoothing_text, "--horizon-smoothing");
    }
    if (!o.graded_spacing_text.empty()) {
      if (o.grid_kind != pd::GridKind::free)
        throw pd::Error("--graded-spacing " + o.graded_spacing_text + " needs --grid free (the " + o.grid +
                        " grid is not one free mesh; for finer NB-NUG boxes use --box-spacing)");
      o.graded = pd::parse_graded_spacing(o.graded_spacing_text, o.spacing, o.horizon, "--graded-spacing");
    }
    const double unit = pd::length_unit_in_metres(o.geo_unit, "--geo-unit");
    const double memory_budget = o.max_memory_text.empty() ? pd::available_memory_bytes()
                                                           : pd::parse_byte_size(o.max_memory_text, "--max-memory");

    // pd-solve reads the particle file by the name a scene gives (particles =),
    // whatever its ending; a name without .pdp is most often one left off
    // (-o out/c3a), which the scene's particles = "../out/c3a.pdp" would then
    // not find. Said once the options are checked, before the meshing, which
    // may take long.
    if (const std::string meant = meant_particle_file_name(o.output); !meant.empty())
      std::fprintf(stderr,
                   "pd-mesh: warning: -o %s: the particle file's name does not end in .pdp; it is written under this "
                   "name, and a scene's particles = must give the same name (or write -o %s)\n",
                   pd::clipped(o.output).c_str(), pd::clipped(meant).c_str());
    pd::StageTimes times;
    auto start = std::chrono::steady_clock::now();
    pd::GmshSession session;
    session.set_time_limit(o.gmsh_time_limit, "pd-mesh", "--gmsh-time-limit");
    const auto outline = pd::read_plate_outline(session, o.geometry, unit);
    for (const auto& warning : outline.warnings)
      std::fprintf(stderr, "pd-mesh: warning: %s: %s\n", o.geometry.c_str(), warning.c_str());
    // The plate's unit first: the checks below then fail with sizes that only it explains.
    if (const auto warning = pd::plate_unit_warning(outline, o.geo_unit); !warning.empty())
      std::fprintf(stderr, "pd-mesh: warning: %s\n", warning.c_str());
    pd::PlateSizedLengths sized;
    sized.nbnug = o.grid_kind == pd::GridKind::nbnug;
    sized.padding_text = o.padding_text, sized.padding = o.padding;
    sized.horizon = o.horizon, sized.spacing = o.spacing;
    sized.refine_region_text = o.refine_region_text, sized.refinement = &o.refinement;
    sized.graded_spacing_text = o.graded_spacing_text, sized.graded = &o.graded;
    // The warnings about lengths too large for the plate wait for the checks
    // that need the sampled curves: a refinement region refused there (no
    // square in it) gets its refusal alone. A refusal for memory, which they
    // may explain, gets them first.
    auto length_warnings = pd::check_lengths_against_plate(outline, sized);
    const auto say_length_warnings = [&] {
      for (const auto& warning : length_warnings) std::fprintf(stderr, "pd-mesh: warning: %s\n", warning.c_str());
      length_warnings.clear();
    };
    const std::string budget_option = o.max_memory_text.empty() ? "" : "--max-memory " + o.max_memory_text;
    const auto check_estimate = [&](const pd::ResourceEstimate& e) {
      try {
        pd::check_resources(o.geometry, e, memory_budget, budget_option);
      } catch (...) {
        say_length_warnings();
        throw;
      }
    };
    // Refuse what cannot fit before sampling and meshing anything.
    // A refined cell holds factor^2 particles with as many bonds each as a coarse one.
    // With --horizon-smoothing, a square of the band has on average at most
    // (F^2 + F + 1) / 3 times the family of m (the mean of (delta / delta_f)^2
    // over the linear ramp; less where its disk covers coarse cells).
    double refined_extra_area = 0, smoothed_extra_bond_area = 0;
    if (o.refinement.factor > 1) {
      const auto snapped = pd::snap_to_lattice(o.refinement, o.spacing, outline.xmin, outline.ymin, outline.xmax,
                                               outline.ymax, "--refine-region");
      const double f = o.refinement.factor;
      refined_extra_area = snapped.area(o.spacing) * (f * f - 1);
      const double band =
          pd::smoothing_band_area(snapped, o.spacing, std::lround((outline.xmax - outline.xmin) / o.spacing),
                                  std::lround((outline.ymax - outline.ymin) / o.spacing), o.horizon_smoothing);
      smoothed_extra_bond_area = band * f * f * ((f * f + f + 1) / 3 - 1);
    }
    // The loading layers' squares: each side's length plus the corners, times the depth (a bound).
    double layer_area = 0;
    for (const auto& edge : o.loading_layers) {
      const bool vertical = edge == "left" || edge == "right";
      const double depth = pd::loading_layer_rows(o.loading_layer_depth, o.spacing) * o.spacing;
      layer_area += ((vertical ? outline.ymax - outline.ymin : outline.xmax - outline.xmin) + 2 * depth) * depth;
    }
    refined_extra_area += layer_area;
    auto estimate = pd::estimate_resources(outline.area + refined_extra_area, o.spacing, o.horizon,
                                           o.quadrature_kind, smoothed_extra_bond_area);
    check_estimate(estimate);
    // The curves' samples are the free cells' nodes on them: as far apart as those cells are large.
    const double free_cell_size = o.box_spacing > 0 ? o.box_spacing : o.spacing;
    // A graded mesh's curves are sampled at its fine size, its straight edges at dx.
    const auto geometry = pd::sample_plate(session, outline, free_cell_size, o.graded.fine);
    if (o.graded.enabled()) {
      // Now that the curves are known: the graded band's extra cells.
      estimate = pd::estimate_resources(outline.area + refined_extra_area + pd::graded_extra_area(geometry, o.graded),
                                        o.spacing, o.horizon, o.quadrature_kind, smoothed_extra_bond_area);
      check_estimate(estimate);
    }
    if (o.box_spacing > 0 && o.box_spacing < o.spacing) {
      // Now that the holes are known: their finer boxes' cells.
      const auto boxes = pd::finer_boxes_estimate(geometry, o.spacing, o.box_spacing, o.padding, o.horizon_smoothing);
      estimate = pd::estimate_resources(outline.area + refined_extra_area + boxes.extra_area, o.spacing, o.horizon,
                                        o.quadrature_kind, smoothed_extra_bond_area + boxes.smoothed_extra_bond_area);
      check_estimate(estimate);
    }
    times.seconds.push_back({"geometry", seconds_since(start)});

    start = std::chrono::steady_clock::now();
    pd::GridReport report;
    const pd::MeshWorker worker("/proc/self/exe", o.gmsh_time_limit, "--gmsh-time-limit");
    pd::GridOptions grid_options{o.grid_kind, o.spacing, o.padding, free_cell_size, &worker, o.graded};
    grid_options.before_meshing = [&](const pd::ParticleSet& squares) {
      // Which squares a region holds is known once the lattice's cells are
      // (the boxes around curves off its lines): said before gmsh meshes
      // (before 7 December 2026, after the meshing, and after the warning
      // that a region of ten plates is in another unit).
      if (o.refinement.factor > 1 && pd::region_squares(squares, o.refinement, "--refine-region") == 0)
        throw pd::Error("--refine-region " + o.refine_region_text + ": no lattice square of the plate lies in it");
      say_length_warnings();
    };
    auto particles = pd::build_grid(session, geometry, grid_options, report);
    if (o.refinement.factor > 1) pd::refine_squares(particles, o.refinement, "--refine-region");
    if (!o.loading_layers.empty())
      pd::append_loading_layers(particles, geometry, o.loading_layers, o.loading_layer_depth, "--loading-layer");
    pd::sort_particles_spatially(particles);
    // Every boundary on lattice lines: no box to mesh finer (or to smooth).
    if (o.box_spacing > 0 && o.box_spacing < o.spacing * (1 - 1e-9) && report.free_regions == 0)
      std::fprintf(stderr,
                   "pd-mesh: warning: %s: --box-spacing %s changes nothing: every boundary of this plate lies on "
                   "lattice lines, so it has no box of free cells to mesh finer%s\n",
                   o.geometry.c_str(), o.box_spacing_text.c_str(),
                   o.horizon_smoothing > 0 && o.refinement.factor <= 1
                       ? " (nor --horizon-smoothing any box cell to smooth)"
                       : "");
    times.seconds.push_back({"grid", seconds_since(start)});

    start = std::chrono::steady_clock::now();
    pd::assign_horizons(particles, o.horizon, o.box_spacing);
    if (o.graded.enabled()) pd::assign_graded_horizons(particles, geometry, o.graded);
    if (o.refinement.factor > 1) {
      const auto smoothing = pd::smooth_horizons(particles, o.refinement, o.horizon_smoothing, "--refine-region");
      warn_if_no_fine_horizon_left(o.geometry, o.horizon_smoothing_text, o.horizon_smoothing, smoothing,
                                   particles.horizon_nominal,
                                   "the refinement region's innermost square to its edges that face coarse squares",
                                   "refined square", "the region's middle");
      warn_if_nothing_to_ramp_to(o.geometry, o.horizon_smoothing_text, smoothing, "refined square",
                                 "the refinement region covers the plate's bounding box, so no refined square has a "
                                 "square of side dx beside it");
    }
    std::size_t smoothed_box_cells = 0;
    if (o.box_spacing > 0 && o.box_spacing < o.spacing * (1 - 1e-9)) {
      const auto smoothing = pd::smooth_box_horizons(particles, o.horizon_smoothing);
      smoothed_box_cells = smoothing.grown;
      warn_if_no_fine_horizon_left(o.geometry, o.horizon_smoothing_text, o.horizon_smoothing, smoothing,
                                   particles.horizon_nominal, "the boxes' innermost cell to the squares of side dx",
                                   "box cell", "the boxes' cells farthest from the squares");
      warn_if_nothing_to_ramp_to(o.geometry, o.horizon_smoothing_text, smoothing, "box cell",
                                 "no square of side dx is left in the plate (the refinement region covers it)");
    }
    // Now that the cells and horizons are known, before the families take
    // their memory: the bonds from the particles' density within each
    // horizon. Free cells far below their target size (around holes narrower
    // than the spacing) multiply the bonds per particle, which the estimate
    // from the area alone cannot see.
    pd::ResourceEstimate meshed;
    std::vector<std::string> small_cells_remedies;
    {
      const auto family_sizes = pd::estimate_family_sizes(particles);  // (freed before the families)
      meshed = pd::resources_of(static_cast<double>(particles.size()),
                                std::accumulate(family_sizes.begin(), family_sizes.end(), 0.0));
      const auto small_cells = pd::find_small_free_cells(particles, family_sizes, o.box_spacing);
      small_cells_remedies = pd::small_free_cells_remedies(small_cells, particles, o.box_spacing, o.graded.fine);
      pd::ResourceAdvice advice;
      advice.grid = "once meshed, this grid";
      if (small_cells.forced()) {
        advice.cause = pd::small_free_cells_cause(small_cells, particles);
        advice.remedies = small_cells_remedies;
      }
      pd::check_resources(o.geometry, meshed, memory_budget, budget_option, advice);
    }
    // With layers, bonds may cross the loaded edges into the layers.
    const auto boundary = o.loading_layers.empty()
                              ? pd::material_boundary(geometry, o.spacing, o.horizon)
                              : pd::material_boundary_with_layers(geometry, o.spacing, o.horizon, o.loading_layers,
                                                                  o.loading_layer_depth);
    // The families take most of a long run (a fine refinement region): a
    // progress line every 10 s on stderr; runs shorter than that print none.
    const auto families_start = std::chrono::steady_clock::now();
    double next_report_s = 10;
    const pd::FamilyProgress families_progress = [&](std::size_t done, std::size_t total) {
      const double elapsed = seconds_since(families_start);
      if (elapsed < next_report_s || done == 0) return;
      next_report_s = elapsed + 10;
      std::fprintf(stderr, "pd-mesh: families: %.0f %% of %zu particles (%.3g bonds estimated), %.0f s, about %.0f s left\n",
                   100.0 * static_cast<double>(done) / static_cast<double>(total), total, meshed.bonds, elapsed,
                   elapsed * (static_cast<double>(total) / static_cast<double>(done) - 1));
    };
    const auto families = pd::build_families(particles, o.quadrature_kind,
                                             o.bonds_across_voids == "cut" ? &boundary : nullptr, families_progress);
    times.seconds.push_back({"families", seconds_since(start)});
    // Timed apart: along holes of many chords they once took longer than the families.
    start = std::chrono::steady_clock::now();
    for (const auto& warning : pd::add_boundary_sets(particles, geometry, o.horizon))
      std::fprintf(stderr, "pd-mesh: warning: %s: %s\n", o.geometry.c_str(), warning.c_str());
    if (!o.loading_layers.empty()) pd::add_loading_layer_sets(particles, geometry, o.loading_layers);
    times.seconds.push_back({"sets", seconds_since(start)});
    start = std::chrono::steady_clock::now();
    // Voids narrower than 4 dx: their width, and what the grid makes of it.
    auto narrow = pd::narrow_voids(geometry, o.spacing, 4 * o.spacing);
    if (o.grid_kind == pd::GridKind::uniform) pd::measure_resolved_widths(narrow, report.cells);
    // And the mirror image: material narrower than dx that the uniform grid drops.
    const auto lost = o.grid_kind == pd::GridKind::uniform ? pd::lost_ligaments(geometry, report.cells)
                                                           : std::vector<pd::LostLigament>{};
    times.seconds.push_back({"narrow voids", seconds_since(start)});

    start = std::chrono::steady_clock::now();
    particles.provenance = provenance(o);
    // The view first: a failed write leaves no particle file that looks whole,
    // and no folder made for it.
    // Their errors name the option as well as the path (before 7 December
    // 2026 the path alone, "PATH: write failed (disk full?)").
    const auto by_option = [](const char* option, auto&& step) {
      try {
        return step();
      } catch (const pd::Error& e) {
        throw pd::Error(std::string(option) + " " + e.what());
      }
    };
    std::vector<std::string> made = by_option("-o", [&] { return pd::create_folder_for(o.output); });
    bool view_written = false;
    try {
      if (!o.vtk.empty()) {
        const auto made_for_view = by_option("--vtk", [&] { return pd::create_folder_for(o.vtk); });
        made.insert(made.end(), made_for_view.begin(), made_for_view.end());
        by_option("--vtk", [&] { pd::write_particles_vtp(o.vtk, particles); });
        view_written = true;
      }
      by_option("-o", [&] { pd::write_particle_file(o.output, particles); });
    } catch (...) {
      // The view just written shows particles that no particle file holds
      // (beside an earlier run's file under -o's name, a grid it is not):
      // taken back with the failed command.
      std::error_code ignored;
      if (view_written) std::filesystem::remove(o.vtk, ignored);
      pd::remove_made_folders(made);
      throw;
    }
    times.seconds.push_back({"write", seconds_since(start)});

    pd::print_mesh_summary(std::cout,
                           {particles, geometry, report, families, narrow, estimate, meshed, times, smoothed_box_cells});
    warn_about_coarse_grid(particles);
    warn_about_small_free_cells(o.geometry, particles, narrow, small_cells_remedies, o.box_spacing);
    warn_about_pieces(o.geometry, particles, o.grid);
    warn_about_lost_ligaments(o.geometry, lost, o.spacing);
    std::cout << "wrote " << o.output << (o.vtk.empty() ? "" : " and " + o.vtk) << "\n";
    return 0;
  });
}
