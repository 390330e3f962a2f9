#pragma once
// Reading the solver's VTK PolyData files (arrival.vtp, final_state.vtp,
// snapshots): the file without VTK's console output, and its arrays checked.
// Every problem is one pd::Error naming the file and the array.
#include <optional>
#include <string>
#include <vector>

#include <vtkSmartPointer.h>

class vtkPolyData;

namespace pd::post {

// The whole file; "PATH: not a readable VTK PolyData (.vtp) file: WHY" if it
// is not XML, or truncated, "PATH: file not found" if it is missing, and
// "PATH: a folder, not a file (WHAT)" (a device, a FIFO) if it is no regular
// file, `what` saying which file it is and what to do.
vtkSmartPointer<vtkPolyData> read_vtp_quietly(const std::string& path,
                                              const std::string& what = "a VTK PolyData (.vtp) file");

// Point array `name` with one value per point (empty if absent and not
// required); a non-finite value is an error naming the array and the particle.
std::vector<double> read_point_array(vtkPolyData* poly, const std::string& path, const char* name, bool required);

// Point array `name` with 2 or 3 components per point: its x and y components.
// Returns false (and empty vectors) if absent; non-finite values are errors.
bool read_vector_array(vtkPolyData* poly, const std::string& path, const char* name, std::vector<double>& x,
                       std::vector<double>& y);

// Field-data values (empty if absent).
std::vector<double> read_field_values(vtkPolyData* poly, const char* name);
// A field-data number pd-solve writes (its first value), checked: none if
// absent; a text where a number belongs, or a value that is no finite
// number, is an error naming the file and the field.
std::optional<double> read_field_number(vtkPolyData* poly, const std::string& path, const char* name);

// The fields 'spacing' and 'horizon' of a state pd-solve wrote (arrival.vtp,
// final_state.vtp, a snapshot), each absent or checked against what a run
// can have: the spacing within the particle file's limits (1e-9 to 1e3 m)
// and within max_spacing_to_cell_ratio of the median of `cell_size` (when
// given), the horizon 1/64 to 64 spacings (the particle file's limits on
// every particle's horizon: refined squares down to dx / 64, a nominal
// horizon up to 64 dx). Anything else is an error naming the file, the
// field and its value.
inline constexpr double max_spacing_to_cell_ratio = 1e3;
struct LengthFields {
  std::optional<double> spacing, horizon;  // [m]
};
LengthFields read_length_fields(vtkPolyData* poly, const std::string& path, const std::vector<double>& cell_size);
// A field-data text (a string array's first value; empty if absent).
std::string read_field_text(vtkPolyData* poly, const char* name);

// Damage values as written, checked: in [0, 1] up to single-precision
// round-off (1e-6), which is clamped away (a damage of 1.00000003 is 1).
// Anything else (NaN, -0.2, 1.5) is an error naming the particle.
std::vector<double> checked_damage(std::vector<double> values, const std::string& path, const char* array);

// Cell sizes or volumes (`areas`) as written, checked: each more than 0, and
// none of a side more than max_spacing_to_cell_ratio times the median (an
// error naming the array and the particle otherwise).
std::vector<double> checked_sizes(std::vector<double> values, const std::string& path, const char* array,
                                  bool areas = false);

// Positions known to a millionth of their cells: a particle so far from the
// origin that its position's round-off (a double's 2^-52 of it) is more is
// an error naming the file and the particle. (Before 7 December 2026 a plate
// at 1e16 m, its cells rounded into one point, crashed the pore search.)
inline constexpr double position_round_off_per_cell = 1e-6;
void check_positions_resolved(const std::string& path, const std::vector<double>& x, const std::vector<double>& y,
                              const std::vector<double>& cell_size);

// Reference positions of the points, each finite and none farther than
// far_point_factor times the distance within which half of them lie from
// their middle (medians of x and y): an error naming the point otherwise.
inline constexpr double far_point_factor = 1e4;
void read_points(vtkPolyData* poly, const std::string& path, std::vector<double>& x, std::vector<double>& y);

}  // namespace pd::post
