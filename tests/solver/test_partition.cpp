// The slabs of a run on several processes (solver/state/partition.hpp): every
// particle owned once, slabs of balanced directed bonds, ghosts exactly the
// neighbours owned elsewhere. No MPI needed: a partition is computed the same
// on every process from the particle file.
#include <catch2/catch.hpp>
#include <algorithm>
#include <cmath>
#include <condition_variable>
#include <functional>
#include <mutex>
#include <numeric>
#include <thread>
#include <type_traits>

#include "bond_setup.hpp"
#include "compact_families.hpp"
#include "families.hpp"
#include "loads.hpp"
#include "local_bonds.hpp"
#include "particle_band.hpp"
#include "partition.hpp"
#include "osb.hpp"
#include "pmb.hpp"
#include "scene.hpp"
#include "slab_band.hpp"
#include "state_surface_correction.hpp"
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

// Dual-horizon OSB with the lattice split on several processes builds no
// rows for the bonds the sweep computes, so its stable step (theory.md Secs.
// 5.4, 6.8) is summed from the local particles' bonds without their table:
// each process's bound over its owned rows is the whole table's over the
// same rows bit for bit, and the smallest over the processes is the
// one-process step. (The table's bound is the reference: the one-process
// run takes it, and tests/solver/test_dual_horizon_osb.cpp checks it.)
TEST_CASE("a process's dual-horizon OSB stable step from its local particles' bonds is the whole table's over its "
          "owned rows",
          "[partition][dual_horizon][osb]") {
  const ParticleSet p = test::half_refined_plate(40e-3, 10e-3, 1e-3, 3, 4);
  Scene scene = test::basic_scene();
  scene.model = ModelType::osb;
  scene.dual_horizon = true;
  const BondSetup setup = build_bond_setup(scene, p, compact_families(p), {});
  REQUIRE(setup.horizon_mode == HorizonMode::dual_horizon);
  const BondTable whole =
      variable_horizon_table<Osb>(p, setup, scene.material, HorizonMode::dual_horizon, false, nullptr);
  const double a = Osb::dilatation_coefficient(Osb::constants(scene.material, setup.horizon));
  const double density = scene.material.density;
  const double one_process = dual_horizon_state_stable_time_step(whole, a, density);
  REQUIRE(std::isfinite(one_process));
  // Every particle's row from every particle's bonds: the one-process run
  // with the lattice split sums its step so, bit for bit the table's.
  CHECK(dual_horizon_state_stable_time_step<Osb>(p, setup, scene.material, a, density) == one_process);
  const int size = 7;
  double smallest = INFINITY;
  for (int rank = 0; rank < size; ++rank) {
    INFO("process " << rank);
    const Partition part = slab_partition(p, setup.families, rank, size, "plate", GhostReach::bonds_both_ways);
    const std::vector<std::uint32_t> ids = part.local_ids();
    const std::vector<std::uint32_t> owned_rows(ids.begin(), ids.begin() + static_cast<std::ptrdiff_t>(part.owned.size()));
    std::vector<std::uint32_t> owners(ids);
    std::sort(owners.begin(), owners.end());
    REQUIRE(owners.size() < p.size());
    const double from_bonds =
        dual_horizon_state_stable_time_step<Osb>(p, setup, scene.material, a, density, &owned_rows, &owners);
    CHECK(from_bonds == dual_horizon_state_stable_time_step(whole, a, density, &owned_rows));
    smallest = std::min(smallest, from_bonds);
  }
  CHECK(smallest == one_process);
}

// A process builds the rows from the bonds its owned rows hold alone (an
// owned particle's own bonds and the bonds towards it: the force field's
// distributed_variable_horizon_rows), piece by piece, not from every bond of
// its band: the rows cut from such a table, or joined from the pieces, the
// entries' bond numbers (each bond's place in its owner's family) and the
// owned particles' row stiffness sums are the whole table's bit for bit.
// (The table of every bond held the band's bonds, its rows and the cut-out
// at once.)
TEST_CASE("a process's dual-horizon rows from the bonds with an owned end alone are the whole table's rows",
          "[partition][dual_horizon]") {
  const ParticleSet p = test::half_refined_plate(40e-3, 10e-3, 1e-3, 3, 4);
  Scene scene = test::basic_scene();
  scene.dual_horizon = true;
  scene.effects.damage = true;
  const BondSetup setup = build_bond_setup(scene, p, compact_families(p), {});
  REQUIRE(setup.horizon_mode == HorizonMode::dual_horizon);
  std::vector<std::uint8_t> whole_intact;
  std::vector<std::uint64_t> whole_entry_bond;
  const BondTable whole = variable_horizon_table<Pmb>(p, setup, scene.material, HorizonMode::dual_horizon, true,
                                                      &whole_intact, {}, &whole_entry_bond);
  const std::vector<double> whole_sums = dual_horizon_row_stiffness<Pmb>(p, setup, scene.material);
  const std::vector<std::uint64_t> starts = family_starts(setup.families);
  const int size = 7;
  for (int rank = 0; rank < size; ++rank) {
    INFO("process " << rank);
    const Partition part = slab_partition(p, setup.families, rank, size, "plate", GhostReach::bonds_both_ways);
    const std::vector<std::uint32_t> ids = part.local_ids();
    std::vector<std::uint8_t> owned(p.size(), 0);
    for (std::size_t l = 0; l < part.owned.size(); ++l) owned[ids[l]] = 1;
    const KeepBond keep = [&](std::uint32_t i, std::uint32_t j) { return owned[i] || owned[j]; };
    std::vector<OwnedBond> bonds;
    std::vector<std::uint64_t> number;
    for_each_owned_bond<Pmb>(p, setup, scene.material, HorizonMode::dual_horizon, keep,
                             [&](const OwnedBond& b, std::uint32_t place) {
                               bonds.push_back(b);
                               number.push_back(starts[b.owner] + place);
                             });
    CHECK(bonds.size() < setup.families.bond_count());
    std::vector<std::uint8_t> intact;
    std::vector<std::uint64_t> entry_bond;
    BondTable kept = variable_horizon_rows(p, bonds, HorizonMode::dual_horizon, true, &intact, false, &entry_bond);
    for (auto& e : entry_bond) e = number[e];
    const LocalRows from_kept = local_rows(std::move(kept), std::move(intact), std::move(entry_bond), ids,
                                           part.owned.size());
    const LocalRows from_whole = local_rows(whole, whole_intact, whole_entry_bond, ids, part.owned.size());
    const BondTable &a = from_kept.table, &b = from_whole.table;
    CHECK(a.offsets == b.offsets);
    CHECK(a.dual_begin == b.dual_begin);
    BondTable::for_each_entry_array([&, &a = a, &b = b](const char* name, auto member) {
      INFO(name);
      CHECK(a.*member == b.*member);
    });
    CHECK(from_kept.intact == from_whole.intact);
    CHECK(from_kept.entry_bond == from_whole.entry_bond);
    for (std::size_t l = 0; l < part.owned.size(); ++l) CHECK(a.family_area[l] == b.family_area[l]);
    const std::vector<double> sums = dual_horizon_row_stiffness<Pmb>(p, setup, scene.material, nullptr, nullptr, keep);
    for (std::size_t l = 0; l < part.owned.size(); ++l) CHECK(sums[ids[l]] == whole_sums[ids[l]]);

    // In 3 pieces of the owned rows, each from the bonds with an end among
    // its own particles, joined: the same rows again.
    const std::size_t owned_count = part.owned.size();
    std::vector<LocalRows> pieces;
    std::vector<std::size_t> first_rows;
    for (std::size_t k = 0; k < 3; ++k) {
      const std::size_t from = owned_count * k / 3, to = owned_count * (k + 1) / 3;
      std::fill(owned.begin(), owned.end(), std::uint8_t{0});
      for (std::size_t l = from; l < to; ++l) owned[ids[l]] = 1;
      std::vector<OwnedBond> piece_bonds;
      std::vector<std::uint64_t> piece_number;
      for_each_owned_bond<Pmb>(p, setup, scene.material, HorizonMode::dual_horizon, keep,
                               [&](const OwnedBond& b, std::uint32_t place) {
                                 piece_bonds.push_back(b);
                                 piece_number.push_back(starts[b.owner] + place);
                               });
      std::vector<std::uint8_t> piece_intact;
      std::vector<std::uint64_t> piece_entry_bond;
      BondTable piece = variable_horizon_rows(p, piece_bonds, HorizonMode::dual_horizon, true, &piece_intact, false,
                                              &piece_entry_bond);
      for (auto& e : piece_entry_bond) e = piece_number[e];
      pieces.push_back(local_rows(std::move(piece), std::move(piece_intact), std::move(piece_entry_bond), ids, to,
                                  from));
      first_rows.push_back(from);
    }
    const LocalRows joined = joined_rows(std::move(pieces), first_rows, owned_count);
    const BondTable& c = joined.table;
    CHECK(c.offsets == b.offsets);
    CHECK(c.dual_begin == b.dual_begin);
    BondTable::for_each_entry_array([&, &b = b](const char* name, auto member) {
      INFO(name);
      CHECK(c.*member == b.*member);
    });
    CHECK(joined.intact == from_whole.intact);
    CHECK(joined.entry_bond == from_whole.entry_bond);
    for (std::size_t l = 0; l < owned_count; ++l) CHECK(c.family_area[l] == b.family_area[l]);
  }
}

// Every array of a table, whichever a run holds (here all of them, state-based
// ones too), reaches a process's rows: cut from the whole table and joined
// from pieces, each entry array holds the owned rows' entries in order, each
// per-particle array the local particles' values (the lists a cut and a join
// take from BondTable::for_each_entry_array and for_each_particle_array).
TEST_CASE("a process's rows cut and joined from a table that holds every array keep each array's values",
          "[partition]") {
  // Four particles with 2, 1, 3 and 2 entries; every entry and particle value distinct.
  BondTable whole;
  whole.particle_count = 4;
  whole.offsets = {0, 2, 3, 6, 8};
  whole.dual_begin = {1, 3, 5, 7};
  whole.critical_stretch = 0.01;
  whole.neighbor = {1, 2, 0, 0, 1, 3, 2, 0};
  const auto fill = [](auto& v, std::size_t size, double first) {
    v.resize(size);
    for (std::size_t k = 0; k < size; ++k) v[k] = static_cast<std::decay_t<decltype(v[0])>>(first + k);
  };
  const auto is_neighbor = [](auto member) {
    if constexpr (std::is_same_v<decltype(member), decltype(&BondTable::neighbor)>)
      return member == &BondTable::neighbor;
    else
      return false;
  };
  double first = 10;
  BondTable::for_each_entry_array([&](const char*, auto member) {
    if (!is_neighbor(member)) fill(whole.*member, 8, first += 10);
  });
  BondTable::for_each_particle_array([&](const char*, auto member) { fill(whole.*member, 4, first += 10); });
  const std::vector<std::uint8_t> intact = {1, 0, 1, 1, 0, 1, 1, 1};
  const std::vector<std::uint64_t> entry_bond = {7, 6, 5, 4, 3, 2, 1, 0};
  // Particles 2 and 0 owned, in that order; 1 and 3 their ghosts.
  const std::vector<std::uint32_t> ids = {2, 0, 1, 3};
  const std::vector<std::uint32_t> local_of = {1, 2, 0, 3};
  const std::vector<std::uint64_t> rows = {3, 4, 5, 0, 1};  // the whole table's entries of rows 2 and 0
  const auto expect = [&](const LocalRows& r) {
    const BondTable& t = r.table;
    CHECK(t.offsets == std::vector<std::uint64_t>{0, 3, 5, 5, 5});
    CHECK(t.dual_begin == std::vector<std::uint64_t>{2, 4, 5, 5});
    CHECK(t.critical_stretch == 0.01);
    BondTable::for_each_entry_array([&](const char* name, auto member) {
      INFO(name);
      REQUIRE((t.*member).size() == rows.size());
      for (std::size_t e = 0; e < rows.size(); ++e)
        if (is_neighbor(member)) CHECK(t.neighbor[e] == local_of[whole.neighbor[rows[e]]]);
        else CHECK((t.*member)[e] == (whole.*member)[rows[e]]);
    });
    BondTable::for_each_particle_array([&](const char* name, auto member) {
      INFO(name);
      REQUIRE((t.*member).size() == ids.size());
      for (std::size_t l = 0; l < ids.size(); ++l) CHECK((t.*member)[l] == (whole.*member)[ids[l]]);
    });
    for (std::size_t e = 0; e < rows.size(); ++e) {
      CHECK(r.intact[e] == intact[rows[e]]);
      CHECK(r.entry_bond[e] == entry_bond[rows[e]]);
    }
  };
  expect(local_rows(whole, intact, entry_bond, ids, 2));
  std::vector<LocalRows> pieces;
  pieces.push_back(local_rows(whole, intact, entry_bond, ids, 1, 0));
  pieces.push_back(local_rows(whole, intact, entry_bond, ids, 2, 1));
  expect(joined_rows(std::move(pieces), {0, 1}, 2));
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

namespace {

// The surface correction's coupled factors (`iterate`: a process's
// iteration on its local set-up with the exchange, returning its
// iterations) iterated on 2 and 3 slabs of `p`, each slab in a thread of its
// own exchanging through shared memory as the processes do through MPI,
// from `unfactored` (the set-up without them): every process stops at the
// whole plate's iteration count, and `differing` (a process's local set-up
// against the whole plate's, at its local particles' ids) counts no factor
// that differs.
using SlabIteration = std::function<int(LocalBonds&, const ScalarFactorExchange&)>;
using FactorDifference = std::function<std::size_t(const BondSetup&, const std::vector<std::uint32_t>&)>;
void check_factors_on_slabs(const ParticleSet& p, const BondSetup& unfactored, int whole_iterations,
                            const SlabIteration& iterate, const FactorDifference& differing) {
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
        try {
          iterations[static_cast<std::size_t>(rank)] = iterate(local, exchange);
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
      CHECK(iterations[r] == whole_iterations);
      CHECK(differing(locals[r].setup, parts[r].local_ids()) == 0);  // owned and ghost factors, bit for bit
    }
  }
}

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
  without.coupled_factors = false;
  const BondSetup unfactored = build_bond_setup(scene, p, compact_families(p), without);
  CHECK(unfactored.lambda_iterations == 0);
  CHECK(std::all_of(unfactored.lambda.begin(), unfactored.lambda.end(), [](double l) { return l == 1.0; }));
  REQUIRE(unfactored.shapes.count() == whole.shapes.count());
  check_factors_on_slabs(
      p, unfactored, whole.lambda_iterations,
      [](LocalBonds& local, const ScalarFactorExchange& exchange) {
        BondSetup& s = local.setup;
        return iterate_scalar_factors(local.particles, s.families, s.energy_weight, s.listed_intact, s.shapes,
                                      s.horizon, surface_correction_tolerance, s.lambda, &exchange);
      },
      [&](const BondSetup& local, const std::vector<std::uint32_t>& ids) {
        std::size_t differing = 0;
        for (std::size_t l = 0; l < ids.size(); ++l) differing += local.lambda[l] != whole.lambda[ids[l]] ? 1 : 0;
        return differing;
      });
}

TEST_CASE("the state-based dilatation factors iterated on slabs equal the whole plate's bit for bit",
          "[partition][surface_correction][osb]") {
  // The plate above with OSB: its dilatation factors d_i, solved together
  // by damped block Jacobi (theory.md Sec. 5.7), couple the slabs along the
  // edges and crack faces; its distortion factors come from each family alone.
  const double dx = 1e-3;
  const ParticleSet p = make_rectangle_lattice(60 * dx, 20 * dx, dx, 3 * dx, Quadrature::analytic);
  Scene scene = test::basic_scene();
  scene.model = ModelType::osb;
  scene.material.poisson_ratio = 0.3;
  scene.effects.surface_correction = true;
  scene.precracks = {PrecrackSpec{{0.0, 10.01 * dx}, {31.3 * dx, 10.01 * dx}}};
  const BondSetup whole = build_bond_setup(scene, p, compact_families(p), {});
  REQUIRE(whole.lambda_iterations > 5);
  const DirectionalShapes& d = whole.dilatation_shapes;
  REQUIRE(d.count() > 100);
  std::size_t corrected = 0;
  for (const Harmonics& c : d.coefficients) corrected += std::fabs(c[1]) + std::fabs(c[2]) > 1e-3 ? 1 : 0;
  REQUIRE(corrected > 50);  // the factors are not all 0
  SetupOptions without;
  without.coupled_factors = false;
  const BondSetup unfactored = build_bond_setup(scene, p, compact_families(p), without);
  CHECK(unfactored.lambda_iterations == 0);
  // The distortion factors are made without the coupled ones; the dilatation rows wait at 0.
  CHECK(unfactored.lambda == whole.lambda);
  REQUIRE(unfactored.dilatation_shapes.row == d.row);
  CHECK(std::all_of(unfactored.dilatation_shapes.coefficients.begin(), unfactored.dilatation_shapes.coefficients.end(),
                    [](const Harmonics& c) { return c == Harmonics{}; }));
  check_factors_on_slabs(
      p, unfactored, whole.lambda_iterations,
      [](LocalBonds& local, const ScalarFactorExchange& exchange) {
        BondSetup& s = local.setup;
        return iterate_dilatation_factors(local.particles, s.families, s.energy_weight, s.listed_intact,
                                          surface_correction_tolerance, s.dilatation_shapes, &exchange);
      },
      [&](const BondSetup& local, const std::vector<std::uint32_t>& ids) {
        std::size_t differing = 0;
        for (std::size_t l = 0; l < ids.size(); ++l) {
          differing += local.dilatation_shapes.has(static_cast<std::uint32_t>(l)) != d.has(ids[l]) ? 1 : 0;
          if (d.has(ids[l]) && local.dilatation_shapes.has(static_cast<std::uint32_t>(l)))
            differing += local.dilatation_shapes.coefficients[local.dilatation_shapes.row[l]] !=
                                 d.coefficients[d.row[ids[l]]]
                             ? 1
                             : 0;
        }
        return differing;
      });
}

TEST_CASE("a process reads its slab's band of the particle file: the cuts from the family lengths, whole families "
          "inside the band",
          "[partition][band]") {
  // C3-A's plate with its pores (pd-mesh's own file: stencil and listed
  // families, boundary sets), cut into 3 slabs along x.
  const std::string folder = test::fresh_folder("partition_band");
  const std::string path = test::pd_mesh(folder, "c3a_pores.geo", "--spacing 0.25mm --horizon 0.875mm");
  const ParticleSet whole = read_particle_file(path);
  const Families families = compact_families(whole);
  // The lengths alone, as the streaming reader leaves them (no family kept).
  const ParticleSet lengths_only =
      read_particle_file(path, [](const ParticleSet&, std::uint32_t, const std::uint32_t*, const double*,
                                  std::size_t) {});
  REQUIRE(lengths_only.neighbors.empty());
  const double reach = longest_possible_bond(lengths_only);
  // The bound holds and is not loose by more than a cell.
  double longest = 0;
  for (std::uint32_t i = 0; i < whole.size(); ++i)
    for (auto b = whole.family_offsets[i]; b < whole.family_offsets[i + 1]; ++b)
      longest = std::max(longest, std::hypot(whole.x[whole.neighbors[b]] - whole.x[i],
                                             whole.y[whole.neighbors[b]] - whole.y[i]));
  CHECK(longest <= reach);
  CHECK(longest > reach - whole.spacing);
  const int size = 3;
  const SlabCuts slabs = slab_cuts(lengths_only, file_family_lengths(lengths_only), size, path);
  REQUIRE(slabs.axis == 0);
  for (int rank = 0; rank < size; ++rank) {
    INFO("process " << rank);
    const Partition part = slab_partition(whole, families, rank, size, path);
    CHECK(slabs.cuts == part.cuts);
    for (auto i : part.owned) CHECK(slabs.slab_of(whole.x[i]) == rank);

    // The slab widened by three bond reaches (docs/solver.md, "Set-up").
    const double lo = rank > 0 ? slabs.cuts[rank - 1] - 3 * reach : whole.xmin;
    const double hi = rank < size - 1 ? slabs.cuts[rank] + 3 * reach : whole.xmax;
    const ParticleBand band = read_particle_band(path, 0, lo, hi);
    CHECK(band.whole_count == whole.size());
    CHECK(band.whole_bond_count == whole.bond_count());
    std::vector<std::uint32_t> expected_ids;
    for (std::uint32_t i = 0; i < whole.size(); ++i)
      if (whole.x[i] >= lo && whole.x[i] <= hi) expected_ids.push_back(i);
    REQUIRE(band.global_id == expected_ids);
    const ParticleSet& q = band.particles;
    const Families& f = band.families;
    REQUIRE(q.size() == expected_ids.size());
    REQUIRE(f.particle_count == q.size());
    std::size_t complete = 0, incomplete = 0, within = 0, differing = 0;
    for (std::uint32_t l = 0; l < q.size(); ++l) {
      const std::uint32_t i = band.global_id[l];
      REQUIRE(q.x[l] == whole.x[i]);
      REQUIRE(q.y[l] == whole.y[i]);
      REQUIRE(q.volume[l] == whole.volume[i]);
      REQUIRE(q.horizon[l] == whole.horizon[i]);
      REQUIRE(q.region[l] == whole.region[i]);
      // The family in the file's order, neighbours outside the band left
      // out; the partial volumes of the whole file's compact families (a
      // stencil particle's are its level's stencil's).
      std::vector<std::uint32_t> expected_family, family;
      std::vector<double> expected_phi, phi;
      families.for_each_bond(i, [&](const BondRef& b) {
        if (whole.x[b.neighbor] < lo || whole.x[b.neighbor] > hi) return;
        expected_family.push_back(b.neighbor);
        expected_phi.push_back(b.partial_volume);
      });
      f.for_each_bond(l, [&](const BondRef& b) {
        family.push_back(band.global_id[b.neighbor]);
        phi.push_back(b.partial_volume);
      });
      differing += family != expected_family || phi != expected_phi;
      const bool is_whole = family.size() == whole.family_offsets[i + 1] - whole.family_offsets[i];
      CHECK(static_cast<bool>(band.family_complete[l]) == is_whole);
      if (is_whole) CHECK(f.on_stencil[l] == families.on_stencil[i]);
      (is_whole ? complete : incomplete) += 1;
      // More than a bond's reach inside the band: the whole family.
      if (whole.x[i] - reach >= lo && whole.x[i] + reach <= hi) {
        ++within;
        CHECK(band.family_complete[l] == 1);
      }
    }
    CHECK(differing == 0);
    CHECK(within > 0);
    CHECK(complete > 0);
    CHECK(incomplete > 0);  // near the band's inner edges
    // The owned particles, their ghosts and the ghosts' neighbours keep whole families.
    std::vector<std::uint32_t> local_of(whole.size(), Families::none);
    for (std::uint32_t l = 0; l < q.size(); ++l) local_of[band.global_id[l]] = l;
    std::size_t cut_short = 0;
    for (const auto& ids : {part.owned, part.ghosts})
      for (auto i : ids) {
        REQUIRE(local_of[i] != Families::none);
        cut_short += band.family_complete[local_of[i]] == 0;
        families.for_each_bond(i, [&](const BondRef& b) {
          REQUIRE(local_of[b.neighbor] != Families::none);
          cut_short += band.family_complete[local_of[b.neighbor]] == 0;
        });
      }
    CHECK(cut_short == 0);
    // The boundary sets, restricted to the band, in local numbering.
    REQUIRE(q.sets.size() == whole.sets.size());
    for (std::size_t s = 0; s < whole.sets.size(); ++s) {
      std::vector<std::uint32_t> expected_set, set;
      for (auto i : whole.sets[s].particles)
        if (local_of[i] != Families::none) expected_set.push_back(i);
      for (auto l : q.sets[s].particles) set.push_back(band.global_id[l]);
      CHECK(q.sets[s].name == whole.sets[s].name);
      CHECK(set == expected_set);
    }
  }
  CHECK_THROWS_WITH(read_particle_band(path, 0, 1.0, 0.0), Catch::Contains(path));
}

TEST_CASE("a bond-based set-up made on a slab's band equals the whole plate's for the slab's particles and ghosts",
          "[partition][band][surface_correction]") {
  // C3-A's plate with its pores, PMB with the surface correction (its scalar
  // factors left to the slabs' iteration, as a distributed run does) and a
  // pre-crack that crosses both cuts: weights, cuts, directional shapes and
  // the stencil/list choice of the band's set-up against the whole plate's.
  const std::string folder = test::fresh_folder("partition_band_setup");
  const std::string path = test::pd_mesh(folder, "c3a_pores.geo", "--spacing 0.25mm --horizon 0.875mm");
  const ParticleSet whole = read_particle_file(path);
  Scene scene = test::basic_scene();
  scene.particle_file = path;
  scene.effects.surface_correction = true;
  scene.precracks = {PrecrackSpec{{0.0, 0.0125}, {0.04, 0.0125}}};
  SetupOptions options;
  options.coupled_factors = false;
  const BondSetup whole_setup = build_bond_setup(scene, whole, compact_families(whole), options);
  REQUIRE(whole_setup.precrack_cut > 100);
  REQUIRE(whole_setup.shapes.count() > 100);
  const double reach = longest_possible_bond(whole);
  const int size = 3;
  for (int rank = 0; rank < size; ++rank) {
    INFO("process " << rank);
    const Partition part = slab_partition(whole, whole_setup.families, rank, size, path);
    const double lo = rank > 0 ? part.cuts[rank - 1] - 3 * reach : whole.xmin;
    const double hi = rank < size - 1 ? part.cuts[rank] + 3 * reach : whole.xmax;
    const ParticleBand band = read_particle_band(path, 0, lo, hi);
    const BondSetup band_setup = build_bond_setup(scene, band.particles, band.families, options);
    std::vector<std::uint32_t> local_of(whole.size(), Families::none);
    for (std::uint32_t l = 0; l < band.global_id.size(); ++l) local_of[band.global_id[l]] = l;
    const Families& wf = whole_setup.families;
    const Families& bf = band_setup.families;
    // The same lattices and stencils.
    REQUIRE(bf.levels.size() == wf.levels.size());
    for (std::size_t v = 0; v < wf.levels.size(); ++v) {
      CHECK(bf.levels[v].di == wf.levels[v].di);
      CHECK(bf.levels[v].dj == wf.levels[v].dj);
      CHECK(bf.levels[v].phi == wf.levels[v].phi);
    }
    std::size_t bonds = 0, differing = 0;
    const auto compare = [&](std::uint32_t i, bool with_bonds) {
      const std::uint32_t l = local_of[i];
      REQUIRE(l != Families::none);
      CHECK(bf.on_stencil[l] == wf.on_stencil[i]);
      CHECK(bf.cell[l] == wf.cell[i]);
      CHECK(band_setup.shapes.has(l) == whole_setup.shapes.has(i));
      if (whole_setup.shapes.has(i) && band_setup.shapes.has(l))
        differing += band_setup.shapes.coefficients[band_setup.shapes.row[l]] !=
                     whole_setup.shapes.coefficients[whole_setup.shapes.row[i]];
      if (!with_bonds) return;
      std::vector<std::uint32_t> wn, bn;
      std::vector<double> wphi, bphi, wweight, bweight;
      std::vector<int> wintact, bintact;
      wf.for_each_bond(i, [&](const BondRef& b) {
        wn.push_back(b.neighbor);
        wphi.push_back(b.partial_volume);
        wweight.push_back(whole_setup.energy_weight(b));
        wintact.push_back(b.on_stencil || whole_setup.listed_intact[b.index]);
      });
      bf.for_each_bond(l, [&](const BondRef& b) {
        bn.push_back(band.global_id[b.neighbor]);
        bphi.push_back(b.partial_volume);
        bweight.push_back(band_setup.energy_weight(b));
        bintact.push_back(b.on_stencil || band_setup.listed_intact[b.index]);
      });
      CHECK(bn == wn);
      CHECK(bphi == wphi);
      CHECK(bweight == wweight);  // bit for bit
      CHECK(bintact == wintact);
      bonds += wn.size();
    };
    // Owned particles: their whole set-up; ghosts: what their owned
    // neighbours' bonds read of them (cell, stencil, directional shape).
    for (auto i : part.owned) compare(i, true);
    for (auto g : part.ghosts) compare(g, false);
    CHECK(differing == 0);
    CHECK(bonds == part.owned_bonds);
  }
}

TEST_CASE("a process's slab band gives the whole plate's partition, family offsets, loads and stop region",
          "[partition][band]") {
  // C3-A's plate with its pores in 3 slabs; the reference is the whole file
  // read as one process reads it (slab_partition, resolve_loads, resolve_region).
  const std::string folder = test::fresh_folder("partition_slab_band");
  const std::string path = test::pd_mesh(folder, "c3a_pores.geo", "--spacing 0.25mm --horizon 0.875mm");
  const std::string scene_text =
      "particles = \"" + path + "\"\n"
      "[material]\nyoungs_modulus = 3.24e9\ndensity = 1190\nfracture_energy = 200\npoisson_ratio = 0.35\n"
      "[model]\ntype = \"pmb\"\n[effects]\ndamage = true\nsurface_correction = true\n"
      "[time]\nstep = \"auto\"\nend = 1e-6\n"
      "[[loads]]\nset = \"top\"\ntype = \"velocity\"\ny = 1.0\n"
      "[[loads]]\nnearest = [0.05, 0.0125]\ntype = \"fixed\"\n"
      "[[loads]]\nset = \"left\"\ntype = \"traction\"\nx = -1e5\n"
      "[[loads]]\nbox = [0.02, 0.0, 0.03, 0.001]\ntype = \"velocity\"\n"
      "x = { from = [0.02, 0], to = [0.03, 0], values = [0.5, 1.5] }\n"
      "[stop]\nbox = [0.006, 0.010, 0.012, 0.015]\n";
  const Scene scene = parse_scene(scene_text, folder + "/scene.toml");
  const ParticleSet whole = read_particle_file(path);
  const Families families = compact_families(whole);
  const std::vector<ResolvedLoad> whole_loads = resolve_loads(scene, whole);
  const std::vector<std::uint32_t> whole_stop = resolve_region(scene.stop.region, whole, scene.path, "stop");
  REQUIRE(distributed_setup_refusal(scene).empty());
  const int size = 3;
  std::size_t owned_total = 0;
  for (int rank = 0; rank < size; ++rank) {
    INFO("process " << rank);
    const Partition expected = slab_partition(whole, families, rank, size, path);
    const std::optional<SlabBand> band = read_slab_band(scene, rank, size);
    const Partition& part = band->partition;
    CHECK(part.rank == rank);
    CHECK(part.size == size);
    CHECK(part.axis == expected.axis);
    CHECK(part.cuts == expected.cuts);
    CHECK(part.owned == expected.owned);
    CHECK(part.ghosts == expected.ghosts);
    CHECK(part.ghost_owner == expected.ghost_owner);
    CHECK(part.owned_bonds == expected.owned_bonds);
    CHECK(part.whole_count == whole.size());
    owned_total += part.owned.size();
    // Less than the plate, more than the slab and its ghosts.
    CHECK(band->particles.size() < whole.size());
    CHECK(band->particles.size() > part.local_count());
    const WholePlateFacts& w = band->whole;
    CHECK(w.particle_count == whole.size());
    CHECK(w.bond_count == whole.family_offsets.back());
    REQUIRE(w.owned_family_start.size() == part.owned.size());
    REQUIRE(w.owned_family_length.size() == part.owned.size());
    std::size_t differing = 0;
    for (std::size_t k = 0; k < part.owned.size(); ++k) {
      const std::uint32_t i = part.owned[k];
      differing += w.owned_family_start[k] != whole.family_offsets[i] ||
                   w.owned_family_length[k] != whole.family_offsets[i + 1] - whole.family_offsets[i];
    }
    CHECK(differing == 0);
    // Each local particle's place in the band: the same particle.
    const std::vector<std::uint32_t> local = part.local_ids();
    REQUIRE(w.band_index.size() == local.size());
    for (std::size_t l = 0; l < local.size(); ++l) {
      differing += band->particles.x[w.band_index[l]] != whole.x[local[l]] ||
                   band->particles.y[w.band_index[l]] != whole.y[local[l]] ||
                   band->families.family_size(w.band_index[l]) != families.family_size(local[l]);
    }
    CHECK(differing == 0);
    // The loads and the stop region of the whole plate, in global ids.
    REQUIRE(w.loads.size() == whole_loads.size());
    for (std::size_t l = 0; l < whole_loads.size(); ++l) {
      CHECK(w.loads[l].particles == whole_loads[l].particles);
      CHECK(w.loads[l].value_x == whole_loads[l].value_x);
      CHECK(w.loads[l].value_y == whole_loads[l].value_y);
      CHECK(w.loads[l].edge_length == whole_loads[l].edge_length);
      CHECK(w.loads[l].body_force_x == whole_loads[l].body_force_x);
    }
    CHECK(band->stop_region == whole_stop);
  }
  CHECK(owned_total == whole.size());

  // The state-based model with or without the surface correction takes the
  // band (before 7 December 2026 it made the whole plate's set-up:
  // "model.type = \"osb\": its ... stable time step read(s) whole families
  // of neighbours"), and so do dual horizons and a file whose horizons
  // differ (before this day: "model.dual_horizon = true: the rows reach up
  // to the largest horizon", and "the particle file's horizons differ").
  Scene osb = scene;
  osb.model = ModelType::osb;
  for (const bool correction : {true, false}) {
    osb.effects.surface_correction = correction;
    CHECK(distributed_setup_refusal(osb).empty());
  }
  Scene dual = scene;
  dual.dual_horizon = true;
  CHECK(distributed_setup_refusal(dual).empty());
}

TEST_CASE("a slab's band of a file whose horizons differ: the whole plate's partition, with dual horizons the "
          "ghosts owning bonds towards the slab, whole families and the file's family offsets",
          "[partition][band][dual_horizon]") {
  // C3-A at dx = 0.625 mm, delta = 2.5 mm, its boxes round the pores at
  // dx / 2 with horizons of 1.25 mm: the ghosts a dual-horizon row reaches
  // (owners of bonds towards the slab, up to the largest horizon away) are
  // more than an ordinary row's.
  const std::string folder = test::fresh_folder("partition_slab_band_varying");
  const std::string path =
      test::pd_mesh(folder, "c3a_pores.geo", "--spacing 0.625mm --horizon 2.5mm --box-spacing 0.3125mm");
  const ParticleSet whole = read_particle_file(path);
  const Families families = compact_families(whole);
  Scene scene = parse_scene("particles = \"" + path +
                                "\"\n[material]\nyoungs_modulus = 3.24e9\ndensity = 1190\nfracture_energy = 200\n"
                                "[effects]\ndamage = true\nsurface_correction = false\n[time]\nstep = \"auto\"\n"
                                "end = 1e-6\n[[loads]]\nset = \"top\"\ntype = \"velocity\"\ny = 1.0\n",
                            folder + "/scene.toml");
  for (const bool dual : {true, false}) {
    INFO("model.dual_horizon = " << dual);
    scene.dual_horizon = dual;
    REQUIRE(distributed_setup_refusal(scene).empty());
    const GhostReach reach = dual ? GhostReach::bonds_both_ways : GhostReach::own_bonds;
    const int size = 3;
    std::size_t ghosts_both_ways = 0, ghosts_own_bonds = 0;
    for (int rank = 0; rank < size; ++rank) {
      INFO("process " << rank);
      const Partition expected = slab_partition(whole, families, rank, size, path, reach);
      const SlabBand band = read_slab_band(scene, rank, size);
      const Partition& part = band.partition;
      CHECK(part.owned == expected.owned);
      CHECK(part.ghosts == expected.ghosts);
      CHECK(part.ghost_owner == expected.ghost_owner);
      ghosts_both_ways += part.ghosts.size();
      ghosts_own_bonds += slab_partition(whole, families, rank, size, path).ghosts.size();
      const WholePlateFacts& w = band.whole;
      CHECK(w.horizons.mode == (dual ? HorizonMode::dual_horizon : HorizonMode::ordinary_variable));
      CHECK(w.horizons.horizon == largest_horizon(whole));
      CHECK(band.particles.size() < whole.size());
      // Every local particle (a ghost too) with its whole family, and where it starts in the file.
      REQUIRE(w.band_family_start.size() == band.particles.size());
      const std::vector<std::uint32_t> local = part.local_ids();
      std::size_t differing = 0;
      for (std::size_t l = 0; l < local.size(); ++l)
        differing += band.families.family_size(w.band_index[l]) != families.family_size(local[l]) ||
                     w.band_family_start[w.band_index[l]] != whole.family_offsets[local[l]];
      CHECK(differing == 0);
    }
    // Dual horizons reach further ghosts than own bonds do (the boxes' short horizons meet the squares' long ones).
    if (dual) CHECK(ghosts_both_ways > ghosts_own_bonds);
  }
}
