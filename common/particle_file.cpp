#include "particle_file.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "atomic_file.hpp"
#include "checksum.hpp"
#include "error.hpp"

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

// ---- Payload serialisation ---------------------------------------------------
class PayloadWriter {
public:
  explicit PayloadWriter(std::ofstream& out) : out_(out) {}
  template <class T>
  void array(const std::vector<T>& v) {
    bytes(v.data(), v.size() * sizeof(T));
  }
  template <class T>
  void scalar(T v) {
    bytes(&v, sizeof v);
  }
  void bytes(const void* p, std::size_t n) {
    out_.write(static_cast<const char*>(p), static_cast<std::streamsize>(n));
    checksum_.update(p, n);
    count_ += n;
  }
  std::uint64_t count() const { return count_; }
  std::uint64_t checksum() const { return checksum_.value(); }

private:
  std::ofstream& out_;
  Checksum checksum_;
  std::uint64_t count_ = 0;
};

// Decodes the payload straight from the file into the arrays (no second copy
// of a file that may be hundreds of MB), checksumming on the way. Counts are
// checked against the bytes left before anything is allocated.
class PayloadReader {
public:
  PayloadReader(std::ifstream& in, std::uint64_t size, const std::string& path)
      : in_(in), size_(size), remaining_(size), path_(path) {}
  template <class T>
  void array(std::vector<T>& v, std::uint64_t n, const char* what) {
    require_room(n, sizeof(T), 0, what);
    v.resize(n);
    read(v.data(), n * sizeof(T), what);
  }
  // Reads the next `n` elements of a section into `destination` (a chunk of
  // a section too large to hold at once).
  template <class T>
  void elements(T* destination, std::uint64_t n, const char* what) {
    require_room(n, sizeof(T), 0, what);
    read(destination, n * sizeof(T), what);
  }
  // Throws unless `n` elements of `element_bytes` each fit in the payload
  // after the next `skipped` bytes (which must fit themselves).
  void require_room(std::uint64_t n, std::size_t element_bytes, std::uint64_t skipped,
                    const char* what) const {
    if (skipped > remaining_ || n > (remaining_ - skipped) / element_bytes)
      throw file_error(path_, std::string("truncated or inconsistent counts while reading ") + what);
  }
  template <class T>
  T scalar(const char* what) {
    if (sizeof(T) > remaining_) throw file_error(path_, std::string("truncated while reading ") + what);
    T v;
    read(&v, sizeof(T), what);
    return v;
  }
  std::string string(std::uint64_t n, const char* what) {
    if (n > remaining_) throw file_error(path_, std::string("truncated while reading ") + what);
    std::string s(n, '\0');
    read(s.data(), n, what);
    return s;
  }
  std::uint64_t position() const { return size_ - remaining_; }  // bytes read so far
  std::uint64_t remaining() const { return remaining_; }
  std::uint64_t checksum() const { return checksum_.value(); }

private:
  void read(void* p, std::uint64_t bytes, const char* what) {
    in_.read(static_cast<char*>(p), static_cast<std::streamsize>(bytes));
    if (static_cast<std::uint64_t>(in_.gcount()) != bytes)
      throw file_error(path_, std::string("truncated while reading ") + what);
    checksum_.update(p, bytes);
    remaining_ -= bytes;
  }
  std::ifstream& in_;
  std::uint64_t size_;
  std::uint64_t remaining_;
  const std::string& path_;
  Checksum checksum_;
};

void write_payload(PayloadWriter& w, const ParticleSet& p) {
  w.array(p.x);
  w.array(p.y);
  w.array(p.volume);
  w.array(p.cell_size);
  w.array(p.horizon);
  w.array(p.region);
  w.array(p.material);
  w.array(p.cell_offsets);
  w.array(p.cell_vx);
  w.array(p.cell_vy);
  w.array(p.family_offsets);
  w.array(p.neighbors);
  w.array(p.partial_volume);
  for (const auto& s : p.sets) {
    w.scalar<std::uint32_t>(static_cast<std::uint32_t>(s.name.size()));
    w.bytes(s.name.data(), s.name.size());
    w.scalar<std::uint64_t>(s.particles.size());
    w.array(s.particles);
  }
  w.scalar<std::uint64_t>(p.provenance.size());
  w.bytes(p.provenance.data(), p.provenance.size());
}

std::string describe_index(const char* array, std::size_t i) {
  return std::string(array) + "[" + std::to_string(i) + "]";
}

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

// The checks of validate() that do not need the bonds themselves: counts,
// grid scalars, per-particle values, cell offsets and family offsets (which
// must span `bond_count` bonds). The streaming reader makes them before it
// cuts the first family out of the file.
void validate_particles(const ParticleSet& p, std::uint64_t bond_count, const std::string& where) {
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
  if (!(std::isfinite(p.spacing) && p.spacing > 0))
    throw Error(where + ": spacing must be positive and finite");
  if (!(std::isfinite(p.horizon_nominal) && p.horizon_nominal > 0))
    throw Error(where + ": horizon must be positive and finite");
  for (double b : {p.xmin, p.ymin, p.xmax, p.ymax})
    if (!std::isfinite(b)) throw Error(where + ": non-finite bounding box");
  require_finite(p.x, "x", where);
  require_finite(p.y, "y", where);
  require_finite(p.cell_vx, "cell_vx", where);
  require_finite(p.cell_vy, "cell_vy", where);
  for (std::size_t i = 0; i < n; ++i) {
    if (!(std::isfinite(p.volume[i]) && p.volume[i] > 0))
      throw Error(where + ": volume must be positive and finite, " + describe_index("volume", i) + " = " +
                  std::to_string(p.volume[i]));
    if (!(std::isfinite(p.horizon[i]) && p.horizon[i] > 0))
      throw Error(where + ": horizon must be positive and finite at " + describe_index("horizon", i));
    if (!(std::isfinite(p.cell_size[i]) && p.cell_size[i] > 0))
      throw Error(where + ": cell_size must be positive and finite at " + describe_index("cell_size", i));
    if (p.region[i] > 2)
      throw Error(where + ": unknown region code " + std::to_string(p.region[i]) + " at particle " +
                  std::to_string(i));
  }
  if (p.cell_vx.size() != p.cell_vy.size())
    throw Error(where + ": inconsistent counts: cell_vx and cell_vy differ");
  require_csr<double>(p.cell_offsets, n, p.cell_vx.size(), "cell_offsets", where);
  require_csr<std::uint32_t>(p.family_offsets, n, bond_count, "family_offsets", where);
}

// The per-bond checks, for bond k of a set of `particle_count` particles.
void validate_bond(std::uint64_t k, std::uint32_t neighbor, double partial_volume, std::size_t particle_count,
                   const std::string& where) {
  if (neighbor >= particle_count)
    throw Error(where + ": neighbour index out of range at " + describe_index("neighbors", k) + " = " +
                std::to_string(neighbor) + " (" + std::to_string(particle_count) + " particles)");
  if (!(std::isfinite(partial_volume) && partial_volume > 0 && partial_volume <= 1 + 1e-12))
    throw Error(where + ": partial-volume factor outside (0, 1] at " + describe_index("partial_volume", k) +
                " = " + std::to_string(partial_volume));
}

void validate_sets(const ParticleSet& p, const std::string& where) {
  const std::size_t n = p.size();
  for (const auto& s : p.sets) {
    if (s.name.empty()) throw Error(where + ": a boundary set has an empty name");
    for (auto i : s.particles)
      if (i >= n) throw Error(where + ": set '" + s.name + "' refers to particle " + std::to_string(i) +
                              " of " + std::to_string(n));
  }
}

}  // namespace

void validate(const ParticleSet& p, const std::string& where) {
  validate_particles(p, p.neighbors.size(), where);
  if (p.partial_volume.size() != p.neighbors.size())
    throw Error(where + ": inconsistent counts: partial_volume and neighbors differ");
  for (std::size_t k = 0; k < p.neighbors.size(); ++k)
    validate_bond(k, p.neighbors[k], p.partial_volume[k], p.size(), where);
  validate_sets(p, where);
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
    PayloadWriter w(out);
    write_payload(w, p);
    h.payload_bytes = w.count();
    h.payload_checksum = w.checksum();
    h.header_checksum = checksum_of(&h, offsetof(Header, header_checksum));
    out.seekp(0);
    out.write(reinterpret_cast<const char*>(&h), sizeof h);
  });
}

namespace {

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
  if (!in) throw file_error(path, "cannot open particle file");
  const auto file_size = static_cast<std::uint64_t>(in.tellg());
  in.seekg(0);
  if (file_size < header_bytes)
    throw file_error(path, "truncated: " + std::to_string(file_size) + " bytes, shorter than the " +
                               std::to_string(header_bytes) + "-byte header");
  in.read(reinterpret_cast<char*>(&h), sizeof h);
  if (std::memcmp(h.magic, magic, 8) != 0)
    throw file_error(path, "not a particle file (wrong magic number; expected 'PDPARTS')");
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
void read_particle_sections(PayloadReader& r, const Header& h, ParticleSet& p) {
  const auto n = h.particle_count;
  r.array(p.x, n, "x");
  r.array(p.y, n, "y");
  r.array(p.volume, n, "volume");
  r.array(p.cell_size, n, "cell_size");
  r.array(p.horizon, n, "horizon");
  r.array(p.region, n, "region");
  r.array(p.material, n, "material");
  r.array(p.cell_offsets, n + 1, "cell_offsets");
  r.array(p.cell_vx, h.cell_vertex_count, "cell_vx");
  r.array(p.cell_vy, h.cell_vertex_count, "cell_vy");
  r.array(p.family_offsets, n + 1, "family_offsets");
}

// Throws unless the sets fit in the payload after the next `skipped` bytes,
// each at least its two lengths (no name, no particles), followed by the
// provenance length: checked before the sets are allocated.
void require_room_for_sets(const PayloadReader& r, const Header& h, std::uint64_t skipped) {
  constexpr std::size_t smallest_set = sizeof(std::uint32_t) + sizeof(std::uint64_t);
  r.require_room(h.set_count, smallest_set, skipped + sizeof(std::uint64_t), "sets");
}

// The payload after the bonds (sets, provenance), then the checks that the
// payload is used up and matches its checksum.
void read_trailing_sections(PayloadReader& r, const Header& h, ParticleSet& p, const std::string& path) {
  require_room_for_sets(r, h, 0);
  p.sets.resize(h.set_count);
  for (auto& s : p.sets) {
    const auto len = r.scalar<std::uint32_t>("set name length");
    s.name = r.string(len, "set name");
    const auto count = r.scalar<std::uint64_t>("set size");
    r.array(s.particles, count, "set particles");
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
void stream_families(PayloadReader& payload, const ParticleSet& p, std::uint64_t bond_count,
                     const std::string& path, const FamilyVisitor& visit) {
  constexpr std::size_t neighbor_bytes = sizeof(std::uint32_t);
  std::ifstream second(path, std::ios::binary);
  if (!second) throw file_error(path, "cannot open particle file");
  second.seekg(static_cast<std::streamoff>(header_bytes + payload.position() + bond_count * neighbor_bytes));
  PayloadReader factors_reader(second, bond_count * sizeof(double), path);

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
      for (std::size_t k = kept; k < kept + fresh; ++k)
        validate_bond(begin + k, neighbors[k], factors[k], n, path);
      window_begin = begin;
      window_end += fresh;
    }
    const auto at = static_cast<std::size_t>(begin - window_begin);
    visit(p, static_cast<std::uint32_t>(i), neighbors.data() + at, factors.data() + at,
          static_cast<std::size_t>(end - begin));
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
  PayloadReader r(file.in, h.payload_bytes, path);
  read_particle_sections(r, h, p);
  r.array(p.neighbors, h.bond_count, "neighbors");
  r.array(p.partial_volume, h.bond_count, "partial_volume");
  read_trailing_sections(r, h, p, path);
  validate(p, path);
  return p;
}

ParticleSet read_particle_file(const std::string& path, const FamilyVisitor& visit) {
  if (!visit) throw std::invalid_argument("read_particle_file: empty family visitor");
  auto file = open_particle_file(path);
  const Header& h = file.header;
  ParticleSet p = grid_of(h);
  PayloadReader r(file.in, h.payload_bytes, path);
  read_particle_sections(r, h, p);
  // Counts that do not fit the payload are reported as such before the values
  // they misplace (in this order, so that 12 * bond_count cannot overflow).
  r.require_room(h.bond_count, sizeof(std::uint32_t), 0, "neighbors");
  r.require_room(h.bond_count, sizeof(double), h.bond_count * sizeof(std::uint32_t), "partial_volume");
  require_room_for_sets(r, h, h.bond_count * (sizeof(std::uint32_t) + sizeof(double)));
  // The families are cut out of the file by these offsets: check them (and
  // everything else known so far) before the first visit.
  validate_particles(p, h.bond_count, path);
  stream_families(r, p, h.bond_count, path, visit);
  read_trailing_sections(r, h, p, path);
  validate_sets(p, path);
  return p;
}

}  // namespace pd
