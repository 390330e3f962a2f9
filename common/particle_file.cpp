#include "particle_file.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <cstdio>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <stdexcept>

#include "atomic_file.hpp"
#include "binary_codec.hpp"
#include "error.hpp"
#include "geometry.hpp"
#include "units.hpp"

namespace pd {

const char* to_string(Region r) {
  switch (r) {
    case Region::uniform_square: return "uniform_square";
    case Region::box_free_mesh: return "box_free_mesh";
    case Region::other: return "other";
  }
  return "?";
}
const char* to_string(Quadrature q) {
  switch (q) {
    case Quadrature::analytic: return "analytic";
    case Quadrature::hhb: return "hhb";
    case Quadrature::full: return "full";
  }
  return "?";
}
const char* to_string(GridKind g) {
  switch (g) {
    case GridKind::nbnug: return "nbnug";
    case GridKind::uniform: return "uniform";
    case GridKind::free: return "free";
  }
  return "?";
}
std::optional<GridKind> grid_kind_named(const std::string& name) {
  for (GridKind g : {GridKind::nbnug, GridKind::uniform, GridKind::free})
    if (name == to_string(g)) return g;
  return std::nullopt;
}

const BoundarySet* ParticleSet::find_set(const std::string& name) const {
  for (const auto& s : sets)
    if (s.name == name) return &s;
  return nullptr;
}

void ParticleSet::resize(std::size_t n) {
  x.resize(n);
  y.resize(n);
  volume.resize(n);
  cell_size.resize(n);
  horizon.resize(n);
  region.resize(n);
  material.resize(n);
}

namespace {

// ---- Header (128 bytes, little-endian) --------------------------------------
constexpr char magic[8] = {'P', 'D', 'P', 'A', 'R', 'T', 'S', '\0'};
constexpr std::uint32_t endian_tag = 0x01020304u;
constexpr std::size_t header_bytes = 128;

struct Header {
  char magic[8];
  std::uint32_t version;
  std::uint32_t endianness;
  std::uint64_t particle_count;
  std::uint64_t bond_count;
  std::uint64_t cell_vertex_count;
  std::uint32_t set_count;
  std::uint8_t grid;
  std::uint8_t quadrature;
  std::uint16_t reserved;
  double length_unit_m;  // always 1.0: lengths are metres
  double spacing;
  double horizon;
  double bbox[4];
  std::uint64_t payload_bytes;
  std::uint64_t payload_checksum;
  std::uint64_t header_checksum;  // over the 120 bytes before it
};
static_assert(sizeof(Header) == header_bytes, "header layout");

// ---- Payload serialisation (binary_codec.hpp) ---------------------------------
// The reader decodes the payload straight from the file into the arrays (no
// second copy of a file that may be hundreds of MB), checksumming on the way;
// counts are checked against the bytes left before anything is allocated.
void write_payload(BinaryWriter& w, const ParticleSet& p) {
  w.values(p.x);
  w.values(p.y);
  w.values(p.volume);
  w.values(p.cell_size);
  w.values(p.horizon);
  w.values(p.region);
  w.values(p.material);
  w.values(p.cell_offsets);
  w.values(p.cell_vx);
  w.values(p.cell_vy);
  w.values(p.family_offsets);
  w.values(p.neighbors);
  w.values(p.partial_volume);
  for (const auto& s : p.sets) {
    w.scalar<std::uint32_t>(static_cast<std::uint32_t>(s.name.size()));
    w.bytes(s.name.data(), s.name.size());
    w.scalar<std::uint64_t>(s.particles.size());
    w.values(s.particles);
  }
  w.scalar<std::uint64_t>(p.provenance.size());
  w.bytes(p.provenance.data(), p.provenance.size());
}

std::string describe_index(const char* array, std::size_t i) {
  return std::string(array) + "[" + std::to_string(i) + "]";
}

// A number in a message: all significant digits that matter, 1e-300 not 0.000000.
std::string number(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%.9g", v);
  return text;
}

// Equal up to the round-off of a few operations on the values.
constexpr double round_off = 1e-9;

template <class T>
void require_finite(const std::vector<T>& v, const char* name, const std::string& where) {
  for (std::size_t i = 0; i < v.size(); ++i)
    if (!std::isfinite(v[i]))
      throw Error(where + ": non-finite value in " + describe_index(name, i));
}

template <class T>
void require_csr(const std::vector<std::uint64_t>& offsets, std::size_t rows, std::size_t entries,
                 const char* name, const std::string& where) {
  if (offsets.size() != rows + 1)
    throw Error(where + ": " + name + " has " + std::to_string(offsets.size()) + " offsets, expected " +
                std::to_string(rows + 1));
  if (offsets.front() != 0 || offsets.back() != entries)
    throw Error(where + ": " + name + " offsets do not span the " + std::to_string(entries) + " entries");
  for (std::size_t i = 0; i < rows; ++i)
    if (offsets[i + 1] < offsets[i])
      throw Error(where + ": " + name + " offsets decrease at " + describe_index(name, i));
}

// The grid description against itself and the limits of the format: the
// spacing, the nominal horizon, and a bounding box that is a whole, bounded
// number of spacings (the lattice the solver lays over the plate).
void validate_grid(const ParticleSet& p, const std::string& where) {
  const double dx = p.spacing;
  if (!(std::isfinite(dx) && dx >= min_spacing_m && dx <= max_spacing_m))
    throw Error(where + ": spacing dx = " + number(dx) + " m, expected " + number(min_spacing_m) + " to " +
                number(max_spacing_m) + " m");
  const double delta = p.horizon_nominal;
  if (!(std::isfinite(delta) && delta >= dx * (1 - round_off) && delta <= max_horizon_factor * dx * (1 + round_off)))
    throw Error(where + ": nominal horizon delta = " + number(delta) + " m, expected 1 to " +
                number(max_horizon_factor) + " spacings (dx = " + number(dx) + " m)");
  for (double b : {p.xmin, p.ymin, p.xmax, p.ymax})
    if (!std::isfinite(b)) throw Error(where + ": non-finite bounding box");
  for (double b : {p.xmin, p.ymin, p.xmax, p.ymax})
    if (std::fabs(b) > max_coordinate_in_spacings * dx)
      throw Error(where + ": bounding box coordinate " + number(b) + " m is more than " +
                  number(max_coordinate_in_spacings) + " spacings from the origin (dx = " + number(dx) + " m)");
  const auto whole_spacings = [&](double low, double high, const char* side) {
    const double cells = (high - low) / dx;
    if (!(high > low && cells >= 1 - round_off && std::fabs(cells - std::round(cells)) <= round_off * cells))
      throw Error(where + ": bounding box " + side + " " + number(high - low) +
                  " m is not a whole number of spacings dx = " + number(dx) + " m");
    return std::round(cells);
  };
  const double columns = whole_spacings(p.xmin, p.xmax, "width");
  const double rows = whole_spacings(p.ymin, p.ymax, "height");
  const double particles = static_cast<double>(std::max<std::size_t>(p.size(), 1));
  if (columns * rows > max_lattice_cells_per_particle * particles)
    throw Error(where + ": the bounding box is " + number(columns) + " x " + number(rows) +
                " spacings for " + std::to_string(p.size()) + " particles, more than " +
                number(max_lattice_cells_per_particle) + " lattice cells per particle");
}

// One particle's cell: its polygon (at least a triangle, counter-clockwise,
// inside the bounding box) against its volume and centroid. Returns the cell's
// reach: the largest distance from the particle to a vertex of its cell.
double validate_cell(const ParticleSet& p, std::size_t i, double box_tolerance, const std::string& where) {
  const auto first = p.cell_offsets[i], count = p.cell_offsets[i + 1] - first;
  const std::string cell = "cell of particle " + std::to_string(i);
  if (count < 3)
    throw Error(where + ": " + cell + " has " + std::to_string(count) + " vertices, expected at least 3");
  const double* vx = p.cell_vx.data() + first;
  const double* vy = p.cell_vy.data() + first;
  for (std::size_t v = 0; v < count; ++v)
    if (vx[v] < p.xmin - box_tolerance || vx[v] > p.xmax + box_tolerance || vy[v] < p.ymin - box_tolerance ||
        vy[v] > p.ymax + box_tolerance)
      throw Error(where + ": " + cell + " has the vertex (" + number(vx[v]) + ", " + number(vy[v]) +
                  ") m outside the bounding box");
  const double area = polygon_signed_area(vx, vy, count);
  if (!(area > 0))
    throw Error(where + ": " + cell + " has the signed area " + number(area) +
                " m^2; expected a counter-clockwise polygon");
  // The volume is the polygon's area corrected for curved edges, whose extra
  // arc points leave only a small fraction of the cell between polygon and arc.
  const double volume = p.volume[i];
  if (!(volume >= 0.5 * area && volume <= 2 * area))
    throw Error(where + ": " + describe_index("volume", i) + " = " + number(volume) + " m^2 does not match its " +
                "cell's area " + number(area) + " m^2");
  const Vec2 at{p.x[i], p.y[i]};
  const double reach = polygon_max_vertex_distance(vx, vy, count, at);
  const Vec2 centroid = polygon_centroid(vx, vy, count);
  const double off = std::hypot(centroid.x - at.x, centroid.y - at.y);
  if (!(off <= 0.01 * reach))
    throw Error(where + ": particle " + std::to_string(i) + " at (" + number(at.x) + ", " + number(at.y) +
                ") m is " + number(off) + " m from its cell's centroid");
  return reach;
}

// A lattice square (region 0) of side `dx` (the spacing, or a refined side
// dx / 2^k) is a cell of the lattice the bounding box and that side span: its four vertices are the corners of the lattice cell
// that holds the particle, and the particle is that cell's centre (to the
// round-off of the coordinates), as the solver's lattice kernel assumes.
void validate_lattice_square(const ParticleSet& p, std::size_t i, double dx, const std::string& where) {
  const double scale = std::max({std::fabs(p.xmin), std::fabs(p.xmax), std::fabs(p.ymin), std::fabs(p.ymax), dx});
  const double tolerance = 1e-9 * dx + 1e-15 * scale;
  const double column = std::floor((p.x[i] - p.xmin) / dx), row = std::floor((p.y[i] - p.ymin) / dx);
  const double left = p.xmin + column * dx, bottom = p.ymin + row * dx;
  const auto on = [&](double value, double a, double b) {
    return std::fabs(value - a) <= tolerance || std::fabs(value - b) <= tolerance;
  };
  bool square = std::fabs(p.x[i] - (left + 0.5 * dx)) <= tolerance && std::fabs(p.y[i] - (bottom + 0.5 * dx)) <= tolerance &&
                p.cell_offsets[i + 1] - p.cell_offsets[i] == 4;
  for (auto v = p.cell_offsets[i]; v < p.cell_offsets[i + 1] && square; ++v)
    square = on(p.cell_vx[v], left, left + dx) && on(p.cell_vy[v], bottom, bottom + dx);
  // Four corners of the cell with its area: each corner once, counter-clockwise.
  const auto first = p.cell_offsets[i];
  square = square && std::fabs(polygon_signed_area(&p.cell_vx[first], &p.cell_vy[first], 4) - dx * dx) <= 1e-6 * dx * dx;
  if (!square)
    throw Error(where + ": particle " + std::to_string(i) + " at (" + number(p.x[i]) + ", " + number(p.y[i]) +
                ") m is a lattice square (region 0) but not the centre of a square of the lattice with its cell");
}

// The side of a lattice square whose stored cell size is `size`: dx / 2^k
// for k = 0 .. log2(max_refinement_ratio) (to round-off), 0 if none fits.
double refined_side(double dx, double size) {
  for (double ratio = 1; ratio <= max_refinement_ratio; ratio *= 2)
    if (std::fabs(size - dx / ratio) <= round_off * dx / ratio) return dx / ratio;
  return 0;
}

// What the bond checks need from the particles' checks.
struct ParticleLimits {
  std::vector<double> cell_reach;  // per particle: largest distance from it to a vertex of its cell [m]
};

// The checks of validate() that do not need the bonds themselves: counts,
// grid, per-particle values, cells, cell offsets and family offsets (which
// must span `bond_count` bonds). The streaming reader makes them before it
// cuts the first family out of the file; the result is what the bond checks need.
ParticleLimits validate_particles(const ParticleSet& p, std::uint64_t bond_count, const std::string& where) {
  const std::size_t n = p.size();
  const auto same = [&](std::size_t m, const char* name) {
    if (m != n)
      throw Error(where + ": inconsistent counts: " + name + " has " + std::to_string(m) +
                  " entries for " + std::to_string(n) + " particles");
  };
  same(p.y.size(), "y");
  same(p.volume.size(), "volume");
  same(p.cell_size.size(), "cell_size");
  same(p.horizon.size(), "horizon");
  same(p.region.size(), "region");
  same(p.material.size(), "material");
  if (n > 0xffffffffull) throw Error(where + ": more than 2^32-1 particles");
  validate_grid(p, where);
  require_finite(p.x, "x", where);
  require_finite(p.y, "y", where);
  require_finite(p.cell_vx, "cell_vx", where);
  require_finite(p.cell_vy, "cell_vy", where);
  if (p.cell_vx.size() != p.cell_vy.size())
    throw Error(where + ": inconsistent counts: cell_vx and cell_vy differ");
  require_csr<double>(p.cell_offsets, n, p.cell_vx.size(), "cell_offsets", where);
  require_csr<std::uint32_t>(p.family_offsets, n, bond_count, "family_offsets", where);

  const double dx = p.spacing;
  const double box_tolerance = round_off * std::max(p.xmax - p.xmin, p.ymax - p.ymin);
  ParticleLimits limits;
  limits.cell_reach.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    if (p.x[i] < p.xmin - box_tolerance || p.x[i] > p.xmax + box_tolerance || p.y[i] < p.ymin - box_tolerance ||
        p.y[i] > p.ymax + box_tolerance)
      throw Error(where + ": particle " + std::to_string(i) + " at (" + number(p.x[i]) + ", " + number(p.y[i]) +
                  ") m lies outside the bounding box [" + number(p.xmin) + ", " + number(p.xmax) + "] x [" +
                  number(p.ymin) + ", " + number(p.ymax) + "] m");
    if (!(std::isfinite(p.volume[i]) && p.volume[i] > 0))
      throw Error(where + ": volume must be positive and finite, " + describe_index("volume", i) + " = " +
                  number(p.volume[i]));
    if (p.region[i] > 2)
      throw Error(where + ": unknown region code " + std::to_string(p.region[i]) + " at particle " +
                  std::to_string(i));
    // cell_size: the side of a lattice square (dx, or dx / 2^k in a refinement
    // region; volume side^2), sqrt(volume) for the other cells.
    const bool square = p.region[i] == static_cast<std::uint8_t>(Region::uniform_square);
    const double side = square ? refined_side(dx, p.cell_size[i]) : 0;
    if (square && side == 0)
      throw Error(where + ": " + describe_index("cell_size", i) + " = " + number(p.cell_size[i]) + " m of a lattice " +
                  "square, expected the spacing " + number(dx) + " m or the spacing over a power of two up to " +
                  number(max_refinement_ratio));
    const double expected_size = square ? side : std::sqrt(p.volume[i]);
    if (!(std::fabs(p.cell_size[i] - expected_size) <= round_off * expected_size))
      throw Error(where + ": " + describe_index("cell_size", i) + " = " + number(p.cell_size[i]) + " m, expected " +
                  "sqrt(volume) = " + number(expected_size) + " m");
    if (square && !(std::fabs(p.volume[i] - side * side) <= round_off * side * side))
      throw Error(where + ": " + describe_index("volume", i) + " = " + number(p.volume[i]) +
                  " m^2 of a lattice square, expected " + (side < dx ? "its side^2 = " : "dx^2 = ") +
                  number(side * side) + " m^2");
    // The horizon reaches at least one cell: a square's side (dx or refined),
    // or for a free cell, which may belong to a box meshed finer than the
    // squares (pd-mesh --box-spacing), the finest refined side.
    const double h = p.horizon[i];
    const double shortest = square ? side : dx / max_refinement_ratio;
    if (!(std::isfinite(h) && h >= shortest * (1 - round_off) && h <= p.horizon_nominal * (1 + round_off)))
      throw Error(where + ": " + describe_index("horizon", i) + " = " + number(h) + " m, expected between " +
                  (square ? (side < dx ? "the refined square's side " : "the spacing ")
                          : "the finest refined side (the spacing / " + number(max_refinement_ratio) + ") ") +
                  number(shortest) + " m and the nominal horizon " + number(p.horizon_nominal) + " m");
    limits.cell_reach[i] = validate_cell(p, i, box_tolerance, where);
    if (square) validate_lattice_square(p, i, side, where);
  }
  return limits;
}

// The family of particle i: neighbours in range, sorted without repeats, not
// i itself, factors in (0, 1], and each bond no longer than i's horizon plus
// the neighbour's cell reach (beyond that the cell cannot meet the horizon)
// and no shorter than a millionth of the spacing (distinct particles).
// `first` numbers the family's first bond in the file.
void validate_family(const ParticleSet& p, const ParticleLimits& limits, std::uint32_t i,
                     const std::uint32_t* neighbors, const double* partial_volume, std::size_t count,
                     std::uint64_t first, const std::string& where) {
  const std::size_t n = p.size();
  for (std::size_t k = 0; k < count; ++k) {
    const std::uint32_t j = neighbors[k];
    const std::uint64_t bond = first + k;
    if (j >= n)
      throw Error(where + ": neighbour index out of range at " + describe_index("neighbors", bond) + " = " +
                  std::to_string(j) + " (" + std::to_string(n) + " particles)");
    if (j == i)
      throw Error(where + ": particle " + std::to_string(i) + " is in its own family at " +
                  describe_index("neighbors", bond));
    if (k > 0 && j <= neighbors[k - 1])
      throw Error(where + ": the family of particle " + std::to_string(i) + " is not sorted or repeats a " +
                  "neighbour at " + describe_index("neighbors", bond) + " = " + std::to_string(j) + " (after " +
                  std::to_string(neighbors[k - 1]) + ")");
    const double phi = partial_volume[k];
    if (!(std::isfinite(phi) && phi > 0 && phi <= 1 + 1e-12))
      throw Error(where + ": partial-volume factor outside (0, 1] at " + describe_index("partial_volume", bond) +
                  " = " + number(phi));
    // Squared lengths: no square root per bond (the coordinates are bounded,
    // so the squares cannot overflow).
    const double along_x = p.x[j] - p.x[i], along_y = p.y[j] - p.y[i];
    const double length_squared = along_x * along_x + along_y * along_y;
    const double longest = (p.horizon[i] + limits.cell_reach[j]) * (1 + round_off);
    const double shortest = min_bond_length_in_spacings * p.spacing;
    if (length_squared <= longest * longest && length_squared >= shortest * shortest) continue;
    const double length = std::sqrt(length_squared);
    if (!(length <= longest))
      throw Error(where + ": the bond " + std::to_string(i) + " -> " + std::to_string(j) + " (" +
                  describe_index("neighbors", bond) + ") is " + number(length) + " m long, more than the horizon " +
                  number(p.horizon[i]) + " m plus the neighbour's cell reach " + number(limits.cell_reach[j]) + " m");
    if (!(length >= shortest))
      throw Error(where + ": the bond " + std::to_string(i) + " -> " + std::to_string(j) + " (" +
                  describe_index("neighbors", bond) + ") is " + number(length) + " m long, shorter than " +
                  number(min_bond_length_in_spacings) + " spacings (coincident particles?)");
  }
}

// Boundary sets: named, no two with the same name, indices sorted without
// repeats and in range.
void validate_sets(const ParticleSet& p, const std::string& where) {
  const std::size_t n = p.size();
  std::set<std::string> names;
  for (const auto& s : p.sets) {
    if (s.name.empty()) throw Error(where + ": a boundary set has an empty name");
    if (!names.insert(s.name).second) throw Error(where + ": two boundary sets are named '" + s.name + "'");
    for (std::size_t k = 0; k < s.particles.size(); ++k) {
      const auto i = s.particles[k];
      if (i >= n)
        throw Error(where + ": set '" + s.name + "' refers to particle " + std::to_string(i) + " of " +
                    std::to_string(n));
      if (k > 0 && i <= s.particles[k - 1])
        throw Error(where + ": set '" + s.name + "' is not sorted or repeats particle " + std::to_string(i));
    }
  }
}

}  // namespace

void validate(const ParticleSet& p, const std::string& where) {
  const auto limits = validate_particles(p, p.neighbors.size(), where);
  if (p.partial_volume.size() != p.neighbors.size())
    throw Error(where + ": inconsistent counts: partial_volume and neighbors differ");
  for (std::uint32_t i = 0; i < p.size(); ++i) {
    const auto first = p.family_offsets[i];
    validate_family(p, limits, i, p.neighbors.data() + first, p.partial_volume.data() + first,
                    static_cast<std::size_t>(p.family_offsets[i + 1] - first), first, where);
  }
  validate_sets(p, where);
}

bool begins_as_particle_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  char start[sizeof magic] = {};
  return in.read(start, sizeof start) && std::memcmp(start, magic, sizeof magic) == 0;
}

void write_particle_file(const std::string& path, const ParticleSet& p) {
  validate(p, path + " (before writing)");
  write_atomically(path, [&](std::ofstream& out) {
    Header h{};
    std::memcpy(h.magic, magic, 8);
    h.version = particle_file_version;
    h.endianness = endian_tag;
    h.particle_count = p.size();
    h.bond_count = p.bond_count();
    h.cell_vertex_count = p.cell_vx.size();
    h.set_count = static_cast<std::uint32_t>(p.sets.size());
    h.grid = static_cast<std::uint8_t>(p.grid);
    h.quadrature = static_cast<std::uint8_t>(p.quadrature);
    h.length_unit_m = 1.0;
    h.spacing = p.spacing;
    h.horizon = p.horizon_nominal;
    h.bbox[0] = p.xmin;
    h.bbox[1] = p.ymin;
    h.bbox[2] = p.xmax;
    h.bbox[3] = p.ymax;
    // The header goes first but its payload size and checksum are known only
    // at the end: write a placeholder, then rewrite it.
    out.write(reinterpret_cast<const char*>(&h), sizeof h);
    BinaryWriter w(out);
    write_payload(w, p);
    h.payload_bytes = w.count();
    h.payload_checksum = w.checksum();
    h.header_checksum = checksum_of(&h, offsetof(Header, header_checksum));
    out.seekp(0);
    out.write(reinterpret_cast<const char*>(&h), sizeof h);
  });
}

namespace {

// Why a file that does not begin as a particle file is not one: the other
// files of the pipeline, given where a particle file goes (pd-post
// --particles plate.geo, a scene's particles = "scene.toml"), named for
// what they are (before 7 December 2026 "wrong magic number", or
// "truncated" for a file shorter than the header).
std::string not_a_particle_file(const std::string& path, const std::string& head) {
  std::string extension = std::filesystem::path(path).extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(), [](unsigned char c) { return std::tolower(c); });
  if (extension == ".geo") return "a gmsh geometry, not a particle file: pd-mesh meshes it into one (docs/mesher.md)";
  if (extension == ".toml")
    return "a scene (TOML), not a particle file: a scene names its particle file with particles = \"...\" "
           "(docs/scenes.md)";
  if (extension == ".vtp" || extension == ".pvd")
    return "a VTK file (a run's results), not a particle file: pd-mesh writes particle files (docs/formats.md)";
  // A particle file packed to be moved or stored (they run to hundreds of
  // MB) is named by its packer's signature, with how to unpack it (before 7
  // December 2026 "wrong magic number", what to do unsaid).
  struct Packed {
    const char* signature;
    const char* what;
    const char* unpack;
  };
  for (const Packed& p : {Packed{"\x1F\x8B", "a gzip", "gunzip"}, Packed{"\xFD" "7zXZ", "an xz", "unxz"},
                          Packed{"\x28\xB5\x2F\xFD", "a zstd", "unzstd"}, Packed{"BZh", "a bzip2", "bunzip2"},
                          Packed{"PK\x03\x04", "a zip", "unzip"}})
    if (head.compare(0, std::char_traits<char>::length(p.signature), p.signature) == 0)
      return std::string(p.what) + "-compressed file, not a particle file: unpack it (" + p.unpack +
             ") and give the .pdp it holds";
  // A Git LFS pointer stands in a clone made without git-lfs.
  if (head.compare(0, 8, "version ") == 0)
    return "a text file (a Git LFS pointer?), not a particle file: fetch the file itself (git lfs pull), or mesh "
           "it again with pd-mesh";
  return "not a particle file (wrong magic number; expected 'PDPARTS'): give the .pdp file that pd-mesh wrote, "
         "or mesh it again (docs/mesher.md)";
}

struct OpenedParticleFile {
  std::ifstream in;  // positioned at the start of the payload
  Header header;
};

// Opens the file and makes every check the header and the file size allow.
OpenedParticleFile open_particle_file(const std::string& path) {
  OpenedParticleFile file;
  std::ifstream& in = file.in;
  Header& h = file.header;
  in.open(path, std::ios::binary | std::ios::ate);
  if (!in) throw file_error(path, std::string("cannot open particle file: ") + std::strerror(errno));
  const auto file_size = static_cast<std::uint64_t>(in.tellg());
  in.seekg(0);
  // The magic first: another kind of file is named as such, not as a
  // truncated particle file.
  char head[sizeof magic] = {};
  const auto head_bytes = static_cast<std::size_t>(std::min<std::uint64_t>(sizeof magic, file_size));
  in.read(head, static_cast<std::streamsize>(head_bytes));
  if (std::memcmp(head, magic, head_bytes) != 0)
    throw file_error(path, not_a_particle_file(path, std::string(head, head_bytes)));
  in.seekg(0);
  if (file_size < header_bytes)
    throw file_error(path, "truncated: " + std::to_string(file_size) + " bytes, shorter than the " +
                               std::to_string(header_bytes) + "-byte header");
  in.read(reinterpret_cast<char*>(&h), sizeof h);
  if (std::memcmp(h.magic, magic, 8) != 0) throw file_error(path, not_a_particle_file(path, std::string(h.magic, 8)));
  if (h.endianness != endian_tag)
    throw file_error(path, "written with a different byte order (endianness tag mismatch)");
  if (h.version != particle_file_version)
    throw file_error(path, "unknown format version " + std::to_string(h.version) +
                               " (this build reads version " + std::to_string(particle_file_version) + ")");
  if (checksum_of(&h, offsetof(Header, header_checksum)) != h.header_checksum)
    throw file_error(path, "header checksum mismatch (corrupted header)");
  if (h.length_unit_m != 1.0) throw file_error(path, "length unit is not metres");
  if (file_size - header_bytes < h.payload_bytes)
    throw file_error(path, "truncated: payload has " + std::to_string(file_size - header_bytes) +
                               " bytes, header announces " + std::to_string(h.payload_bytes));
  if (file_size - header_bytes > h.payload_bytes)
    throw file_error(path, "trailing bytes after the payload (" +
                               std::to_string(file_size - header_bytes - h.payload_bytes) + " extra)");
  if (h.grid > 2 || h.quadrature > 2) throw file_error(path, "unknown grid or quadrature code");
  if (h.reserved != 0) throw file_error(path, "reserved header field is " + std::to_string(h.reserved) + ", not 0");
  return file;
}

// The grid description from the header, with no particles yet.
ParticleSet grid_of(const Header& h) {
  ParticleSet p;
  p.grid = static_cast<GridKind>(h.grid);
  p.quadrature = static_cast<Quadrature>(h.quadrature);
  p.spacing = h.spacing;
  p.horizon_nominal = h.horizon;
  p.xmin = h.bbox[0];
  p.ymin = h.bbox[1];
  p.xmax = h.bbox[2];
  p.ymax = h.bbox[3];
  return p;
}

// The payload before the bonds: per-particle arrays, cells, family offsets.
void read_particle_sections(BinaryReader& r, const Header& h, ParticleSet& p) {
  const auto n = h.particle_count;
  r.values(p.x, n, "x");
  r.values(p.y, n, "y");
  r.values(p.volume, n, "volume");
  r.values(p.cell_size, n, "cell_size");
  r.values(p.horizon, n, "horizon");
  r.values(p.region, n, "region");
  r.values(p.material, n, "material");
  r.values(p.cell_offsets, n + 1, "cell_offsets");
  r.values(p.cell_vx, h.cell_vertex_count, "cell_vx");
  r.values(p.cell_vy, h.cell_vertex_count, "cell_vy");
  r.values(p.family_offsets, n + 1, "family_offsets");
}

// Throws unless the sets fit in the payload after the next `skipped` bytes,
// each at least its two lengths (no name, no particles), followed by the
// provenance length: checked before the sets are allocated.
void require_room_for_sets(const BinaryReader& r, const Header& h, std::uint64_t skipped) {
  constexpr std::size_t smallest_set = sizeof(std::uint32_t) + sizeof(std::uint64_t);
  r.require_room(h.set_count, smallest_set, skipped + sizeof(std::uint64_t), "sets");
}

// The payload after the bonds (sets, provenance), then the checks that the
// payload is used up and matches its checksum.
void read_trailing_sections(BinaryReader& r, const Header& h, ParticleSet& p, const std::string& path) {
  require_room_for_sets(r, h, 0);
  p.sets.resize(h.set_count);
  for (auto& s : p.sets) {
    const auto len = r.scalar<std::uint32_t>("set name length");
    s.name = r.string(len, "set name");
    const auto count = r.scalar<std::uint64_t>("set size");
    r.values(s.particles, count, "set particles");
  }
  const auto prov = r.scalar<std::uint64_t>("provenance length");
  p.provenance = r.string(prov, "provenance");
  if (r.remaining() != 0) throw file_error(path, "inconsistent counts: payload has unread bytes");
  if (r.checksum() != h.payload_checksum) throw file_error(path, "payload checksum mismatch (file corrupted)");
}

// Hands each family of `p` to `visit` (its offsets validated, the bond
// sections known to fit the payload: the caller checked both), reading
// the neighbors section through `payload` and the partial_volume section in
// lockstep through a second stream, chunk by chunk, checking each bond before
// its family is visited. The payload checksum needs partial_volume after
// neighbors, so `payload` then reads that section once more; equal checksums
// of its two reads tie the factors the visitor saw to the payload checksum.
void stream_families(BinaryReader& payload, const ParticleSet& p, const ParticleLimits& limits,
                     std::uint64_t bond_count, const std::string& path, const FamilyVisitor& visit) {
  constexpr std::size_t neighbor_bytes = sizeof(std::uint32_t);
  std::ifstream second(path, std::ios::binary);
  if (!second) throw file_error(path, "cannot open particle file");
  second.seekg(static_cast<std::streamoff>(header_bytes + payload.position() + bond_count * neighbor_bytes));
  BinaryReader factors_reader(second, bond_count * sizeof(double), path);

  // Bonds [window_begin, window_end) of the file are in the buffers.
  const auto chunk = static_cast<std::size_t>(std::min<std::uint64_t>(family_read_chunk_bonds, bond_count));
  std::vector<std::uint32_t> neighbors(chunk);
  std::vector<double> factors(chunk);
  std::uint64_t window_begin = 0, window_end = 0;
  const std::size_t n = p.size();
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint64_t begin = p.family_offsets[i], end = p.family_offsets[i + 1];
    if (end > window_end) {
      // Keep the start of this family, read on from the end of the window.
      const auto kept = static_cast<std::size_t>(window_end - begin);
      const auto from = static_cast<std::ptrdiff_t>(begin - window_begin);
      if (from > 0) {
        std::copy(neighbors.begin() + from, neighbors.begin() + from + kept, neighbors.begin());
        std::copy(factors.begin() + from, factors.begin() + from + kept, factors.begin());
      }
      if (end - begin > neighbors.size()) {
        neighbors.resize(end - begin);
        factors.resize(end - begin);
      }
      const auto fresh =
          static_cast<std::size_t>(std::min<std::uint64_t>(neighbors.size() - kept, bond_count - window_end));
      payload.elements(neighbors.data() + kept, fresh, "neighbors");
      factors_reader.elements(factors.data() + kept, fresh, "partial_volume");
      window_begin = begin;
      window_end += fresh;
    }
    const auto at = static_cast<std::size_t>(begin - window_begin);
    const auto count = static_cast<std::size_t>(end - begin);
    validate_family(p, limits, static_cast<std::uint32_t>(i), neighbors.data() + at, factors.data() + at, count,
                    begin, path);
    visit(p, static_cast<std::uint32_t>(i), neighbors.data() + at, factors.data() + at, count);
  }
  // The offsets span all bonds, so every bond was read: `payload` is at partial_volume.
  Checksum second_read;
  for (std::uint64_t done = 0; done < bond_count;) {
    const auto count = static_cast<std::size_t>(std::min<std::uint64_t>(factors.size(), bond_count - done));
    payload.elements(factors.data(), count, "partial_volume");
    second_read.update(factors.data(), count * sizeof(double));
    done += count;
  }
  if (second_read.value() != factors_reader.checksum())
    throw file_error(path, "partial_volume differs between its two reads (file changed while being read)");
}

}  // namespace

ParticleSet read_particle_file(const std::string& path) {
  auto file = open_particle_file(path);
  const Header& h = file.header;
  ParticleSet p = grid_of(h);
  BinaryReader r(file.in, h.payload_bytes, path);
  read_particle_sections(r, h, p);
  r.values(p.neighbors, h.bond_count, "neighbors");
  r.values(p.partial_volume, h.bond_count, "partial_volume");
  read_trailing_sections(r, h, p, path);
  validate(p, path);
  return p;
}

ParticleSet read_particle_file(const std::string& path, const FamilyVisitor& visit) {
  if (!visit) throw std::invalid_argument("read_particle_file: empty family visitor");
  auto file = open_particle_file(path);
  const Header& h = file.header;
  ParticleSet p = grid_of(h);
  BinaryReader r(file.in, h.payload_bytes, path);
  read_particle_sections(r, h, p);
  // Counts that do not fit the payload are reported as such before the values
  // they misplace (in this order, so that 12 * bond_count cannot overflow).
  r.require_room(h.bond_count, sizeof(std::uint32_t), 0, "neighbors");
  r.require_room(h.bond_count, sizeof(double), h.bond_count * sizeof(std::uint32_t), "partial_volume");
  require_room_for_sets(r, h, h.bond_count * (sizeof(std::uint32_t) + sizeof(double)));
  // The families are cut out of the file by these offsets: check them (and
  // everything else known so far) before the first visit.
  const auto limits = validate_particles(p, h.bond_count, path);
  stream_families(r, p, limits, h.bond_count, path, visit);
  read_trailing_sections(r, h, p, path);
  validate_sets(p, path);
  return p;
}

ParticleSet empty_like(const ParticleSet& p) {
  ParticleSet q;
  q.grid = p.grid, q.quadrature = p.quadrature, q.spacing = p.spacing, q.horizon_nominal = p.horizon_nominal;
  q.xmin = p.xmin, q.ymin = p.ymin, q.xmax = p.xmax, q.ymax = p.ymax;
  q.cell_offsets.push_back(0);
  return q;
}

void append_particle(ParticleSet& to, const ParticleSet& from, std::size_t i) {
  to.x.push_back(from.x[i]);
  to.y.push_back(from.y[i]);
  to.volume.push_back(from.volume[i]);
  to.cell_size.push_back(from.cell_size[i]);
  to.horizon.push_back(from.horizon[i]);
  to.region.push_back(from.region[i]);
  to.material.push_back(from.material[i]);
  for (auto v = from.cell_offsets[i]; v < from.cell_offsets[i + 1]; ++v) {
    to.cell_vx.push_back(from.cell_vx[v]);
    to.cell_vy.push_back(from.cell_vy[v]);
  }
  to.cell_offsets.push_back(to.cell_vx.size());
}

double parse_spacing(const std::string& text, const std::string& option, const std::string& example) {
  const double spacing = parse_length(text, option);
  if (!(spacing > 0))
    throw Error(option + " must be positive, got '" + clipped(text) + "' (e.g. " + option + " " + example + ")");
  if (spacing < min_spacing_m || spacing > max_spacing_m) {
    char metres[32];
    std::snprintf(metres, sizeof metres, "%.3g m", spacing);
    throw Error(option + " " + clipped(text) + " is " + metres + ", " +
                (spacing < min_spacing_m ? "below the smallest" : "above the largest") +
                " spacing a particle file holds (1 nm to 1 km): is the exponent or the unit a slip? (e.g. " + option +
                " " + example + ")");
  }
  return spacing;
}

}  // namespace pd
