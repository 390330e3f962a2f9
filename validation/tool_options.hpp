#pragma once
// The command line of the validation tools (pd-validate-c1, -c2, -crack):
// their geometry argument, output folder, lengths, numbers and counts, each
// checked before any mesh or solve, refused as the other tools refuse
// (one line naming the option and the value, and what to do). Before 7
// December 2026 Boost read their numbers ("the argument ('abc') for option
// '--tolerance' is invalid"), std::stod their factors ("stod"), a negative
// --threads was ignored, and a bad item late in a list was found after
// the solves before it.
#include <omp.h>

#include <algorithm>
#include <boost/program_options.hpp>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <string>
#include <thread>
#include <vector>

#include "atomic_file.hpp"
#include "cli.hpp"
#include "error.hpp"
#include "geo_file_check.hpp"
#include "input_file.hpp"
#include "particle_file.hpp"
#include "units.hpp"

namespace pd::validation {

// The comma-separated items of `list`, split as every tool splits its lists
// (pd::comma_items: blanks around an item are not part of it); an empty item
// (`0.1mm,,0.05mm`, a trailing comma) is refused naming its place, and so is
// a list of none. Before 7 December 2026 split here its own way: blanks were
// part of the item (`--variants 'force_only, force_and_dilatation'`: "unknown
// variant ' force_and_dilatation'"), and the empty item's place was unsaid.
inline std::vector<std::string> list_items(const std::string& list, const std::string& option,
                                           const std::string& example) {
  const std::vector<std::string> items = comma_items(list);
  if (items.empty() || (items.size() == 1 && items.front().empty()))
    throw Error(option + ": the list is empty: give at least one item, e.g. " + option + " " + example);
  for (std::size_t k = 0; k < items.size(); ++k)
    if (items[k].empty())
      throw Error(option + " '" + clipped(list) + "': item " + std::to_string(k + 1) + " is empty: give a "
                  "comma-separated list without empty items, e.g. " + option + " " + example);
  return items;
}

// --grids: a list of grid kinds by the names pd-mesh's --grid takes.
inline std::vector<GridKind> grids_option(const std::string& list) {
  std::vector<GridKind> kinds;
  for (const auto& name : list_items(list, "--grids", "uniform,free,nbnug")) {
    const auto kind = grid_kind_named(name);
    if (!kind) throw Error("--grids: unknown grid '" + name + "' (use uniform, free or nbnug)");
    kinds.push_back(*kind);
  }
  return kinds;
}

// A grid spacing with its unit, in the range a particle file holds
// (parse_spacing: pd-mesh's words).
inline double spacing_option(const std::string& text, const std::string& option = "--spacing") {
  return parse_spacing(text, option, "0.1mm");
}

// A plain number (no unit) from `low` to `high`: one message, pd-mesh's form
// ("OPTION TEXT: expected ..."), for a text that is no number and for one
// out of range.
inline double number_option(const std::string& text, const std::string& option, double low, double high,
                            const std::string& example) {
  const std::string advice =
      "expected " + example + " from " + format_number(low) + " to " + format_number(high);
  const double value = number_as_typed(text, option, advice);
  if (!(value >= low && value <= high)) throw Error(option + " " + clipped(text) + ": " + advice);
  return value;
}

// An FEM element size (at the hole, at the crack tips): positive, and not
// below 1/32 of the finest grid spacing `finest` (a reference that fine
// has about 1000 times the particles' count of elements near the hole;
// before 7 December 2026 --fem-size 1e-6mm left gmsh meshing without end).
inline constexpr double finest_fem_size_per_spacing = 1.0 / 32;
inline double fem_size_option(const std::string& text, const std::string& option, double finest) {
  const double h = parse_positive_length(text, option);
  if (h < finest * finest_fem_size_per_spacing * (1 - 1e-12))
    throw Error(option + " " + clipped(text) + ": less than 1/32 of the finest spacing (" + format_mm(finest) +
                "): more elements than a reference needs, which gmsh would mesh for hours; give at least " +
                format_mm(finest * finest_fem_size_per_spacing));
  return h;
}

// The horizon factor m = delta / dx: from 1 to the 64 a particle file holds.
inline double horizon_factor_option(const std::string& text, const std::string& option = "--horizon-factor") {
  return number_option(text, option, 1, max_horizon_factor, "a number of spacings (delta = m dx, e.g. -m 4)");
}

// A whole number from `low` to `high`.
inline long count_option(const std::string& text, const std::string& option, long low, long high,
                         const std::string& what) {
  const std::string advice =
      "expected a whole number of " + what + " from " + std::to_string(low) + " to " + std::to_string(high);
  const double value = number_as_typed(text, option, advice);
  if (!(value >= static_cast<double>(low) && value <= static_cast<double>(high)) || value != std::floor(value))
    throw Error(option + " " + clipped(text) + ": " + advice);
  return static_cast<long>(value);
}

// --threads: 0 (OpenMP's default) or a count, set at once. A count above the
// machine's hardware threads is capped to them with a note, as pd-solve caps
// it (a script written for a larger machine still runs).
inline void set_threads(const std::string& text, const std::string& tool) {
  const long most = std::max(1u, std::thread::hardware_concurrency());
  constexpr long largest_count = 1L << 20;
  const long threads = count_option(text, "--threads", 0, largest_count,
                                    "OpenMP threads (0: the default; this machine has " + std::to_string(most) +
                                        " hardware threads)");
  if (threads > most)
    std::cerr << tool << ": note: --threads " << threads << " is more than the " << most
              << " hardware threads of this machine; using " << most << "\n";
  if (threads > 0) omp_set_num_threads(static_cast<int>(std::min(threads, most)));
}

// The geometry file, the command's one argument: given, a regular file that
// exists, and geometry (check_geometry_file_is_data).
inline std::string geometry_argument(const boost::program_options::variables_map& vm, const std::string& example) {
  if (!vm.count("geometry") || vm["geometry"].as<std::string>().empty())
    throw Error("no geometry file given: give the plate's .geo file as the command's one argument, e.g. " + example);
  const std::string geo = vm["geometry"].as<std::string>();
  check_usable_path(geo, "");
  require_regular_input(geo, "the geometry file");
  std::error_code error;
  if (!std::filesystem::exists(geo, error)) throw file_error(clipped(geo), "not found (the geometry file)");
  // An empty file, a binary one or a script that runs commands: said now, as
  // pd-mesh says it, not when the first grid is made.
  static_cast<void>(check_geometry_file_is_data(geo));
  return geo;
}

}  // namespace pd::validation
