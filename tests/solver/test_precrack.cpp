// Pre-crack rule (precrack.hpp): a bond is cut when its particles lie on
// different sides of the crack line and the crack segment reaches the bond;
// a particle on the line counts as lying on the left of from -> to.
#include <catch2/catch.hpp>

#include <algorithm>

#include "lattice.hpp"
#include "precrack.hpp"
#include "bond_setup.hpp"
#include "simulation.hpp"
#include "test_support.hpp"

using namespace pd::solver;

TEST_CASE("bonds crossing a crack segment are cut, others are not", "[precrack]") {
  const PrecrackSpec crack{{0.0, 1.0}, {2.0, 1.0}};  // runs in +x along y = 1: "left" is above
  // Strictly crossing.
  CHECK(bond_crosses_crack({1.0, 0.5}, {1.2, 1.5}, crack));
  CHECK(bond_crosses_crack({1.2, 1.5}, {1.0, 0.5}, crack));
  // Both on one side, or parallel above.
  CHECK_FALSE(bond_crosses_crack({1.0, 0.5}, {1.5, 0.9}, crack));
  CHECK_FALSE(bond_crosses_crack({1.0, 1.5}, {1.5, 1.1}, crack));
  // Beyond the crack tip.
  CHECK_FALSE(bond_crosses_crack({2.1, 0.5}, {2.1, 1.5}, crack));
  CHECK_FALSE(bond_crosses_crack({-0.1, 0.5}, {-0.2, 1.5}, crack));
  // The tip lying exactly on the bond cuts it (closed crack segment).
  CHECK(bond_crosses_crack({2.0, 0.5}, {2.0, 1.5}, crack));
  // A particle on the line counts as above: its bonds downwards are cut, upwards and along the line are not.
  CHECK(bond_crosses_crack({1.0, 1.0}, {1.0, 0.8}, crack));
  CHECK(bond_crosses_crack({1.0, 0.8}, {1.0, 1.0}, crack));
  CHECK_FALSE(bond_crosses_crack({1.0, 1.0}, {1.0, 1.2}, crack));
  CHECK_FALSE(bond_crosses_crack({1.0, 1.0}, {1.5, 1.0}, crack));
  // Reversing the crack direction moves on-line particles to the other side.
  const PrecrackSpec reversed{{2.0, 1.0}, {0.0, 1.0}};
  CHECK_FALSE(bond_crosses_crack({1.0, 1.0}, {1.0, 0.8}, reversed));
  CHECK(bond_crosses_crack({1.0, 1.0}, {1.0, 1.2}, reversed));
}

TEST_CASE("a pre-crack through a row of particles cuts both directions of each bond", "[precrack]") {
  // 11 rows: the middle row's centres lie exactly on y = 5.5 dx.
  const double dx = 1e-4;
  const auto p = pd::make_rectangle_lattice(20 * dx, 11 * dx, dx, 3 * dx, pd::Quadrature::analytic);
  auto scene = test::basic_scene();
  scene.effects.damage = true;
  scene.precracks = {{{0.0, 5.5 * dx}, {8 * dx, 5.5 * dx}}};
  Simulation sim(scene, p);
  // The run's bonds as a table: the cut ones have state 0.
  const auto run_bonds = build_bond_setup(scene, p, compact_families(p), {});
  std::vector<std::uint8_t> intact;
  const auto model = Pmb::constants(scene.material, run_bonds.horizon);
  const auto bonds = bond_table(p, run_bonds, bond_constants_of<Pmb>(p, run_bonds, model), model.critical_stretch, true, &intact);
  const auto cut = static_cast<std::size_t>(std::count(intact.begin(), intact.end(), 0));
  CHECK(cut == sim.precrack_bonds_cut());
  CHECK(cut == run_bonds.precrack_cut);
  CHECK(cut > 0);
  CHECK(cut % 2 == 0);
  for (std::size_t i = 0; i < p.size(); ++i)
    for (auto b = bonds.offsets[i]; b < bonds.offsets[i + 1]; ++b) {
      const auto j = bonds.neighbor[b];
      for (auto r = bonds.offsets[j]; r < bonds.offsets[j + 1]; ++r)
        if (bonds.neighbor[r] == i) CHECK(intact[b] == intact[r]);
      // No bond between two particles at or above the line is cut, nor one right of the tip.
      if (p.y[i] >= 5.5 * dx - 1e-12 && p.y[j] >= 5.5 * dx - 1e-12) CHECK(intact[b] == 1);
      if (p.x[i] > 8 * dx && p.x[j] > 8 * dx) CHECK(intact[b] == 1);
    }
  // The cut bonds count as broken: particles along the crack are damaged, far ones are not.
  const auto d = sim.damage();
  double on_line = 0, far = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (std::fabs(p.y[i] - 5.5 * dx) < 1e-12 && p.x[i] < 6 * dx) on_line = std::max(on_line, d[i]);
    if (p.x[i] > 12 * dx) far = std::max(far, d[i]);
  }
  CHECK(on_line > 0.2);
  CHECK(far == 0);
  CHECK(sim.broken_bond_count() == cut);
}
