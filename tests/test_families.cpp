// Families and partial-volume factors on a uniform lattice.
// Reference: for a particle whose disk lies inside the body, the exact
// neighbourhood area is pi delta^2 (docs/theory.md Sec. 2); the particle's own
// cell is part of the disk but not of its family, so the family sum is
// pi delta^2 - V_i.
#include <catch2/catch.hpp>
#include <algorithm>
#include <cmath>
#include <sstream>

#include "families.hpp"
#include "lattice.hpp"

namespace {
struct SumStats {
  double max_relative_error = 0;
  int interior = 0;
};

SumStats interior_area_error(const pd::ParticleSet& p, double delta) {
  SumStats s;
  for (std::size_t i = 0; i < p.size(); ++i) {
    const double margin = delta + p.spacing;
    if (p.x[i] < p.xmin + margin || p.x[i] > p.xmax - margin || p.y[i] < p.ymin + margin ||
        p.y[i] > p.ymax - margin)
      continue;
    double sum = p.volume[i];
    for (auto k = p.family_offsets[i]; k < p.family_offsets[i + 1]; ++k)
      sum += p.partial_volume[k] * p.volume[p.neighbors[k]];
    const double exact = M_PI * delta * delta;
    s.max_relative_error = std::max(s.max_relative_error, std::fabs(sum - exact) / exact);
    ++s.interior;
  }
  return s;
}
}  // namespace

TEST_CASE("analytic partial volumes sum to pi delta^2 inside the body", "[families]") {
  for (double m : {3.0, 4.0, 3.3}) {
    const double dx = 1e-4, delta = m * dx;
    const auto p = pd::make_rectangle_lattice(30 * dx, 30 * dx, dx, delta, pd::Quadrature::analytic);
    const auto analytic = interior_area_error(p, delta);
    const auto hhb = interior_area_error(
        pd::make_rectangle_lattice(30 * dx, 30 * dx, dx, delta, pd::Quadrature::hhb), delta);
    INFO("m = " << m << ": analytic max rel. error " << analytic.max_relative_error << ", HHB "
                << hhb.max_relative_error << " over " << analytic.interior << " particles");
    REQUIRE(analytic.interior > 100);
    CHECK(analytic.max_relative_error < 1e-12);
    // HHB is only approximate: it must be worse than round-off, yet within a few percent.
    CHECK(hhb.max_relative_error > 1e-6);
    CHECK(hhb.max_relative_error < 0.05);
  }
}

TEST_CASE("families are symmetric in membership and sorted", "[families]") {
  const double dx = 1e-4;
  const auto p = pd::make_rectangle_lattice(12 * dx, 10 * dx, dx, 3 * dx, pd::Quadrature::analytic);
  for (std::size_t i = 0; i < p.size(); ++i)
    for (auto k = p.family_offsets[i]; k < p.family_offsets[i + 1]; ++k) {
      const auto j = p.neighbors[k];
      if (k > p.family_offsets[i]) CHECK(p.neighbors[k - 1] < j);
      // Equal horizons and congruent cells: i in family of j too, with the same factor.
      bool found = false;
      for (auto l = p.family_offsets[j]; l < p.family_offsets[j + 1]; ++l)
        if (p.neighbors[l] == i) found = std::fabs(p.partial_volume[l] - p.partial_volume[k]) < 1e-14;
      CHECK(found);
    }
  // Boundary sets: 3 columns of 10 particles within one horizon of the left edge.
  REQUIRE(p.find_set("left") != nullptr);
  CHECK(p.find_set("left")->particles.size() == 30);
}

TEST_CASE("the family of a particle not in the set is built the same way", "[families]") {
  // A refinement child: a point at the centre of a quarter of a square, with
  // half the horizon. Reference: the exact neighbourhood area pi delta^2 of a
  // point whose disk lies inside the body (docs/theory.md Sec. 2); the point
  // has no cell of its own in the set, so its family alone must sum to it.
  const double dx = 1e-4, delta = 3 * dx;
  const auto p = pd::make_rectangle_lattice(30 * dx, 30 * dx, dx, delta, pd::Quadrature::analytic);
  const pd::FamilyBuilder builder(p, pd::Quadrature::analytic);
  std::vector<std::uint32_t> neighbors, candidates;
  std::vector<double> factors;

  // An existing particle gets its own family back.
  const std::uint32_t i = 15 * 30 + 15;
  builder.family({p.x[i], p.y[i]}, p.horizon[i], i, neighbors, factors, candidates);
  const std::vector<std::uint32_t> stored(p.neighbors.begin() + static_cast<std::ptrdiff_t>(p.family_offsets[i]),
                                          p.neighbors.begin() + static_cast<std::ptrdiff_t>(p.family_offsets[i + 1]));
  CHECK(neighbors == stored);

  const pd::Vec2 child{p.x[i] + 0.25 * dx, p.y[i] - 0.25 * dx};
  const double child_horizon = 0.5 * delta;
  builder.family(child, child_horizon, pd::FamilyBuilder::none, neighbors, factors, candidates);
  double area = 0;
  for (std::size_t k = 0; k < neighbors.size(); ++k) area += factors[k] * p.volume[neighbors[k]];
  CHECK(area == Approx(M_PI * child_horizon * child_horizon).epsilon(1e-12));
  // The parent's own cell holds the child: it is in the child's family.
  CHECK(std::find(neighbors.begin(), neighbors.end(), i) != neighbors.end());
  CHECK(std::is_sorted(neighbors.begin(), neighbors.end()));
}

// Every horizon factor m = delta / dx from 1 to 8 in steps of 0.25. At the
// half-integer m the square at offset (m + 1/2) dx touches the horizon circle
// along its near edge: it has no area inside the disk, so it must not be in
// the family, and the exact area sum must still hold. Reference: pi delta^2
// (closed form) and the symmetry of congruent squares with equal horizons
// (reflection through the midpoint of the bond maps cell_j ∩ disk_i onto
// cell_i ∩ disk_j, so phi_ij = phi_ji).
TEST_CASE("families are exact and symmetric for every horizon factor from 1 to 8", "[families]") {
  const double dx = 1e-4;
  for (int quarter = 4; quarter <= 32; ++quarter) {
    const double m = 0.25 * quarter, delta = m * dx;
    // Just wide enough for interior particles one horizon and one cell away from every edge.
    const int cells = 2 * static_cast<int>(std::ceil(m + 1)) + 4;
    const auto p = pd::make_rectangle_lattice(cells * dx, cells * dx, dx, delta, pd::Quadrature::analytic);
    const auto sums = interior_area_error(p, delta);
    std::ostringstream unpaired;
    double worst_mismatch = 0, smallest_factor = 1;
    for (std::size_t i = 0; i < p.size(); ++i)
      for (auto k = p.family_offsets[i]; k < p.family_offsets[i + 1]; ++k) {
        smallest_factor = std::min(smallest_factor, p.partial_volume[k]);
        const auto j = p.neighbors[k];
        bool found = false;
        for (auto l = p.family_offsets[j]; l < p.family_offsets[j + 1]; ++l)
          if (p.neighbors[l] == i) {
            found = true;
            worst_mismatch = std::max(worst_mismatch, std::fabs(p.partial_volume[l] - p.partial_volume[k]));
          }
        if (!found && unpaired.tellp() < 200) unpaired << i << " -> " << j << " ";
      }
    INFO("m = " << m << ": max rel. error of sum phi V over " << sums.interior << " interior particles "
                << sums.max_relative_error << "; bonds without a partner: " << unpaired.str()
                << "; largest |phi_ij - phi_ji| " << worst_mismatch << "; smallest factor " << smallest_factor);
    REQUIRE(sums.interior >= 9);
    CHECK(sums.max_relative_error < 1e-12);
    CHECK(unpaired.str().empty());
    // Round-off only: phi is a sum of signed areas up to about (m + 1)^2 dx^2,
    // divided by dx^2, from coordinates that differ in their last bits
    // between i and j (measured: at most 0.3 (m + 1)^2 ulps of 1).
    CHECK(worst_mismatch < 4e-15 * (m + 1) * (m + 1));
    CHECK(smallest_factor > 1e-6);  // tangent cells carry no area: no bonds with a round-off factor
  }
}

TEST_CASE("the cell-disk memo finds every value it was given, by the key's bits, across its growth", "[families]") {
  // Reference: the values handed to `add` (one per key, the key's index),
  // for 5,000 keys (the table grows from 1,024 slots several times) of
  // squares at offsets i dx, j dx from the centre, as the set-ups ask.
  const double dx = 1e-3;
  pd::CellDiskMemo memo;
  std::vector<pd::CellDiskMemo::Key> keys;
  pd::CellDiskMemo::Found found;
  for (int j = 0; j < 50; ++j)
    for (int i = 0; i < 100; ++i) {
      const double cx = i * dx, cy = j * dx, h = 0.5 * dx;
      const double vx[4] = {cx - h, cx + h, cx + h, cx - h}, vy[4] = {cy - h, cy - h, cy + h, cy + h};
      keys.push_back(pd::CellDiskMemo::key(vx, vy, pd::Vec2{0, 0}, 3 * dx));
      found.emplace_back(keys.back(), static_cast<double>(keys.size() - 1));
    }
  CHECK(memo.find(keys[0]) == nullptr);  // an empty memo
  // The first half, then all (the first half again: found twice, kept once).
  memo.add(pd::CellDiskMemo::Found(found.begin(), found.begin() + 2500));
  CHECK(memo.size() == 2500);
  CHECK(memo.find(keys[2500]) == nullptr);
  memo.add(found);
  REQUIRE(memo.size() == keys.size());
  std::size_t wrong = 0;
  for (std::size_t k = 0; k < keys.size(); ++k) {
    const double* value = memo.find(keys[k]);
    wrong += value == nullptr || *value != static_cast<double>(k);
  }
  CHECK(wrong == 0);
  // A value added again for a known key does not replace the first.
  memo.add({{keys[7], -1.0}});
  REQUIRE(memo.find(keys[7]) != nullptr);
  CHECK(*memo.find(keys[7]) == 7.0);
  // Keys equal as numbers but not in their bits are different keys
  // (atan2(-0.0, -1) = -pi, atan2(0.0, -1) = pi).
  pd::CellDiskMemo::Key negative_zero = keys[0];
  negative_zero[8] = 0.0;
  pd::CellDiskMemo::Key positive_zero = negative_zero;
  negative_zero[8] = -0.0;
  memo.add({{positive_zero, 1.5}});
  CHECK(memo.find(negative_zero) == nullptr);
  REQUIRE(memo.find(positive_zero) != nullptr);
  CHECK(*memo.find(positive_zero) == 1.5);
  // A radius other than the one stored is another key.
  pd::CellDiskMemo::Key wider = keys[3];
  wider[8] = 3.5 * dx;
  CHECK(memo.find(wider) == nullptr);
}
