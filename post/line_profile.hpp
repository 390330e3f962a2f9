#pragma once
// Values along a line given by the user, and the jump of displacement
// across it (the crack-opening profile when the line follows a crack).
//
// The segment runs from P0 to P1 (length L), with unit tangent t = (P1 - P0) / L
// and unit normal n = t turned 90 degrees counter-clockwise (the "+" side is
// on the left looking from P0 to P1). Samples p_k = P0 + s_k t are taken
// every lattice spacing dx (s_k = k L / N, N = ceil(L / dx)). A particle at x
// has coordinates a = (x - p_k).t along and b = (x - p_k).n across the line.
//  - Displacement on the line u(s_k): a least-squares plane
//    u = c0 + c1 a + c2 b through the particles with |a| <= dx, |b| <= dx,
//    evaluated at a = b = 0 (for a line on a crack it mixes both faces).
//  - One-sided displacements u+(s_k), u-(s_k): the same fit over the particles
//    with |a| <= dx and d <= b <= 2d (+) or -2d <= b <= -d (-), extrapolated
//    to the line (a = b = 0). d is the offset, one horizon by default: only
//    particles closer than a horizon to a crack on the line have bonds across
//    it, so the band [d, 2d] is intact material on each side, and the linear
//    extrapolation removes the elastic strain between it and the line.
//  - Jump [u](s_k) = u+ - u-; opening = [u].n, sliding = [u].t (both the
//    same for the line given either way round: + and -, n and t all swap).
// A fit needs 3 particles not on one line; where a side has fewer (a hole,
// the plate edge), its values are missing. Fields that are linear on each
// side of the line are reproduced exactly.
#include <string>
#include <utility>
#include <vector>

namespace pd::post {

struct SampleLine {
  double x0 = 0, y0 = 0, x1 = 0, y1 = 0;  // [m]
};

// Parses "x0,y0,x1,y1" with a length unit on each value (e.g.
// "10mm,12.5mm,40mm,12.5mm"); pd::Error names `option` otherwise.
SampleLine parse_sample_line(const std::string& text, const std::string& option);

// The particle fields a profile reads (references, not copies).
struct ParticleFields {
  const std::vector<double>& x;
  const std::vector<double>& y;
  const std::vector<double>& ux;      // [m]
  const std::vector<double>& uy;      // [m]
  const std::vector<double>& damage;  // in [0, 1]
};

struct LineSample {
  double s = 0, x = 0, y = 0;  // [m] distance from P0 and position
  bool on_plate = false;       // a particle lies within one spacing (else no damage either)
  bool has_u = false;
  double ux = 0, uy = 0;       // [m] displacement on the line
  double damage = 0;           // of the particle nearest the sample (on_plate only)
  bool has_jump = false;
  double opening = 0, sliding = 0;  // [m]
};

std::vector<LineSample> sample_line(const ParticleFields& fields, const SampleLine& line, double spacing,
                                    double offset);

// A line no sample of which is on the plate (in the wrong unit, or beside
// the plate) gives nothing but empty values: refused with pd::Error naming
// `option` and the extent of the particles (x, y). When some samples lie
// beyond that extent (by more than the spacing dx), returns a warning saying
// how many; "" otherwise (samples in a hole are expected and not counted).
std::string check_line_on_plate(const std::vector<LineSample>& samples, const SampleLine& line,
                                const std::vector<double>& x, const std::vector<double>& y, double dx,
                                const std::string& option);

// A line with an end more than max_plate_sizes_away (arrival_data.hpp)
// plate sizes (the larger side of the particles' extent) beyond the plate,
// or an `offset` > 0 of more than that many plate sizes, is refused with
// pd::Error naming `option` (or --line-offset), the plate's extent and the
// unit: sampled every spacing, such a line has more samples than can be
// counted (1e300 m), or is in the wrong unit by far.
void check_line_reach(const SampleLine& line, double offset, const std::vector<double>& x, const std::vector<double>& y,
                      double dx, const std::string& option);

// The values along --line of either kind of run: sampled with the offset
// asked for (0: the horizon), the line refused when it meets no particle; a
// warning when part of it lies off the plate, and one when no sample has a
// jump (no material at the offset on one side or the other).
struct LineProfile {
  std::vector<LineSample> samples;
  double offset = 0;  // [m] the offset used
  std::vector<std::string> warnings;
};
LineProfile line_profile(const ParticleFields& fields, const SampleLine& line, double spacing, double offset,
                         double horizon);
// The same into a pipeline's result (its line_segment, line, line_offset and warnings).
template <class Result>
void add_line_profile(Result& r, const ParticleFields& fields, const SampleLine& line, double spacing, double offset,
                      double horizon) {
  LineProfile profile = line_profile(fields, line, spacing, offset, horizon);
  r.line_segment = line;
  r.line = std::move(profile.samples);
  r.line_offset = profile.offset;
  for (auto& warning : profile.warnings) r.warnings.push_back(std::move(warning));
}

// line_profile.csv: s_m, x_m, y_m, u_x_m, u_y_m, damage, opening_m, sliding_m
// (missing values are empty; off the plate the damage too), written atomically.
void write_line_profile(const std::string& path, const std::vector<LineSample>& samples);

}  // namespace pd::post
