// Compact families (compact_families.hpp) against the particle file's own
// families: whether collected from memory or while the file streams by, every
// particle's bonds must come out as the file has them (same neighbours in the
// same order, partial volumes to 1e-9, the stencil's tolerance), with most
// squares on the stencil and nothing per bond stored for them.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "compact_families.hpp"
#include "families.hpp"
#include "lattice.hpp"
#include "particle_file.hpp"
#include "refinement.hpp"
#include "test_support.hpp"

using namespace pd;
using namespace pd::solver;

namespace {

// Largest difference in partial volume; fails on any other difference.
double compare_with_file(const pd::ParticleSet& p, const Families& f) {
  REQUIRE(f.particle_count == p.size());
  REQUIRE(f.bond_count() == p.bond_count());
  double worst = 0;
  for (std::uint32_t i = 0; i < p.size(); ++i) {
    auto b = p.family_offsets[i];
    f.for_each_bond(i, [&](const BondRef& bond) {
      REQUIRE(b < p.family_offsets[i + 1]);
      REQUIRE(bond.neighbor == p.neighbors[b]);
      worst = std::max(worst, std::fabs(bond.partial_volume - p.partial_volume[b]));
      ++b;
    });
    REQUIRE(b == p.family_offsets[i + 1]);
  }
  return worst;
}

}  // namespace

TEST_CASE("compact families give back the particle file's families", "[families]") {
  const double dx = 1e-4, horizon = 4 * dx;
  const auto p = pd::make_rectangle_lattice(40 * dx, 30 * dx, dx, horizon, pd::Quadrature::analytic);
  const auto folder = test::fresh_folder("compact_families");
  const std::string path = (std::filesystem::path(folder) / "plate.pdp").string();
  pd::write_particle_file(path, p);

  const auto in_memory = compact_families(p);
  const auto streamed = read_compact_particle_file(path);
  CHECK(compare_with_file(p, in_memory) < 1e-9);
  CHECK(compare_with_file(p, streamed.families) < 1e-9);

  // The streamed particle set keeps no families, the rest is the file's.
  CHECK(streamed.particles.neighbors.empty());
  CHECK(streamed.particles.partial_volume.empty());
  CHECK(streamed.particles.family_offsets == p.family_offsets);
  CHECK(streamed.particles.x == p.x);

  // Squares one horizon and more from the edges have the full interior
  // family: (40 - 2 * 4) x (30 - 2 * 4) of them, all on the stencil; only
  // the others keep lists.
  const auto& f = streamed.families;
  CHECK(f.stencil_particle_count() == (40 - 8) * (30 - 8));
  CHECK(in_memory.stencil_particle_count() == f.stencil_particle_count());
  REQUIRE(f.levels.size() == 1);
  CHECK(f.neighbors.size() == p.bond_count() - f.stencil_particle_count() * f.levels[0].size());
  CHECK(f.levels[0].size() > 40);
}

TEST_CASE("particles taken off the stencil keep their families", "[families]") {
  const double dx = 1e-4;
  const auto p = pd::make_rectangle_lattice(30 * dx, 30 * dx, dx, 3 * dx, pd::Quadrature::analytic);
  auto f = compact_families(p);
  const auto before = f.stencil_particle_count();
  std::vector<std::uint32_t> some;
  for (std::uint32_t i = 0; i < p.size() && some.size() < 5; i += 37)
    if (f.on_stencil[i]) some.push_back(i);
  REQUIRE(some.size() == 5);
  f.make_listed(some);
  CHECK(f.stencil_particle_count() == before - 5);
  CHECK(compare_with_file(p, f) < 1e-9);
}

TEST_CASE("a grid of two resolutions gets a stencil per resolution level", "[families]") {
  // Left half: squares of 2 dx; right half: squares of dx; each particle's
  // horizon is 3 times its own cell size (families by the exact partial
  // areas, built by the discretisation library). Reference: the file's own
  // families, which the compact form must give back bond for bond.
  const double dx = 1e-4;
  pd::ParticleSet p;
  p.grid = pd::GridKind::nbnug;
  p.quadrature = pd::Quadrature::analytic;
  p.spacing = 2 * dx;
  p.horizon_nominal = 6 * dx;
  p.xmin = 0, p.ymin = 0, p.xmax = 80 * dx, p.ymax = 40 * dx;
  const auto all = [](long, long) { return true; };
  pd::append_lattice_squares(p, 0, 0, 2 * dx, 0, 20, 0, 20, all, pd::Region::uniform_square);
  const std::size_t coarse = p.size();
  pd::append_lattice_squares(p, 40 * dx, 0, dx, 0, 40, 0, 40, all, pd::Region::uniform_square);
  for (std::size_t i = 0; i < p.size(); ++i) p.horizon[i] = 3 * p.cell_size[i];
  pd::build_families(p, pd::Quadrature::analytic);

  const auto f = compact_families(p);
  CHECK(compare_with_file(p, f) < 1e-9);
  REQUIRE(f.levels.size() == 2);
  CHECK(f.levels[0].spacing == 2 * dx);  // the file's spacing first
  CHECK(f.levels[1].spacing == dx);
  CHECK(f.levels[1].horizon == 3 * dx);
  // Each level has interior squares with a whole family on its stencil.
  CHECK(f.stencil_particle_count(0) > 0);
  CHECK(f.stencil_particle_count(1) > 0);
  CHECK(f.stencil_particle_count(0) + f.stencil_particle_count(1) == f.stencil_particle_count());
  for (std::size_t i = 0; i < p.size(); ++i)
    if (f.on_stencil[i]) CHECK(f.level[i] == (i < coarse ? 0 : 1));
}

TEST_CASE("with smoothed horizons a level's stencil is the family of its squares' own horizon", "[families]") {
  // A plate of 24 x 12 squares of dx, its right half refined 4x, the fine
  // horizons ramping from 3 dx at the interface to 3 dx / 4 over 12 fine
  // spacings (horizon_smoothing.hpp): in particle order, squares of the ramp
  // with whole fine families come before any square with the fine horizon.
  // Reference: the file's own families, bond for bond, and the stencil of
  // the fine level is that of the fine horizon m x the fine side, which
  // most fine squares have.
  const double dx = 1e-4, fine = dx / 4, width = 24 * dx, height = 12 * dx;
  pd::RefinementRegion r;
  r.x0 = 12 * dx, r.y0 = 0, r.x1 = width, r.y1 = height, r.factor = 4;
  const auto p = pd::make_refined_rectangle_lattice(width, height, dx, 3 * dx, r, pd::Quadrature::analytic, 12 * fine);
  const auto f = compact_families(p);
  CHECK(compare_with_file(p, f) < 1e-9);
  REQUIRE(f.levels.size() == 2);
  CHECK(f.levels[1].spacing == fine);
  CHECK(f.levels[1].horizon == Approx(3 * fine).epsilon(1e-12));
  std::size_t smoothed = 0, smoothed_on_stencil = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (p.cell_size[i] != fine || std::fabs(p.horizon[i] - 3 * fine) < 1e-12 * fine) continue;
    ++smoothed;
    smoothed_on_stencil += f.on_stencil[i];
  }
  CHECK(smoothed == 12u * 48u);
  CHECK(smoothed_on_stencil == 0);
  CHECK(f.stencil_particle_count(1) > 0);
}

TEST_CASE("families must be collected in particle order", "[families]") {
  const double dx = 1e-4;
  const auto p = pd::make_rectangle_lattice(10 * dx, 10 * dx, dx, 3 * dx, pd::Quadrature::analytic);
  FamilyCollector collector(p);
  CHECK_THROWS_WITH(collector.add(1, p.neighbors.data(), p.partial_volume.data(), 1),
                    Catch::Contains("in particle order"));
}

// The progress callback of build_families (pd-mesh's progress line) sees the
// count of particles done rise to the particle count, and the families are
// the same as without it.
TEST_CASE("build_families reports its progress up to every particle, with the same families", "[families]") {
  const double dx = 1e-4;
  const auto plain = pd::make_rectangle_lattice(100 * dx, 50 * dx, dx, 3 * dx, pd::Quadrature::analytic);
  auto p = plain;
  std::vector<std::size_t> seen;
  pd::build_families(p, pd::Quadrature::analytic, nullptr, [&](std::size_t done, std::size_t total) {
    CHECK(total == p.size());
    seen.push_back(done);
  });
  REQUIRE_FALSE(seen.empty());
  CHECK(std::is_sorted(seen.begin(), seen.end()));
  CHECK(seen.back() <= p.size());
  CHECK(seen.front() > 0);
  CHECK(p.neighbors == plain.neighbors);
  CHECK(p.partial_volume == plain.partial_volume);
}
