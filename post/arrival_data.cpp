#include "arrival_data.hpp"

#include <vtkDataArray.h>
#include <vtkFieldData.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkXMLPolyDataReader.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>

#include "error.hpp"
#include "results_format.hpp"

namespace fs = std::filesystem;

namespace pd::post {
namespace {

vtkSmartPointer<vtkPolyData> read_polydata(const std::string& path) {
  if (!fs::is_regular_file(path)) throw file_error(path, "file not found");
  vtkNew<vtkXMLPolyDataReader> reader;
  reader->SetFileName(path.c_str());
  reader->Update();
  vtkPolyData* poly = reader->GetOutput();
  if (reader->GetErrorCode() != 0 || poly == nullptr || poly->GetPoints() == nullptr)
    throw file_error(path, "not a readable VTK PolyData (.vtp) file");
  vtkSmartPointer<vtkPolyData> copy = vtkSmartPointer<vtkPolyData>::New();
  copy->ShallowCopy(poly);
  return copy;
}

std::vector<double> point_array(vtkPolyData* poly, const std::string& path, const char* name,
                                bool required) {
  vtkDataArray* a = poly->GetPointData()->GetArray(name);
  if (a == nullptr) {
    if (required) throw file_error(path, std::string("no point array '") + name + "'");
    return {};
  }
  if (a->GetNumberOfComponents() != 1)
    throw file_error(path, std::string("point array '") + name + "' must have one component");
  std::vector<double> v(static_cast<std::size_t>(a->GetNumberOfTuples()));
  for (std::size_t i = 0; i < v.size(); ++i) v[i] = a->GetTuple1(static_cast<vtkIdType>(i));
  return v;
}

std::vector<double> field_values(vtkPolyData* poly, const char* name) {
  vtkFieldData* fd = poly->GetFieldData();
  vtkDataArray* a = fd ? fd->GetArray(name) : nullptr;
  if (a == nullptr) return {};
  std::vector<double> v;
  for (vtkIdType i = 0; i < a->GetNumberOfTuples(); ++i) v.push_back(a->GetComponent(i, 0));
  return v;
}

double required_field(vtkPolyData* poly, const std::string& path, const char* name) {
  const auto v = field_values(poly, name);
  if (v.empty()) throw file_error(path, std::string("no field data '") + name + "'");
  return v.front();
}

double median(std::vector<double> v) {
  if (v.empty()) return 0;
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

}  // namespace

std::string arrival_array_name(double threshold) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%s%.2f", results::arrival_prefix, threshold);
  return buf;
}

ArrivalData read_arrival_data(const std::string& outdir, double threshold) {
  if (!fs::is_directory(outdir)) throw file_error(outdir, "solver output directory not found");
  const std::string path = (fs::path(outdir) / results::arrival_file).string();
  if (!fs::is_regular_file(path))
    throw file_error(path, "file not found (pd-post needs the solver's arrival-time file)");
  auto poly = read_polydata(path);

  ArrivalData d;
  d.path = path;
  const vtkIdType n = poly->GetNumberOfPoints();
  if (n == 0) throw file_error(path, "no particles");
  d.x.resize(n);
  d.y.resize(n);
  for (vtkIdType i = 0; i < n; ++i) {
    double p[3];
    poly->GetPoint(i, p);
    d.x[i] = p[0];
    d.y[i] = p[1];
  }
  d.cell_size = point_array(poly, path, results::cell_size, false);
  if (d.cell_size.empty()) {
    // Square cells of the particle volume are the next best estimate.
    const auto volume = point_array(poly, path, results::volume, true);
    for (double v : volume) d.cell_size.push_back(std::sqrt(std::max(v, 0.0)));
    d.notes.push_back("no 'cell_size' array: cell sizes taken as sqrt(volume)");
  }
  d.damage = point_array(poly, path, results::damage, true);
  d.strain_energy_density = point_array(poly, path, results::strain_energy_density, false);

  // Every arrival array present, so damage maps at given times can be rebuilt.
  std::vector<std::string> available;
  vtkPointData* pd_ = poly->GetPointData();
  const std::string prefix = results::arrival_prefix;
  for (int k = 0; k < pd_->GetNumberOfArrays(); ++k) {
    const char* name = pd_->GetArrayName(k);
    if (name == nullptr || std::string(name).rfind(prefix, 0) != 0) continue;
    available.push_back(name);
    ArrivalField f;
    f.threshold = std::atof(name + prefix.size());
    f.time = point_array(poly, path, name, true);
    d.arrivals.push_back(std::move(f));
  }
  std::sort(d.arrivals.begin(), d.arrivals.end(),
            [](const ArrivalField& a, const ArrivalField& b) { return a.threshold < b.threshold; });

  const std::string wanted = arrival_array_name(threshold);
  if (!pd_->GetArray(wanted.c_str())) {
    std::string list;
    for (const auto& a : available) list += (list.empty() ? "" : ", ") + a;
    throw file_error(path, "no point array '" + wanted + "' for damage threshold " +
                               wanted.substr(prefix.size()) + " (available: " +
                               (list.empty() ? "none" : list) + ")");
  }
  d.arrival = point_array(poly, path, wanted.c_str(), true);
  d.threshold = threshold;

  d.youngs_modulus = required_field(poly, path, results::field_youngs_modulus);
  d.density = required_field(poly, path, results::field_density);
  d.time_step = required_field(poly, path, results::field_time_step);
  if (d.youngs_modulus <= 0 || d.density <= 0 || d.time_step <= 0)
    throw file_error(path, "youngs_modulus, density and time_step must be positive");
  auto nu = field_values(poly, results::field_material_poisson_ratio);
  if (nu.empty()) {
    nu = field_values(poly, results::field_poisson_ratio);
    if (nu.empty())
      throw file_error(path, "no field data 'material_poisson_ratio' (nor 'poisson_ratio')");
    d.notes.push_back("no 'material_poisson_ratio': the model's Poisson ratio is used for c_R");
  }
  d.material_poisson_ratio = nu.front();

  const double max_arrival = *std::max_element(d.arrival.begin(), d.arrival.end());
  const auto end = field_values(poly, results::field_end_time);
  d.end_time = end.empty() ? max_arrival : end.front();
  const auto spacing = field_values(poly, results::field_spacing);
  d.spacing = spacing.empty() ? median(d.cell_size) : spacing.front();
  if (spacing.empty()) d.notes.push_back("no 'spacing' field: median cell size used");
  const auto horizon = field_values(poly, results::field_horizon);
  d.horizon = horizon.empty() ? 3.0 * d.spacing : horizon.front();
  if (horizon.empty()) d.notes.push_back("no 'horizon' field: 3 x spacing used");
  return d;
}

std::vector<double> damage_at_time(const ArrivalData& data, double time) {
  std::vector<double> damage(data.size(), 0.0);
  for (const auto& field : data.arrivals)  // ascending thresholds: the last hit wins
    for (std::size_t i = 0; i < damage.size(); ++i)
      if (field.time[i] >= 0 && field.time[i] <= time) damage[i] = field.threshold;
  return damage;
}

std::vector<SnapshotEntry> list_snapshots(const std::string& outdir) {
  const fs::path pvd = fs::path(outdir) / results::snapshot_collection;
  std::vector<SnapshotEntry> entries;
  std::ifstream in(pvd);
  if (!in) return entries;
  std::stringstream text;
  text << in.rdbuf();
  const std::string s = text.str();
  // The collection is written by pd::write_pvd: one DataSet element per line.
  const std::regex dataset(R"re(<DataSet[^>]*timestep="([^"]+)"[^>]*file="([^"]+)")re");
  for (auto it = std::sregex_iterator(s.begin(), s.end(), dataset); it != std::sregex_iterator();
       ++it) {
    SnapshotEntry e;
    e.time = std::atof((*it)[1].str().c_str());
    e.file = (pvd.parent_path() / (*it)[2].str()).string();
    entries.push_back(e);
  }
  std::sort(entries.begin(), entries.end(),
            [](const SnapshotEntry& a, const SnapshotEntry& b) { return a.time < b.time; });
  return entries;
}

SnapshotFields read_snapshot(const SnapshotEntry& entry, std::size_t expected_points) {
  auto poly = read_polydata(entry.file);
  if (static_cast<std::size_t>(poly->GetNumberOfPoints()) != expected_points)
    throw file_error(entry.file, "has " + std::to_string(poly->GetNumberOfPoints()) +
                                     " particles, arrival.vtp has " +
                                     std::to_string(expected_points));
  SnapshotFields s;
  const auto t = field_values(poly, results::field_time);
  s.time = t.empty() ? entry.time : t.front();
  s.damage = point_array(poly, entry.file, results::damage, true);
  s.strain_energy_density = point_array(poly, entry.file, results::strain_energy_density, true);
  return s;
}

}  // namespace pd::post
