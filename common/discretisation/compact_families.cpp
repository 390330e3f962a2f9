#include "compact_families.hpp"

#include <algorithm>
#include <cmath>

#include "bond_weights.hpp"
#include "error.hpp"

namespace pd {

std::uint64_t Families::bond_count() const {
  std::uint64_t total = neighbors.size();
  for (std::size_t l = 0; l < levels.size(); ++l)
    total += static_cast<std::uint64_t>(stencil_particle_count(static_cast<std::uint8_t>(l))) * levels[l].size();
  return total;
}

std::size_t Families::stencil_particle_count() const {
  return static_cast<std::size_t>(std::count(on_stencil.begin(), on_stencil.end(), std::uint8_t{1}));
}

std::size_t Families::stencil_particle_count(std::uint8_t l) const {
  std::size_t count = 0;
  for (std::size_t i = 0; i < particle_count; ++i) count += on_stencil[i] && level[i] == l ? 1 : 0;
  return count;
}

double Families::longest_stencil_bond() const {
  double longest = 0;
  for (const auto& s : levels)
    for (std::size_t o = 0; o < s.size(); ++o) longest = std::max(longest, std::hypot(s.di[o] * s.spacing, s.dj[o] * s.spacing));
  return longest;
}

Families Families::lattices_renumbered(const Families& whole, std::size_t n,
                                       const std::vector<std::uint32_t>& local_of) {
  Families f;
  f.particle_count = n;
  f.xmin = whole.xmin;
  f.ymin = whole.ymin;
  f.levels = whole.levels;
  for (StencilLevel& level : f.levels)
    for (std::uint32_t& at : level.at_cell)
      if (at != none) at = local_of[at];
  return f;
}

void Families::make_listed(const std::vector<std::uint32_t>& particles) {
  std::vector<std::uint8_t> convert(particle_count, 0);
  for (auto i : particles)
    if (on_stencil[i]) convert[i] = 1;
  std::vector<std::uint64_t> new_offsets(particle_count + 1, 0);
  // Reserved to size: grown bond by bond, the lists would hold up to twice
  // their bonds' memory (and both copies while growing), at the set-up's peak.
  std::uint64_t listed = 0;
  for (std::uint32_t i = 0; i < particle_count; ++i)
    if (convert[i] || !on_stencil[i]) listed += family_size(i);
  std::vector<std::uint32_t> new_neighbors;
  std::vector<double> new_phi;
  new_neighbors.reserve(listed);
  new_phi.reserve(listed);
  // The lists that stay lists are copied a run of rows at a time (they are
  // contiguous between two converted particles); only the converted
  // particles' stencil bonds are visited one by one.
  const auto append_lists = [&](std::uint32_t first, std::uint32_t end) {
    if (first == end) return;
    const auto from = static_cast<std::ptrdiff_t>(offsets[first]), to = static_cast<std::ptrdiff_t>(offsets[end]);
    const auto shift = static_cast<std::int64_t>(new_neighbors.size()) - from;
    new_neighbors.insert(new_neighbors.end(), neighbors.begin() + from, neighbors.begin() + to);
    new_phi.insert(new_phi.end(), partial_volume.begin() + from, partial_volume.begin() + to);
    for (std::uint32_t i = first; i < end; ++i)
      new_offsets[i + 1] = static_cast<std::uint64_t>(static_cast<std::int64_t>(offsets[i + 1]) + shift);
  };
  std::uint32_t run_start = 0;
  for (std::uint32_t i = 0; i < particle_count; ++i) {
    if (!convert[i]) continue;
    append_lists(run_start, i);
    for_each_bond(i, [&](const BondRef& b) {
      new_neighbors.push_back(b.neighbor);
      new_phi.push_back(b.partial_volume);
    });
    new_offsets[i + 1] = new_neighbors.size();
    run_start = i + 1;
  }
  append_lists(run_start, static_cast<std::uint32_t>(particle_count));
  for (std::uint32_t i = 0; i < particle_count; ++i)
    if (convert[i]) on_stencil[i] = 0;
  offsets.swap(new_offsets);
  neighbors.swap(new_neighbors);
  partial_volume.swap(new_phi);
}

namespace {
// Levels beyond this many square sizes are not built (their squares keep lists).
constexpr std::size_t max_levels = 16;
// A level's lattice may cover the plate's bounding box with at most this many
// cells per particle of the set (a fine level over a small band of a large
// plate would otherwise cost more in empty cells than it saves).
constexpr double max_cells_per_particle = 64;
}  // namespace

FamilyCollector::FamilyCollector(const ParticleSet& p) {
  const std::size_t n = p.size();
  f_.particle_count = n;
  f_.xmin = p.xmin;
  f_.ymin = p.ymin;
  f_.on_stencil.assign(n, 0);
  f_.cell.assign(n, -1);
  f_.level.assign(n, Families::no_level);
  f_.offsets.reserve(n + 1);
  f_.offsets.push_back(0);
  if (n == 0) return;
  const auto is_square_of = [&](std::size_t i, double size) {
    return p.region[i] == static_cast<std::uint8_t>(Region::uniform_square) && p.cell_size[i] == size &&
           p.volume[i] == size * size;
  };
  // The square sizes: the file's spacing first, then the others, largest first.
  std::vector<double> sizes;
  for (std::size_t i = 0; i < n; ++i)
    if (is_square_of(i, p.cell_size[i]) && p.cell_size[i] > 0 &&
        std::find(sizes.begin(), sizes.end(), p.cell_size[i]) == sizes.end())
      sizes.push_back(p.cell_size[i]);
  std::sort(sizes.begin(), sizes.end(), [&](double a, double b) {
    return (a == p.spacing) != (b == p.spacing) ? a == p.spacing : a > b;
  });
  if (sizes.size() > max_levels) sizes.resize(max_levels);

  for (const double s : sizes) {
    StencilLevel level;
    level.spacing = s;
    level.nx = std::lround((p.xmax - p.xmin) / s);
    level.ny = std::lround((p.ymax - p.ymin) / s);
    if (level.nx <= 0 || level.ny <= 0 ||
        static_cast<double>(level.nx) * static_cast<double>(level.ny) > max_cells_per_particle * n + 1e6)
      continue;
    const auto l = static_cast<std::uint8_t>(f_.levels.size());
    level.at_cell.assign(static_cast<std::size_t>(level.nx * level.ny), Families::none);
    for (std::uint32_t i = 0; i < n; ++i) {
      if (!is_square_of(i, s)) continue;
      const long col = static_cast<long>(std::floor((p.x[i] - p.xmin) / s));
      const long row = static_cast<long>(std::floor((p.y[i] - p.ymin) / s));
      if (col < 0 || col >= level.nx || row < 0 || row >= level.ny) continue;
      // Only squares whose centre is the cell's centre sit on this lattice.
      if (std::fabs(p.x[i] - (p.xmin + (col + 0.5) * s)) > 1e-6 * s ||
          std::fabs(p.y[i] - (p.ymin + (row + 0.5) * s)) > 1e-6 * s)
        continue;
      f_.level[i] = l;
      f_.cell[i] = row * level.nx + col;
      level.at_cell[static_cast<std::size_t>(f_.cell[i])] = i;
    }
    // The reference: the first square whose surroundings, one horizon and one
    // cell beyond, are all squares of this level, so that its family is a
    // whole interior family. Squares whose horizon is the level's own,
    // m x their side, come first: with smoothed horizons (theory.md Sec. 7)
    // most squares of a level have that one, a few near its edge larger ones.
    const double own_horizon = p.horizon_nominal * s / p.spacing;
    const auto first_interior = [&](bool own_horizon_only) {
      for (std::uint32_t i = 0; i < n; ++i) {
        if (f_.level[i] != l) continue;
        if (own_horizon_only && std::fabs(p.horizon[i] - own_horizon) > 1e-12 * own_horizon) continue;
        const long reach = static_cast<long>(std::ceil(p.horizon[i] / s)) + 1;
        const long col = static_cast<long>(f_.cell[i] % level.nx), row = static_cast<long>(f_.cell[i] / level.nx);
        if (col < reach || col + reach >= level.nx || row < reach || row + reach >= level.ny) continue;
        bool interior = true;
        for (long r = row - reach; r <= row + reach && interior; ++r)
          for (long c = col - reach; c <= col + reach && interior; ++c)
            interior = level.at_cell[static_cast<std::size_t>(r * level.nx + c)] != Families::none;
        if (interior) return i;
      }
      return Families::none;
    };
    std::uint32_t reference = first_interior(true);
    if (reference == Families::none) reference = first_interior(false);
    if (reference != Families::none) level.horizon = p.horizon[reference];
    reference_.push_back(reference);
    f_.levels.push_back(std::move(level));
  }
}

FamilyCollector::FamilyCollector(const ParticleSet& p, std::vector<std::uint8_t> keep) : FamilyCollector(p) {
  if (keep.size() != p.size())
    throw Error("FamilyCollector: " + std::to_string(keep.size()) + " keep flags for " + std::to_string(p.size()) +
                " particles");
  keep_ = std::move(keep);
}

FamilyCollector::FamilyCollector(const ParticleSet& p, const EarlierBondWeights* earlier) : FamilyCollector(p) {
  if (earlier && earlier->listed) {
    listed_anyway_.assign(p.size(), 0);
    for (const std::uint32_t i : *earlier->listed) listed_anyway_.at(i) = 1;
  }
  if (!earlier || !earlier->families || !earlier->listed_before || earlier->origin.size() != p.size() ||
      earlier->same_family.size() != p.size())
    return;
  // A family's match with its stencil reads the levels of its members'
  // squares (the lattice cells they are in): those of every shared particle
  // must be as before. (A split parent's cell is empty now and a child's
  // new, but neither is a member of a family the split copied.)
  const Families& before = *earlier->families;
  for (std::size_t i = 0; i < p.size(); ++i) {
    const std::uint32_t o = earlier->origin[i];
    if (o != Families::none && f_.level[i] != before.level[o]) return;
  }
  earlier_ = earlier;
  level_as_before_.assign(f_.levels.size(), -1);
  listed_before_.assign(before.particle_count, 0);
  for (const std::uint32_t o : *earlier->listed_before) listed_before_.at(o) = 1;
  // The lists at their expected size (the families that were listed before
  // the event and the others that may be): grown by doubling and shrunk at
  // the end, they would be copied up to three times.
  if (p.family_offsets.size() == p.size() + 1) {
    std::uint64_t expected = 0;
    for (std::size_t i = 0; i < p.size(); ++i) {
      const std::uint32_t o = earlier->same_family[i];
      if (o == Families::none || !before.on_stencil[o] || listed_anyway(static_cast<std::uint32_t>(i)))
        expected += p.family_offsets[i + 1] - p.family_offsets[i];
    }
    f_.neighbors.reserve(expected);
    f_.partial_volume.reserve(expected);
    reserved_ = true;
  }
}

int FamilyCollector::on_stencil_as_before(std::uint32_t i) {
  const std::uint8_t l = f_.level[i];
  const std::uint32_t o = earlier_->same_family[i];
  if (l == Families::no_level || o == Families::none) return -1;
  // A level's stencil is decided once its reference has been added (or it has none).
  if (reference_[l] != Families::none && i <= reference_[l]) return -1;
  if (level_as_before_[l] < 0) {
    const Families& before = *earlier_->families;
    const StencilLevel& now = f_.levels[l];
    bool same = l < before.levels.size() && f_.xmin == before.xmin && f_.ymin == before.ymin;
    if (same) {
      const StencilLevel& then = before.levels[l];
      same = now.spacing == then.spacing && now.nx == then.nx && now.ny == then.ny && now.di == then.di &&
             now.dj == then.dj && now.phi == then.phi;
    }
    level_as_before_[l] = same ? 1 : 0;
  }
  if (!level_as_before_[l]) return -1;
  // A family the pre-cracks listed before the event may match its stencil
  // or not: listed again with its earlier list where they list it now (the
  // stencil's partial volumes where it matched, as then), else compared.
  if (listed_before_[o]) return listed_anyway(i) ? listed_as_before : -1;
  return earlier_->families->on_stencil[o];
}

bool FamilyCollector::matches_stencil(std::uint32_t i, const std::uint32_t* neighbors, const double* phi,
                                      std::size_t count) const {
  if (f_.level[i] == Families::no_level) return false;
  const StencilLevel& s = f_.levels[f_.level[i]];
  if (count != s.size() || count == 0) return false;
  const long col = static_cast<long>(f_.cell[i] % s.nx), row = static_cast<long>(f_.cell[i] / s.nx);
  for (std::size_t o = 0; o < count; ++o) {
    const long c = col + s.di[o], r = row + s.dj[o];
    if (c < 0 || c >= s.nx || r < 0 || r >= s.ny) return false;
    if (s.at_cell[static_cast<std::size_t>(r * s.nx + c)] != neighbors[o]) return false;
    // The same analytic partial area of the same relative geometry: equal up
    // to round-off (~1e-13 seen); far below what a float damage weight resolves.
    if (std::fabs(phi[o] - s.phi[o]) > 1e-9) return false;
  }
  return true;
}

void FamilyCollector::append_listed(const std::uint32_t* neighbors, const double* phi, std::size_t count) {
  f_.neighbors.insert(f_.neighbors.end(), neighbors, neighbors + count);
  f_.partial_volume.insert(f_.partial_volume.end(), phi, phi + count);
  f_.offsets.push_back(f_.neighbors.size());
}

void FamilyCollector::take_stencil_from(std::uint32_t i, const std::uint32_t* neighbors, const double* phi,
                                        std::size_t count) {
  const std::uint8_t l = f_.level[i];
  StencilLevel& s = f_.levels[l];
  const long col = static_cast<long>(f_.cell[i] % s.nx), row = static_cast<long>(f_.cell[i] / s.nx);
  for (std::size_t o = 0; o < count; ++o) {
    const auto j = neighbors[o];
    if (f_.level[j] != l) {  // not a family of this level's squares after all: keep them all as lists
      s.di.clear();
      s.dj.clear();
      s.phi.clear();
      return;
    }
    s.di.push_back(static_cast<long>(f_.cell[j] % s.nx) - col);
    s.dj.push_back(static_cast<long>(f_.cell[j] / s.nx) - row);
    s.phi.push_back(phi[o]);
  }
  // The particles of this level before the reference were kept as lists:
  // drop the lists that are the stencil (in place; rows only move towards the front).
  std::uint64_t write = 0, read_begin = 0;
  for (std::uint32_t q = 0; q < i; ++q) {
    const std::uint64_t read_end = f_.offsets[q + 1];
    const std::size_t size = static_cast<std::size_t>(read_end - read_begin);
    const bool matches = !f_.on_stencil[q] && f_.level[q] == l &&
                         matches_stencil(q, f_.neighbors.data() + read_begin,
                                         f_.partial_volume.data() + read_begin, size);
    if (matches && !listed_anyway(q)) {
      f_.on_stencil[q] = 1;
    } else {
      std::copy(f_.neighbors.begin() + static_cast<std::ptrdiff_t>(read_begin),
                f_.neighbors.begin() + static_cast<std::ptrdiff_t>(read_end),
                f_.neighbors.begin() + static_cast<std::ptrdiff_t>(write));
      // A stencil family listed anyway has the stencil's partial volumes (as make_listed lists it).
      if (matches)
        std::copy(s.phi.begin(), s.phi.end(), f_.partial_volume.begin() + static_cast<std::ptrdiff_t>(write));
      else
        std::copy(f_.partial_volume.begin() + static_cast<std::ptrdiff_t>(read_begin),
                  f_.partial_volume.begin() + static_cast<std::ptrdiff_t>(read_end),
                  f_.partial_volume.begin() + static_cast<std::ptrdiff_t>(write));
      write += size;
    }
    f_.offsets[q + 1] = write;
    read_begin = read_end;
  }
  f_.neighbors.resize(write);
  f_.partial_volume.resize(write);
}

void FamilyCollector::add(std::uint32_t i, const std::uint32_t* neighbors, const double* phi, std::size_t count) {
  if (i != next_)
    throw Error("families must be collected in particle order: got particle " + std::to_string(i) + ", expected " +
                std::to_string(next_));
  ++next_;
  const std::uint8_t l = f_.level[i];
  if (l != Families::no_level && i == reference_[l]) take_stencil_from(i, neighbors, phi, count);
  if (!keep_.empty() && !keep_[i]) {
    f_.offsets.push_back(f_.neighbors.size());
    return;
  }
  const int as_before = earlier_ ? on_stencil_as_before(i) : -1;
  if (as_before == listed_as_before) {
    const Families& before = *earlier_->families;
    const std::uint64_t first = before.offsets[earlier_->same_family[i]];
    if (before.offsets[earlier_->same_family[i] + 1] - first != count)
      throw Error("FamilyCollector: particle " + std::to_string(i) + " has another bond count than before");
    append_listed(neighbors, before.partial_volume.data() + first, count);
    return;
  }
  const bool on_stencil = as_before >= 0 ? as_before == 1
                                         : l != Families::no_level && !f_.levels[l].phi.empty() &&
                                               matches_stencil(i, neighbors, phi, count);
  if (on_stencil && !listed_anyway(i)) {
    f_.on_stencil[i] = 1;
    f_.offsets.push_back(f_.neighbors.size());
  } else if (on_stencil) {
    // Listed as make_listed lists a stencil family: the stencil's bonds (the
    // same neighbours in the same order) with its partial volumes.
    if (count != f_.levels[l].size())
      throw Error("FamilyCollector: particle " + std::to_string(i) + " is on its stencil with another bond count");
    append_listed(neighbors, f_.levels[l].phi.data(), count);
  } else {
    append_listed(neighbors, phi, count);
  }
}

Families FamilyCollector::finish() {
  if (next_ != f_.particle_count)
    throw Error("families of " + std::to_string(next_) + " of " + std::to_string(f_.particle_count) +
                " particles collected");
  // Lists reserved at their expected size keep it unless it was well above
  // (a copy of every list to save a few bonds' memory).
  if (!reserved_ || f_.neighbors.capacity() - f_.neighbors.size() > f_.neighbors.size() / 8) {
    f_.neighbors.shrink_to_fit();
    f_.partial_volume.shrink_to_fit();
  }
  return std::move(f_);
}

Families compact_families(const ParticleSet& p, const EarlierBondWeights* earlier) {
  FamilyCollector collector(p, earlier);
  for (std::uint32_t i = 0; i < p.size(); ++i) {
    const auto first = p.family_offsets[i];
    collector.add(i, p.neighbors.data() + first, p.partial_volume.data() + first,
                  static_cast<std::size_t>(p.family_offsets[i + 1] - first));
  }
  return collector.finish();
}

ParticlesAndFamilies read_compact_particle_file(const std::string& path) {
  std::optional<FamilyCollector> collector;
  ParticlesAndFamilies r;
  r.particles = read_particle_file(path, [&](const ParticleSet& particles, std::uint32_t i,
                                             const std::uint32_t* neighbors, const double* phi, std::size_t count) {
    if (!collector) collector.emplace(particles);
    collector->add(i, neighbors, phi, count);
  });
  if (!collector) collector.emplace(r.particles);  // no particles, no families
  r.families = collector->finish();
  return r;
}

}  // namespace pd
