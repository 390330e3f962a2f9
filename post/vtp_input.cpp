#include "vtp_input.hpp"

#include <vtkAbstractArray.h>
#include <vtkDataArray.h>
#include <vtkFieldData.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkStringArray.h>
#include <vtkVariant.h>
#include <vtkXMLPolyDataReader.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "error.hpp"
#include "input_file.hpp"
#include "particle_file.hpp"
#include "quiet_vtk.hpp"
#include "results_format.hpp"
#include "statistics.hpp"
#include "units.hpp"

namespace pd::post {
namespace {

vtkDataArray* point_data_array(vtkPolyData* poly, const std::string& path, const char* name) {
  vtkDataArray* a = poly->GetPointData()->GetArray(name);
  if (a != nullptr && a->GetNumberOfTuples() != poly->GetNumberOfPoints())
    throw file_error(path, std::string("point array '") + name + "' has " + std::to_string(a->GetNumberOfTuples()) +
                               " values for " + std::to_string(poly->GetNumberOfPoints()) + " points");
  return a;
}

}  // namespace

vtkSmartPointer<vtkPolyData> read_vtp_quietly(const std::string& path, const std::string& what) {
  // A folder or a device is no missing file (before 7 December 2026 both were
  // "file not found", of a path that was there).
  require_regular_input(path, what);
  if (!std::filesystem::is_regular_file(path)) throw file_error(path, "file not found");
  QuietVtk quiet;
  vtkNew<vtkXMLPolyDataReader> reader;
  reader->SetFileName(path.c_str());
  reader->Update();
  vtkPolyData* poly = reader->GetOutput();
  if (quiet.failed() || reader->GetErrorCode() != 0 || poly == nullptr || poly->GetPoints() == nullptr) {
    const std::string why = quiet.first_message();
    throw file_error(path, "not a readable VTK PolyData (.vtp) file" + (why.empty() ? std::string() : ": " + why));
  }
  auto copy = vtkSmartPointer<vtkPolyData>::New();
  copy->ShallowCopy(poly);
  return copy;
}

std::vector<double> read_point_array(vtkPolyData* poly, const std::string& path, const char* name,
                                     bool required) {
  vtkDataArray* a = point_data_array(poly, path, name);
  if (a == nullptr) {
    if (required) throw file_error(path, std::string("no point array '") + name + "'");
    return {};
  }
  if (a->GetNumberOfComponents() != 1)
    throw file_error(path, std::string("point array '") + name + "' must have one component");
  // pd-solve writes finite values only (an arrival time never reached is
  // -1): a NaN or an infinity is a damaged or edited file. Refused here, as
  // the colour maps and the sorting of values cannot take them (before 7
  // December 2026 a NaN in 'cell_size' or 'strain_energy_density' crashed
  // pd-post while drawing).
  std::vector<double> v(static_cast<std::size_t>(a->GetNumberOfTuples()));
  for (std::size_t i = 0; i < v.size(); ++i) {
    v[i] = a->GetTuple1(static_cast<vtkIdType>(i));
    if (!std::isfinite(v[i]))
      throw file_error(path, std::string("point array '") + name + "' is " + shortest_text(v[i]) + " at particle " +
                                 std::to_string(i) + ": not a finite number (pd-solve writes none)");
  }
  return v;
}

bool read_vector_array(vtkPolyData* poly, const std::string& path, const char* name, std::vector<double>& x,
                       std::vector<double>& y) {
  x.clear(), y.clear();
  vtkDataArray* a = point_data_array(poly, path, name);
  if (a == nullptr) return false;
  if (a->GetNumberOfComponents() < 2 || a->GetNumberOfComponents() > 3)
    throw file_error(path, std::string("point array '") + name + "' must have 2 or 3 components");
  x.resize(static_cast<std::size_t>(a->GetNumberOfTuples()));
  y.resize(x.size());
  for (std::size_t i = 0; i < x.size(); ++i) {
    x[i] = a->GetComponent(static_cast<vtkIdType>(i), 0);
    y[i] = a->GetComponent(static_cast<vtkIdType>(i), 1);
    if (!std::isfinite(x[i]) || !std::isfinite(y[i]))
      throw file_error(path, std::string("point array '") + name + "' is not finite at particle " + std::to_string(i));
  }
  return true;
}

std::vector<double> read_field_values(vtkPolyData* poly, const char* name) {
  vtkFieldData* fd = poly->GetFieldData();
  vtkDataArray* a = fd ? fd->GetArray(name) : nullptr;
  if (a == nullptr) return {};
  std::vector<double> v;
  for (vtkIdType i = 0; i < a->GetNumberOfTuples(); ++i) v.push_back(a->GetComponent(i, 0));
  return v;
}

std::optional<double> read_field_number(vtkPolyData* poly, const std::string& path, const char* name) {
  vtkFieldData* fd = poly->GetFieldData();
  vtkAbstractArray* a = fd ? fd->GetAbstractArray(name) : nullptr;
  if (a == nullptr || a->GetNumberOfTuples() == 0) return std::nullopt;
  // (Before 7 December 2026 a text there was read as no field at all, and
  // its fallback taken with a note saying the field was missing.)
  if (vtkDataArray::SafeDownCast(a) == nullptr)
    throw file_error(path, std::string("field '") + name + "' is " + clipped(a->GetVariantValue(0).ToString()) +
                               ", a text: pd-solve writes a number there (an edited or damaged file)");
  const double v = vtkDataArray::SafeDownCast(a)->GetComponent(0, 0);
  if (!std::isfinite(v))
    throw file_error(path, std::string("field '") + name + "' is " + shortest_text(v) +
                               ": not a finite number (pd-solve writes none)");
  return v;
}

LengthFields read_length_fields(vtkPolyData* poly, const std::string& path, const std::vector<double>& cell_size) {
  LengthFields f;
  f.spacing = read_field_number(poly, path, results::field_spacing);
  f.horizon = read_field_number(poly, path, results::field_horizon);
  const double cell = cell_size.empty() ? 0.0 : median(cell_size);
  char text[480];
  // Before 7 December 2026 a spacing of 1e-300 m made the speed window 1
  // step, and a horizon of 1e300 m one front of every crack, exit 0.
  if (f.spacing) {
    const double dx = *f.spacing;
    if (!(dx >= min_spacing_m && dx <= max_spacing_m)) {
      std::snprintf(text, sizeof text,
                    "field '%s' = %g m is no particle file's spacing (%g to %g m): an edited or damaged file",
                    results::field_spacing, dx, min_spacing_m, max_spacing_m);
      throw file_error(path, text);
    }
    if (cell > 0 && (dx > max_spacing_to_cell_ratio * cell || cell > max_spacing_to_cell_ratio * dx)) {
      std::snprintf(text, sizeof text,
                    "field '%s' = %g m is more than %g times %s the particles' median cell size, %g m (point array "
                    "'%s'): pd-solve writes the particle file's spacing, which its cells follow (an edited or "
                    "damaged file)",
                    results::field_spacing, dx, max_spacing_to_cell_ratio, dx > cell ? "larger than" : "smaller than",
                    cell, results::cell_size);
      throw file_error(path, text);
    }
  }
  if (f.horizon) {
    const double h = *f.horizon;
    // Against the spacing, else the median cell; with neither, the particle file's bounds.
    const double dx = f.spacing ? *f.spacing : cell;
    const char* by = f.spacing ? "the spacing (field 'spacing')" : "the median cell size";
    constexpr double round_off = 1e-9;
    const double lo = dx > 0 ? dx / max_refinement_ratio : min_spacing_m / max_refinement_ratio;
    const double hi = (dx > 0 ? dx : max_spacing_m) * max_horizon_factor;
    if (!(h >= lo * (1 - round_off) && h <= hi * (1 + round_off))) {
      if (dx > 0)
        std::snprintf(text, sizeof text,
                      "field '%s' = %g m is %.3g times %s, %g m: a run's horizon is 1/%g to %g times it (an edited "
                      "or damaged file)",
                      results::field_horizon, h, h / dx, by, dx, max_refinement_ratio, max_horizon_factor);
      else
        std::snprintf(text, sizeof text, "field '%s' = %g m is no run's horizon (%g to %g m): an edited or damaged file",
                      results::field_horizon, h, lo, hi);
      throw file_error(path, text);
    }
  }
  return f;
}

std::string read_field_text(vtkPolyData* poly, const char* name) {
  vtkFieldData* fd = poly->GetFieldData();
  auto* a = fd ? vtkStringArray::SafeDownCast(fd->GetAbstractArray(name)) : nullptr;
  if (a == nullptr || a->GetNumberOfValues() == 0) return {};
  return a->GetValue(0);
}

std::vector<double> checked_damage(std::vector<double> values, const std::string& path, const char* array) {
  // Single-precision round-off of a damage index near 0 or 1.
  constexpr double round_off = 1e-6;
  for (std::size_t i = 0; i < values.size(); ++i) {
    double& v = values[i];
    if (!(v >= -round_off && v <= 1.0 + round_off)) {
      char value[32];
      std::snprintf(value, sizeof value, "%.9g", v);
      throw file_error(path, std::string("point array '") + array + "' is " + value + " at particle " +
                                 std::to_string(i) + ", outside [0, 1]");
    }
    v = std::clamp(v, 0.0, 1.0);
  }
  return values;
}

std::vector<double> checked_sizes(std::vector<double> values, const std::string& path, const char* array,
                                  bool areas) {
  for (std::size_t i = 0; i < values.size(); ++i)
    if (!(values[i] > 0))
      throw file_error(path, std::string("point array '") + array + "' is " + shortest_text(values[i]) +
                                 " at particle " + std::to_string(i) + ": not a positive size (pd-solve writes "
                                 "every particle's; an edited or damaged file)");
  // One cell far larger than the rest (a cell_size edited to 1e30 m) makes
  // the plate's extent, and every picture and raster over it, that cell:
  // before 7 December 2026 the plate was drawn as one cell 2e33 mm wide,
  // exit 0. pd-solve's cells follow the particle file's spacing (refined
  // squares down to 1/64 of it), none of them near this many times the median.
  const auto side = [areas](double v) { return areas ? std::sqrt(v) : v; };
  const auto largest = std::max_element(values.begin(), values.end());
  const double typical = side(median(values));
  if (largest != values.end() && side(*largest) > max_spacing_to_cell_ratio * typical) {
    char text[480];
    std::snprintf(text, sizeof text,
                  "point array '%s' is %g at particle %zu, %s%.3g times the particles' median cell size, %g m: "
                  "pd-solve's cells follow the particle file's spacing, none more than %g times the median (an "
                  "edited or damaged file)",
                  array, *largest, static_cast<std::size_t>(largest - values.begin()),
                  areas ? "a cell whose side (its square root) is " : "", side(*largest) / typical, typical,
                  max_spacing_to_cell_ratio);
    throw file_error(path, text);
  }
  return values;
}

void read_points(vtkPolyData* poly, const std::string& path, std::vector<double>& x, std::vector<double>& y) {
  const vtkIdType n = poly->GetNumberOfPoints();
  if (n == 0) throw file_error(path, "no particles");
  x.resize(static_cast<std::size_t>(n));
  y.resize(static_cast<std::size_t>(n));
  for (vtkIdType i = 0; i < n; ++i) {
    double p[3];
    poly->GetPoint(i, p);
    if (!std::isfinite(p[0]) || !std::isfinite(p[1]))
      throw file_error(path, "point " + std::to_string(i) + " is not finite");
    x[i] = p[0];
    y[i] = p[1];
  }
  // A plate's particles lie together: one far beyond the rest (a point
  // edited to 1e30 m) makes the plate's extent, and every raster and
  // picture over it, absurd (before 7 December 2026 pd-post failed on it
  // with a message that named no file). Measured from the middle (the
  // medians of x and y) in the distance within which half the particles
  // lie, robust against the one point: a refined region that holds most
  // particles lies within a few dozen of those of the plate's edge.
  const double mx = median(x), my = median(y);
  std::vector<double> distance(x.size());
  for (std::size_t i = 0; i < x.size(); ++i) distance[i] = std::hypot(x[i] - mx, y[i] - my);
  const double half_within = median(distance);
  if (!(half_within > 0)) return;  // half of them at one place: no size to measure by
  const auto farthest = std::max_element(distance.begin(), distance.end());
  if (*farthest <= far_point_factor * half_within) return;
  const std::size_t i = static_cast<std::size_t>(farthest - distance.begin());
  char text[400];
  std::snprintf(text, sizeof text,
                "points: particle %zu is at (%g, %g) m, %.3g times farther from the plate's middle (%.3g, %.3g) "
                "m than the %.3g m within which half its particles lie: not a plate's particle (an edited or "
                "damaged file)",
                i, x[i], y[i], *farthest / half_within, mx, my, half_within);
  throw file_error(path, text);
}

void check_positions_resolved(const std::string& path, const std::vector<double>& x, const std::vector<double>& y,
                              const std::vector<double>& cell_size) {
  for (std::size_t i = 0; i < x.size() && i < cell_size.size(); ++i) {
    const double round_off = std::max(std::abs(x[i]), std::abs(y[i])) * 0x1p-52;
    if (round_off <= position_round_off_per_cell * cell_size[i]) continue;
    char text[480];
    std::snprintf(text, sizeof text,
                  "points: particle %zu is at (%g, %g) m, so far from the origin that its position's round-off, "
                  "%.3g m, is more than a millionth of its cell (%g mm): its cells cannot be told apart there (an "
                  "edited or damaged file); pd-mesh writes a plate where its geometry file draws it",
                  i, x[i], y[i], round_off, cell_size[i] * 1e3);
    throw file_error(path, text);
  }
}

}  // namespace pd::post
