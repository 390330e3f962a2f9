#pragma once
// The particle file (.pdp): what pd-mesh writes and pd-solve reads.
// Binary layout, version history and checks: docs/formats.md.
#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace pd {

// Where a particle's cell comes from (docs/mesher.md).
enum class Region : std::uint8_t {
  uniform_square = 0,  // exact dx square of the lattice
  box_free_mesh = 1,   // free gmsh element within the padding of a boundary off the lattice (the paper's box)
  other = 2,           // anything else (e.g. elements of the global free mesh)
};

// How the partial-volume factors were computed (docs/theory.md).
enum class Quadrature : std::uint8_t { analytic = 0, hhb = 1, full = 2 };

// How the grid was built.
enum class GridKind : std::uint8_t { nbnug = 0, uniform = 1, free = 2 };

const char* to_string(Region r);
const char* to_string(Quadrature q);
const char* to_string(GridKind g);
// The grid kind a name stands for (to_string's inverse), if any.
std::optional<GridKind> grid_kind_named(const std::string& name);

// A named set of particles (e.g. the particles within one horizon of the top edge).
struct BoundarySet {
  std::string name;
  std::vector<std::uint32_t> particles;  // sorted, unique
};

// All data of a particle file, as structure of arrays. SI units: metres, m^2.
// 2D "volume" is the cell area (per unit thickness); thickness belongs to the scene.
struct ParticleSet {
  // Grid description.
  GridKind grid = GridKind::nbnug;
  Quadrature quadrature = Quadrature::analytic;
  double spacing = 0;       // lattice spacing dx [m]
  double horizon_nominal = 0;  // delta [m] used to build the families
  double xmin = 0, ymin = 0, xmax = 0, ymax = 0;  // plate bounding box [m]

  // Per particle.
  std::vector<double> x, y;          // cell centroid [m]
  std::vector<double> volume;        // cell area [m^2], corrected for curved edges
  std::vector<double> cell_size;     // characteristic size sqrt(volume) [m]
  std::vector<double> horizon;       // horizon delta_i [m]
  std::vector<std::uint8_t> region;  // Region
  std::vector<std::uint16_t> material;

  // Cell polygons (counter-clockwise), CSR: vertices of cell i are
  // cell_vx/cell_vy[cell_offsets[i] .. cell_offsets[i+1]).
  std::vector<std::uint64_t> cell_offsets;
  std::vector<double> cell_vx, cell_vy;

  // Families, CSR: neighbours of i are neighbors[family_offsets[i] .. family_offsets[i+1]),
  // sorted by index; partial_volume[k] = phi_ij in (0, 1] for the same bond.
  std::vector<std::uint64_t> family_offsets;
  std::vector<std::uint32_t> neighbors;
  std::vector<double> partial_volume;

  std::vector<BoundarySet> sets;

  // Provenance: JSON text (input file and hash, tool version, all options).
  std::string provenance;

  std::size_t size() const { return x.size(); }
  std::size_t bond_count() const { return neighbors.size(); }
  const BoundarySet* find_set(const std::string& name) const;

  // Resizes all per-particle arrays to n (cells and families untouched).
  void resize(std::size_t n);
};

inline constexpr std::uint32_t particle_file_version = 1;

// Limits of the format, which the reader and writer enforce (docs/formats.md,
// "What the reader rejects"): sizes a plate discretisation never has, and
// beyond which the set-up's tables and lattices would over- or underflow.
inline constexpr double min_spacing_m = 1e-9;             // dx
inline constexpr double max_spacing_m = 1e3;
inline constexpr double max_horizon_factor = 64;          // delta / dx
inline constexpr double max_lattice_cells_per_particle = 64;  // (bbox width / dx) (bbox height / dx) / n
inline constexpr double max_coordinate_in_spacings = 1e9;     // |bbox corner| / dx
inline constexpr double min_bond_length_in_spacings = 1e-6;   // |x_j - x_i| / dx
inline constexpr double max_refinement_ratio = 64;        // dx / side of the finest lattice square

// A grid spacing typed for `option` (pd-mesh --spacing, the validation
// tools' --spacing): a length with its unit, positive, and within the
// spacings a particle file holds; pd::Error otherwise, naming the option and
// the value, with `example` ("0.05mm") for the range. (Outside the range a
// spacing is a slip of the exponent or the unit; 1e-300mm squared is 0.)
double parse_spacing(const std::string& text, const std::string& option, const std::string& example);

// A particle set with `p`'s header (grid, quadrature, spacing, nominal
// horizon, bounding box) and no particles: the start of a renumbered copy.
ParticleSet empty_like(const ParticleSet& p);

// Appends particle i of `from` (position, cell, volume, horizon, region,
// material) to `to`; families and sets are the caller's.
void append_particle(ParticleSet& to, const ParticleSet& from, std::size_t i);

// Writes atomically. Throws pd::Error naming the path on failure.
void write_particle_file(const std::string& path, const ParticleSet& particles);

// Whether the file at `path` begins as a particle file does (its magic
// bytes); false for a missing or unreadable file. A tool replaces an
// existing file with a particle file only if it is one.
bool begins_as_particle_file(const std::string& path);

// Reads and validates (magic, version, endianness, sizes, checksum, counts,
// finite and positive values). Throws pd::Error "PATH: problem" on any defect.
ParticleSet read_particle_file(const std::string& path);

// One particle's family as the streaming reader hands it over: the neighbours
// (sorted, as in the file) and their partial-volume factors, `count` of each.
// The pointers are valid only during the call. `particles` is the set read so
// far: grid description, per-particle arrays, cells and family offsets (the
// sets and provenance come after the families).
using FamilyVisitor = std::function<void(const ParticleSet& particles, std::uint32_t particle,
                                         const std::uint32_t* neighbors, const double* partial_volume,
                                         std::size_t count)>;

// Bonds per read of the streaming reader: its buffer holds this many neighbour
// indices and factors (12 bytes each, 768 KiB). A larger family grows the
// buffer to that family's size, which is bounded by the particle count.
inline constexpr std::size_t family_read_chunk_bonds = std::size_t{1} << 16;

// Reads like read_particle_file, but passes each particle's family to `visit`
// (in particle order, once each) instead of keeping it: in the result
// `family_offsets` is filled (the file's bond count is family_offsets.back())
// and `neighbors`, `partial_volume` are empty, so bond_count() is 0 and
// validate() does not apply to the result.
// Memory beyond the per-particle arrays is a bounded read buffer, independent of
// the bond count. Every check of read_particle_file is made (neighbour index in
// range, partial volume finite and in (0, 1], checksum, counts, truncation, ...).
// Defects of the header, sizes and per-particle sections are reported before the
// first visit, and a bond is checked before its family is visited; a defect in
// the family sections, the sets or provenance after them, or the checksum may be
// reported after some families were visited: the caller must then discard what
// it built. `visit` must not be empty; exceptions it throws propagate.
ParticleSet read_particle_file(const std::string& path, const FamilyVisitor& visit);

// Checks internal consistency of an in-memory set (same checks as the reader
// after decoding). `where` prefixes the messages.
void validate(const ParticleSet& particles, const std::string& where);

}  // namespace pd
