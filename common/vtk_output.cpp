#include "vtk_output.hpp"

#include <vtkCellArray.h>
#include <vtkDoubleArray.h>
#include <vtkErrorCode.h>
#include <vtkFieldData.h>
#include <vtkFloatArray.h>
#include <vtkInformation.h>
#include <vtkInformationVector.h>
#include <vtkObjectFactory.h>
#include <vtkNew.h>
#include <vtkObject.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkPolyDataAlgorithm.h>
#include <vtkStreamingDemandDrivenPipeline.h>
#include <vtkStringArray.h>
#include <vtkTypeInt32Array.h>
#include <vtkXMLPolyDataWriter.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <iomanip>

#include "atomic_file.hpp"
#include "error.hpp"
#include "particle_file.hpp"

namespace pd {

namespace {

// The file's particles, handed to the writer one piece at a time: VTK's
// streaming writer asks for piece p of P, writes it, then asks for the next
// (the points of piece p are first .. first + count - 1, first = n p / P).
class PieceSource : public vtkPolyDataAlgorithm {
public:
  static PieceSource* New();
  vtkTypeMacro(PieceSource, vtkPolyDataAlgorithm);
  const std::vector<double>* x = nullptr;
  const std::vector<double>* y = nullptr;
  const std::vector<PointArray>* arrays = nullptr;
  const std::vector<FieldValue>* fields = nullptr;

protected:
  PieceSource() { SetNumberOfInputPorts(0); }
  int RequestInformation(vtkInformation*, vtkInformationVector**, vtkInformationVector* out) override {
    out->GetInformationObject(0)->Set(vtkAlgorithm::CAN_HANDLE_PIECE_REQUEST(), 1);
    return 1;
  }
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector* out) override;
};
vtkStandardNewMacro(PieceSource);

int PieceSource::RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector* out) {
  vtkInformation* info = out->GetInformationObject(0);
  const auto piece = static_cast<std::size_t>(info->Get(vtkStreamingDemandDrivenPipeline::UPDATE_PIECE_NUMBER()));
  const auto pieces =
      static_cast<std::size_t>(std::max(1, info->Get(vtkStreamingDemandDrivenPipeline::UPDATE_NUMBER_OF_PIECES())));
  const std::size_t total = x->size();
  const std::size_t first = total * piece / pieces, count = total * (piece + 1) / pieces - first;
  const auto n = static_cast<vtkIdType>(count);
  auto* poly = vtkPolyData::GetData(info);
  poly->Initialize();

  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  points->SetNumberOfPoints(n);
  for (vtkIdType i = 0; i < n; ++i) points->SetPoint(i, (*x)[first + i], (*y)[first + i], 0.0);
  // One vertex cell per point; 32-bit cell indices (half the memory of
  // vtkIdType): a piece has far fewer than 2^31 points.
  vtkNew<vtkCellArray> vertices;
  vtkNew<vtkTypeInt32Array> offsets, connectivity;
  offsets->SetNumberOfValues(n + 1);
  connectivity->SetNumberOfValues(n);
  for (vtkIdType i = 0; i <= n; ++i) offsets->SetValue(i, static_cast<std::int32_t>(i));
  for (vtkIdType i = 0; i < n; ++i) connectivity->SetValue(i, static_cast<std::int32_t>(i));
  vertices->SetData(offsets, connectivity);
  poly->SetPoints(points);
  poly->SetVerts(vertices);

  for (const auto& a : *arrays) {
    const std::size_t values = count * static_cast<std::size_t>(a.components);
    const std::size_t from = first * static_cast<std::size_t>(a.components);
    const auto size = static_cast<vtkIdType>(values);
    // The writer only reads: VTK uses our storage instead of a copy (save = 1: not its to free).
    vtkSmartPointer<vtkDataArray> array;
    if (a.float_fill) {
      auto f = vtkSmartPointer<vtkFloatArray>::New();
      f->SetNumberOfComponents(a.components);
      f->SetNumberOfTuples(n);
      a.float_fill(first, count, f->GetPointer(0));
      array = f;
    } else if (!a.float_values.empty()) {
      auto f = vtkSmartPointer<vtkFloatArray>::New();
      f->SetNumberOfComponents(a.components);
      f->SetArray(const_cast<float*>(a.float_values.data()) + from, size, 1);
      array = f;
    } else {
      auto d = vtkSmartPointer<vtkDoubleArray>::New();
      d->SetNumberOfComponents(a.components);
      d->SetArray(const_cast<double*>(a.borrowed ? a.borrowed : a.values.data()) + from, size, 1);
      array = d;
    }
    array->SetName(a.name.c_str());
    poly->GetPointData()->AddArray(array);
  }
  for (const auto& f : *fields) {
    if (!f.text.empty()) {
      vtkNew<vtkStringArray> t;
      t->SetName(f.name.c_str());
      t->InsertNextValue(f.text);
      poly->GetFieldData()->AddArray(t);
      continue;
    }
    vtkNew<vtkDoubleArray> d;
    d->SetName(f.name.c_str());
    d->SetNumberOfTuples(static_cast<vtkIdType>(f.values.size()));
    for (std::size_t k = 0; k < f.values.size(); ++k) d->SetValue(k, f.values[k]);
    poly->GetFieldData()->AddArray(d);
  }
  return 1;
}

}  // namespace

void write_vtp(const std::string& path, const std::vector<double>& x, const std::vector<double>& y,
               const std::vector<PointArray>& arrays, const std::vector<FieldValue>& fields) {
  const std::size_t n = x.size();
  if (y.size() != n) throw file_error(path, "y has the wrong length");
  for (const auto& a : arrays) {
    const std::size_t count = n * static_cast<std::size_t>(a.components);
    const std::size_t given = a.float_fill ? count
                              : !a.float_values.empty() ? a.float_values.size()
                              : a.borrowed ? count
                                           : a.values.size();
    if (given != count) throw file_error(path, "array '" + a.name + "' has the wrong length");
  }
  vtkNew<PieceSource> source;
  source->x = &x;
  source->y = &y;
  source->arrays = &arrays;
  source->fields = &fields;
  const auto pieces = static_cast<int>(std::max<std::size_t>(1, (n + vtp_piece_points - 1) / vtp_piece_points));

  write_atomically_via(path, [&](const std::string& tmp) {
    vtkNew<vtkXMLPolyDataWriter> writer;
    writer->SetFileName(tmp.c_str());
    writer->SetInputConnection(source->GetOutputPort());
    writer->SetNumberOfPieces(pieces);
    writer->SetDataModeToAppended();
    writer->EncodeAppendedDataOff();  // raw binary: fast and compact
    // LZ4 instead of VTK's default zlib: about as compact on these arrays and
    // many times faster to write, which matters for the snapshots of long
    // runs (docs/performance.md); every VTK reader and ParaView read it.
    writer->SetCompressorTypeToLZ4();
    // The writer only logs a failed write (e.g. a full disk) and may still
    // return success: its error code says. Its log is switched off, since the
    // error below says the same once, naming the file.
    const int display = vtkObject::GetGlobalWarningDisplay();
    vtkObject::GlobalWarningDisplayOff();
    const int written = writer->Write();
    vtkObject::SetGlobalWarningDisplay(display);
    const auto code = writer->GetErrorCode();
    if (code == vtkErrorCode::OutOfDiskSpaceError) throw file_error(path, "VTK writer failed: out of disk space");
    // Codes below VTK's own are the system's errno values.
    if (code != vtkErrorCode::NoError && code < vtkErrorCode::FirstVTKErrorCode)
      throw file_error(path, std::string("VTK writer failed: ") + std::strerror(static_cast<int>(code)));
    if (written != 1 || code != vtkErrorCode::NoError)
      throw file_error(path, "VTK writer failed (VTK error code " + std::to_string(code) + ")");
  });
}

std::vector<float> float_values_of(const double* values, std::size_t count) {
  return std::vector<float>(values, values + count);
}

std::function<void(std::size_t, std::size_t, float*)> float_fill_of(const double* values) {
  return [values](std::size_t first, std::size_t count, float* into) {
    for (std::size_t i = 0; i < count; ++i) into[i] = static_cast<float>(values[first + i]);
  };
}

std::function<void(std::size_t, std::size_t, float*)> float_fill_of(const double* x, const double* y) {
  return [x, y](std::size_t first, std::size_t count, float* into) {
    for (std::size_t i = 0; i < count; ++i) {
      into[3 * i] = static_cast<float>(x[first + i]);
      into[3 * i + 1] = static_cast<float>(y[first + i]);
      into[3 * i + 2] = 0.0f;
    }
  };
}

void write_pvd(const std::string& path, const std::vector<std::pair<double, std::string>>& entries,
               const std::string& run_id) {
  write_atomically(path, [&](std::ofstream& out) {
    out << "<?xml version=\"1.0\"?>\n"
        << "<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
        << (run_id.empty() ? "  <Collection>\n" : "  <Collection run_id=\"" + run_id + "\">\n");
    out << std::setprecision(17);
    for (const auto& [time, file] : entries)
      out << "    <DataSet timestep=\"" << time << "\" group=\"\" part=\"0\" file=\"" << file << "\"/>\n";
    out << "  </Collection>\n</VTKFile>\n";
  });
}

bool is_particle_view(const std::string& path) {
  // The XML head comes before the appended data; 1 MB holds it for any view.
  std::ifstream in(path, std::ios::binary);
  std::string head(std::size_t{1} << 20, '\0');
  in.read(head.data(), static_cast<std::streamsize>(head.size()));
  head.resize(static_cast<std::size_t>(in.gcount()));
  head = head.substr(0, head.find("<AppendedData"));
  return head.find("<VTKFile") != std::string::npos && head.find("Name=\"neighborhood_area\"") != std::string::npos;
}

void write_particles_vtp(const std::string& path, const ParticleSet& p) {
  const std::size_t n = p.size();
  PointArray volume{"volume", 1, p.volume};
  PointArray horizon{"horizon", 1, p.horizon};
  PointArray cell_size{"cell_size", 1, p.cell_size};
  PointArray region{"region", 1, std::vector<double>(n)};
  PointArray material{"material", 1, std::vector<double>(n)};
  PointArray neighbors{"neighbors", 1, std::vector<double>(n)};
  PointArray area{"neighborhood_area", 1, std::vector<double>(n)};
  for (std::size_t i = 0; i < n; ++i) {
    region.values[i] = p.region[i];
    material.values[i] = p.material[i];
    const auto begin = p.family_offsets.empty() ? 0 : p.family_offsets[i];
    const auto end = p.family_offsets.empty() ? 0 : p.family_offsets[i + 1];
    neighbors.values[i] = static_cast<double>(end - begin);
    double sum = 0;
    for (auto k = begin; k < end; ++k) sum += p.partial_volume[k] * p.volume[p.neighbors[k]];
    area.values[i] = sum;
  }
  write_vtp(path, p.x, p.y, {volume, region, horizon, neighbors, area, cell_size, material},
            {{"spacing", {p.spacing}}, {"horizon_nominal", {p.horizon_nominal}}});
}

}  // namespace pd
