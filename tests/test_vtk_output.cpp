// The .vtp writer's pieces: a point set larger than one piece is written as
// several <Piece> elements of one file, which VTK's reader returns as one
// data set with every point, vertex cell, array value and field as given.
#include <vtkCellArray.h>
#include <vtkDataArray.h>
#include <vtkFieldData.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkXMLPolyDataReader.h>

#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "vtk_output.hpp"
#include "test_folder.hpp"

namespace {
std::string temp_path(const std::string& name) {
  return (std::filesystem::path(pd::test_support::fresh_folder_under(PD_TEST_TMPDIR, "vtk_output")) / name).string();
}

long pieces_in(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  const std::string s = text.str();
  long count = 0;
  for (auto at = s.find("<Piece "); at != std::string::npos; at = s.find("<Piece ", at + 1)) ++count;
  return count;
}

// Writes n points with arrays of every kind (values are formulas of the
// index, so that the reader's values are checked against numbers made here,
// not by the writer) and reads the file back.
void check_round_trip(std::size_t n, long expected_pieces) {
  std::vector<double> x(n), y(n), volume(n), region(n), ux(n), uy(n), damage(n);
  std::vector<float> cell_size(n);
  for (std::size_t i = 0; i < n; ++i) {
    x[i] = 1e-4 * static_cast<double>(i);
    y[i] = -2e-4 * static_cast<double>(i) + 0.1;
    volume[i] = 1e-9 * static_cast<double>(i % 97 + 1);
    region[i] = static_cast<double>(i % 3);
    ux[i] = 1e-7 * static_cast<double>(i) / 3.0;
    uy[i] = -1e-7 * static_cast<double>(i % 11) / 7.0;
    damage[i] = static_cast<double>(i % 13) / 13.0;
    cell_size[i] = static_cast<float>(1e-5 * static_cast<double>(i % 5 + 1));
  }
  std::vector<pd::PointArray> arrays;
  arrays.push_back({"volume", 1, {}, volume.data()});
  arrays.push_back({"region", 1, region});
  pd::PointArray cells{"cell_size", 1};
  cells.float_values = cell_size;
  arrays.push_back(cells);
  pd::PointArray displacement{"displacement", 3};
  displacement.float_fill = pd::float_fill_of(ux.data(), uy.data());
  arrays.push_back(displacement);
  pd::PointArray damage_array{"damage", 1};
  damage_array.float_fill = pd::float_fill_of(damage.data());
  arrays.push_back(damage_array);
  const auto path = temp_path("pieces_" + std::to_string(n) + ".vtp");
  pd::write_vtp(path, x, y, arrays, {{"time", {2.5e-6}}, {"thresholds", {0.2, 0.35}}});
  CHECK(pieces_in(path) == expected_pieces);

  vtkNew<vtkXMLPolyDataReader> reader;
  reader->SetFileName(path.c_str());
  reader->Update();
  vtkPolyData* poly = reader->GetOutput();
  REQUIRE(poly->GetNumberOfPoints() == static_cast<vtkIdType>(n));
  REQUIRE(poly->GetNumberOfVerts() == static_cast<vtkIdType>(n));
  // Every vertex cell is its own point's, in order, across the pieces.
  vtkIdType points_of_cell = 0;
  const vtkIdType* ids = nullptr;
  vtkIdType cell = 0, wrong_cells = 0;
  vtkCellArray* verts = poly->GetVerts();
  for (verts->InitTraversal(); verts->GetNextCell(points_of_cell, ids); ++cell)
    if (points_of_cell != 1 || ids[0] != cell) ++wrong_cells;
  CHECK(wrong_cells == 0);
  auto* data = poly->GetPointData();
  for (const char* name : {"volume", "region", "cell_size", "displacement", "damage"})
    REQUIRE(data->GetArray(name) != nullptr);
  CHECK(data->GetArray("volume")->GetDataType() == VTK_DOUBLE);
  CHECK(data->GetArray("displacement")->GetDataType() == VTK_FLOAT);
  CHECK(data->GetArray("displacement")->GetNumberOfComponents() == 3);
  long wrong_values = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const auto t = static_cast<vtkIdType>(i);
    double point[3];
    poly->GetPoint(t, point);
    wrong_values += point[0] != x[i] || point[1] != y[i] || point[2] != 0.0;
    wrong_values += data->GetArray("volume")->GetComponent(t, 0) != volume[i];
    wrong_values += data->GetArray("region")->GetComponent(t, 0) != region[i];
    wrong_values += data->GetArray("cell_size")->GetComponent(t, 0) != static_cast<double>(cell_size[i]);
    wrong_values += data->GetArray("displacement")->GetComponent(t, 0) != static_cast<double>(static_cast<float>(ux[i]));
    wrong_values += data->GetArray("displacement")->GetComponent(t, 1) != static_cast<double>(static_cast<float>(uy[i]));
    wrong_values += data->GetArray("displacement")->GetComponent(t, 2) != 0.0;
    wrong_values += data->GetArray("damage")->GetComponent(t, 0) != static_cast<double>(static_cast<float>(damage[i]));
  }
  CHECK(wrong_values == 0);
  vtkDataArray* thresholds = poly->GetFieldData()->GetArray("thresholds");
  REQUIRE(thresholds != nullptr);
  REQUIRE(thresholds->GetNumberOfTuples() == 2);
  CHECK(thresholds->GetComponent(1, 0) == 0.35);
  REQUIRE(poly->GetFieldData()->GetArray("time") != nullptr);
  CHECK(poly->GetFieldData()->GetArray("time")->GetComponent(0, 0) == 2.5e-6);
}
}  // namespace

TEST_CASE("a .vtp of more points than one piece reads back as one data set", "[vtk]") {
  // Two whole pieces and a part of a third: three <Piece> elements, split
  // where the writer splits them (n p / P), not at piece-size boundaries.
  check_round_trip(2 * pd::vtp_piece_points + 12345, 3);
}

TEST_CASE("a .vtp of at most one piece's points is one piece", "[vtk]") {
  check_round_trip(pd::vtp_piece_points, 1);
  check_round_trip(5, 1);
}
