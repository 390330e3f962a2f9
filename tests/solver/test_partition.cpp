// The slabs of a run on several processes (solver/state/partition.hpp): every
// particle owned once, slabs of balanced directed bonds, ghosts exactly the
// neighbours owned elsewhere. No MPI needed: a partition is computed the same
// on every process from the particle file.
#include <catch2/catch.hpp>
#include <algorithm>
#include <cmath>
#include <numeric>

#include "compact_families.hpp"
#include "partition.hpp"
#include "test_support.hpp"

using namespace pd;
using namespace pd::solver;

TEST_CASE("slabs own every particle once, balance directed bonds and list every ghost", "[partition]") {
  // 60 x 20 dx (m = 3): wide, so the slabs follow each other along x.
  const ParticleSet p = make_rectangle_lattice(60e-3, 20e-3, 1e-3, 3e-3, Quadrature::analytic);
  const Families f = compact_families(p);
  const std::uint64_t total = f.bond_count();
  // The heaviest column of particles: a slab boundary moves in whole columns.
  std::vector<double> column_bonds;
  for (std::uint32_t i = 0; i < p.size(); ++i) {
    const auto column = static_cast<std::size_t>(std::lround((p.x[i] - p.xmin) / 1e-3 - 0.5));
    if (column >= column_bonds.size()) column_bonds.resize(column + 1, 0.0);
    column_bonds[column] += f.family_size(i);
  }
  const double heaviest_column = *std::max_element(column_bonds.begin(), column_bonds.end());

  for (int size : {2, 3, 7}) {
    INFO(size << " processes");
    std::vector<int> owners(p.size(), 0);
    std::uint64_t bonds = 0;
    for (int rank = 0; rank < size; ++rank) {
      const Partition part = slab_partition(p, f, rank, size, "plate");
      CHECK(part.axis == 0);
      REQUIRE(part.cuts.size() == static_cast<std::size_t>(size - 1));
      CHECK(std::is_sorted(part.owned.begin(), part.owned.end()));
      CHECK(std::is_sorted(part.ghosts.begin(), part.ghosts.end()));
      // Bonds within one column of the even share.
      CHECK(std::fabs(static_cast<double>(part.owned_bonds) - static_cast<double>(total) / size) <= heaviest_column);
      bonds += part.owned_bonds;
      std::vector<std::uint8_t> local(p.size(), 0), needed(p.size(), 0);
      for (auto i : part.owned) {
        ++owners[i];
        local[i] = 1;
        // Owned particles lie between this slab's cuts.
        if (rank > 0) CHECK(p.x[i] > part.cuts[rank - 1]);
        if (rank < size - 1) CHECK(p.x[i] < part.cuts[rank]);
      }
      for (auto i : part.owned) f.for_each_bond(i, [&](const BondRef& b) { needed[b.neighbor] = !local[b.neighbor]; });
      std::vector<std::uint32_t> expected;
      for (std::uint32_t i = 0; i < p.size(); ++i)
        if (needed[i]) expected.push_back(i);
      CHECK(part.ghosts == expected);
      // A ghost's owner is the slab on either side.
      for (int owner : part.ghost_owner) CHECK(std::abs(owner - rank) == 1);
    }
    CHECK(bonds == total);
    CHECK(std::all_of(owners.begin(), owners.end(), [](int n) { return n == 1; }));
    std::fill(owners.begin(), owners.end(), 0);
  }
}

TEST_CASE("more processes than positions along the plate is refused, naming the file", "[partition]") {
  const ParticleSet p = make_rectangle_lattice(4e-3, 2e-3, 1e-3, 3e-3, Quadrature::analytic);
  const Families f = compact_families(p);
  CHECK_THROWS_WITH(slab_partition(p, f, 0, 5, "small.pdp"),
                    Catch::Contains("small.pdp") && Catch::Contains("5 slabs"));
}
