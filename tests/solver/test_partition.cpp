// The slabs of a run on several processes (solver/state/partition.hpp): every
// particle owned once, slabs of balanced directed bonds, ghosts exactly the
// neighbours owned elsewhere. No MPI needed: a partition is computed the same
// on every process from the particle file.
#include <catch2/catch.hpp>
#include <algorithm>
#include <cmath>
#include <condition_variable>
#include <mutex>
#include <numeric>
#include <thread>

#include "bond_setup.hpp"
#include "compact_families.hpp"
#include "local_bonds.hpp"
#include "partition.hpp"
#include "pmb.hpp"
#include "surface_correction.hpp"
#include "test_support.hpp"
#include "variable_horizon_bonds.hpp"

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

TEST_CASE("with dual horizons a slab's ghosts also hold the particles that own a bond to its particles",
          "[partition][dual_horizon]") {
  // 40 x 10 squares of 1 mm, m = 3, the right half refined 4x: horizons 3 mm
  // and 0.75 mm. A coarse particle's bond reaches 3 mm into the fine half,
  // while the fine particles' own bonds reach 0.75 mm: the slab next to the
  // coarse half needs, for the dual entries of its rows, coarse particles
  // that none of its own bonds reaches (GhostReach::bonds_both_ways).
  const ParticleSet p = test::half_refined_plate(40e-3, 10e-3, 1e-3, 3, 4);
  const Families f = compact_families(p);
  const auto [low, high] = std::minmax_element(p.horizon.begin(), p.horizon.end());
  REQUIRE(*low == Approx(0.75e-3));
  REQUIRE(*high == Approx(3e-3));
  const int size = 7;
  std::size_t extra_ghosts = 0;  // ghosts only the bonds towards a slab bring, over all slabs
  for (int rank = 0; rank < size; ++rank) {
    INFO("process " << rank);
    const Partition own = slab_partition(p, f, rank, size, "plate", GhostReach::own_bonds);
    const Partition both = slab_partition(p, f, rank, size, "plate", GhostReach::bonds_both_ways);
    CHECK(both.owned == own.owned);
    CHECK(both.cuts == own.cuts);
    std::vector<std::uint8_t> is_owned(p.size(), 0), needed(p.size(), 0);
    for (auto i : both.owned) is_owned[i] = 1;
    for (std::uint32_t i = 0; i < p.size(); ++i)
      f.for_each_bond(i, [&](const BondRef& b) {
        if (is_owned[i] && !is_owned[b.neighbor]) needed[b.neighbor] = 1;  // i's own bond
        if (!is_owned[i] && is_owned[b.neighbor]) needed[i] = 1;           // a bond towards an owned particle
      });
    std::vector<std::uint32_t> expected;
    for (std::uint32_t i = 0; i < p.size(); ++i)
      if (needed[i]) expected.push_back(i);
    CHECK(both.ghosts == expected);
    CHECK(std::includes(both.ghosts.begin(), both.ghosts.end(), own.ghosts.begin(), own.ghosts.end()));
    extra_ghosts += both.ghosts.size() - own.ghosts.size();
    // The ghosts lie within the largest horizon of the slab (the cut on either side).
    for (auto g : both.ghosts) {
      if (rank > 0) CHECK(p.x[g] > both.cuts[rank - 1] - *high);
      if (rank < size - 1) CHECK(p.x[g] < both.cuts[rank] + *high);
    }
  }
  CHECK(extra_ghosts > 0);
}

TEST_CASE("a process's dual-horizon rows are the whole plate's rows of its owned particles",
          "[partition][dual_horizon]") {
  // The half-refined plate above, its whole dual-horizon rows with damage
  // (combined entries where the horizons are equal, separate dual entries
  // across the change of horizon), cut for each of 7 slabs (local_rows; the
  // first slab holds the coarse half and less than one coarse horizon of the
  // fine half).
  const ParticleSet p = test::half_refined_plate(40e-3, 10e-3, 1e-3, 3, 4);
  Scene scene = test::basic_scene();
  scene.dual_horizon = true;
  scene.effects.damage = true;
  const BondSetup setup = build_bond_setup(scene, p, compact_families(p), {});
  REQUIRE(setup.horizon_mode == HorizonMode::dual_horizon);
  std::vector<std::uint8_t> intact;
  std::vector<std::uint64_t> entry_bond;
  const BondTable whole = variable_horizon_table<Pmb>(p, setup, scene.material, HorizonMode::dual_horizon, true,
                                                      &intact, {}, &entry_bond);
  // The directed bonds family by family (the checkpoints' layout), and every
  // 7th of them broken, in both of its entries.
  std::vector<std::pair<std::uint32_t, std::uint32_t>> ends;
  for (std::uint32_t i = 0; i < p.size(); ++i)
    setup.families.for_each_bond(i, [&](const BondRef& b) { ends.emplace_back(i, b.neighbor); });
  std::size_t dual_entries = 0;
  for (std::uint32_t i = 0; i < p.size(); ++i)
    for (auto e = whole.offsets[i]; e < whole.offsets[i + 1]; ++e) {
      REQUIRE(entry_bond[e] < ends.size());
      const auto [owner, neighbor] = ends[entry_bond[e]];
      const bool own = e < whole.own_end(i);
      // An own entry carries its own bond, a dual entry the bond its neighbour owns towards i.
      CHECK(owner == (own ? i : whole.neighbor[e]));
      CHECK(neighbor == (own ? whole.neighbor[e] : i));
      dual_entries += own ? 0 : 1;
      intact[e] = entry_bond[e] % 7 == 0 ? 0 : 1;
    }
  CHECK(dual_entries > 0);
  const std::uint64_t broken = (ends.size() + 6) / 7;
  CHECK(broken_directed_bonds(whole, intact) == broken);

  const int size = 7;
  std::uint64_t broken_over_processes = 0;
  for (int rank = 0; rank < size; ++rank) {
    INFO("process " << rank);
    const Partition part = slab_partition(p, setup.families, rank, size, "plate", GhostReach::bonds_both_ways);
    const std::vector<std::uint32_t> ids = part.local_ids();
    const LocalRows local = local_rows(whole, intact, entry_bond, ids, part.owned.size());
    REQUIRE(local.table.particle_count == ids.size());
    REQUIRE(local.intact.size() == local.table.size());
    REQUIRE(local.entry_bond.size() == local.table.size());
    for (std::size_t l = 0; l < ids.size(); ++l) {
      const std::uint64_t begin = local.table.offsets[l], end = local.table.offsets[l + 1];
      if (l >= part.owned.size()) {
        CHECK(begin == end);  // a ghost: no row
        continue;
      }
      const std::uint32_t i = ids[l];
      REQUIRE(end - begin == whole.offsets[i + 1] - whole.offsets[i]);
      CHECK(local.table.dual_begin[l] - begin == whole.dual_begin[i] - whole.offsets[i]);
      CHECK(local.table.family_area[l] == whole.family_area[i]);
      for (std::uint64_t k = 0; k < end - begin; ++k) {
        const std::uint64_t e = begin + k, w = whole.offsets[i] + k;
        CHECK(ids[local.table.neighbor[e]] == whole.neighbor[w]);
        CHECK(local.table.xi_x[e] == whole.xi_x[w]);
        CHECK(local.table.xi_y[e] == whole.xi_y[w]);
        CHECK(local.table.stiffness[e] == whole.stiffness[w]);
        CHECK(local.table.critical_extension[e] == whole.critical_extension[w]);
        CHECK(local.table.entry_halves[e] == whole.entry_halves[w]);
        CHECK(local.intact[e] == intact[w]);
        CHECK(local.entry_bond[e] == entry_bond[w]);
      }
    }
    broken_over_processes += broken_own_entries(local.table, local.intact);
  }
  // Each directed bond counted once, by its owner's process.
  CHECK(broken_over_processes == broken);

  // With the ghosts of the owned particles' own bonds only (a band of their
  // own horizons), a slab next to larger horizons misses owners of its dual
  // entries: the cut refuses rather than misnumbers them.
  bool refused = false;
  for (int rank = 0; rank < size; ++rank) {
    const Partition part = slab_partition(p, setup.families, rank, size, "plate", GhostReach::own_bonds);
    try {
      local_rows(whole, intact, entry_bond, part.local_ids(), part.owned.size());
    } catch (const Error& e) {
      CHECK(std::string(e.what()).find("is not among the local particles") != std::string::npos);
      refused = true;
    }
  }
  CHECK(refused);
}

namespace {

// Processes of a distributed run played by threads of one program: each
// waits for all at the barrier, so that values published before it are read
// after it (the exchange of an MPI run, in memory).
class Barrier {
public:
  explicit Barrier(int count) : count_(count) {}
  void wait() {
    std::unique_lock<std::mutex> lock(mutex_);
    const long generation = generation_;
    if (++waiting_ == count_) {
      waiting_ = 0;
      ++generation_;
      changed_.notify_all();
    } else {
      changed_.wait(lock, [&] { return generation_ != generation; });
    }
  }

private:
  std::mutex mutex_;
  std::condition_variable changed_;
  int count_, waiting_ = 0;
  long generation_ = 0;
};

}  // namespace

TEST_CASE("the surface correction's scalar factors iterated on slabs equal the whole plate's bit for bit",
          "[partition][surface_correction]") {
  // 60 x 20 dx (m = 3) with a pre-crack from the left edge: edges, corners
  // and crack faces give listed families with directional shapes, and the
  // factors along the edges couple the slabs through the fixed point.
  const double dx = 1e-3;
  const ParticleSet p = make_rectangle_lattice(60 * dx, 20 * dx, dx, 3 * dx, Quadrature::analytic);
  Scene scene = test::basic_scene();
  scene.effects.surface_correction = true;
  scene.precracks = {PrecrackSpec{{0.0, 10.01 * dx}, {31.3 * dx, 10.01 * dx}}};
  const BondSetup whole = build_bond_setup(scene, p, compact_families(p), {});
  REQUIRE(whole.lambda_iterations > 5);
  std::size_t corrected = 0;
  for (double l : whole.lambda) corrected += std::fabs(l - 1.0) > 1e-3 ? 1 : 0;
  REQUIRE(corrected > 100);  // the factors are not all 1
  SetupOptions without;
  without.scalar_factors = false;
  const BondSetup unfactored = build_bond_setup(scene, p, compact_families(p), without);
  CHECK(unfactored.lambda_iterations == 0);
  CHECK(std::all_of(unfactored.lambda.begin(), unfactored.lambda.end(), [](double l) { return l == 1.0; }));
  REQUIRE(unfactored.shapes.count() == whole.shapes.count());

  for (int size : {2, 3}) {
    INFO(size << " processes");
    std::vector<Partition> parts;
    std::vector<LocalBonds> locals;
    for (int rank = 0; rank < size; ++rank) {
      parts.push_back(slab_partition(p, unfactored.families, rank, size, "plate"));
      locals.push_back(local_bonds(p, unfactored, parts.back().local_ids(), parts.back().owned.size()));
    }
    std::vector<double> published(p.size(), 0.0), changes(static_cast<std::size_t>(size), 0.0);
    std::vector<int> iterations(static_cast<std::size_t>(size), 0);
    std::vector<std::string> failures(static_cast<std::size_t>(size));
    Barrier barrier(size);
    std::vector<std::thread> processes;
    for (int rank = 0; rank < size; ++rank)
      processes.emplace_back([&, rank] {
        const Partition& part = parts[static_cast<std::size_t>(rank)];
        LocalBonds& local = locals[static_cast<std::size_t>(rank)];
        const ScalarFactorExchange exchange{
            [&](std::vector<double>& values) {
              for (std::size_t l = 0; l < part.owned.size(); ++l) published[part.owned[l]] = values[l];
              barrier.wait();
              for (std::size_t g = 0; g < part.ghosts.size(); ++g)
                values[part.owned.size() + g] = published[part.ghosts[g]];
              barrier.wait();
            },
            [&](double value) {
              changes[static_cast<std::size_t>(rank)] = value;
              barrier.wait();
              const double largest = *std::max_element(changes.begin(), changes.end());
              barrier.wait();
              return largest;
            }};
        BondSetup& s = local.setup;
        try {
          iterations[static_cast<std::size_t>(rank)] =
              iterate_scalar_factors(local.particles, s.families, s.energy_weight, s.listed_intact, s.shapes,
                                     s.horizon, surface_correction_tolerance, s.lambda, &exchange);
        } catch (const std::exception& e) {
          failures[static_cast<std::size_t>(rank)] = e.what();
        }
      });
    for (auto& process : processes) process.join();
    for (int rank = 0; rank < size; ++rank) {
      INFO("process " << rank);
      const std::size_t r = static_cast<std::size_t>(rank);
      REQUIRE(failures[r].empty());
      // The same convergence test over all slabs: the whole plate's count.
      CHECK(iterations[r] == whole.lambda_iterations);
      const std::vector<std::uint32_t> ids = parts[r].local_ids();
      std::size_t differing = 0;
      for (std::size_t l = 0; l < ids.size(); ++l) differing += locals[r].setup.lambda[l] != whole.lambda[ids[l]] ? 1 : 0;
      CHECK(differing == 0);  // owned and ghost factors, bit for bit
    }
  }
}
