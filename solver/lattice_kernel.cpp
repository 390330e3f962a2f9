#include "lattice_kernel.hpp"

#include <algorithm>
#include <cmath>
#include <type_traits>

namespace pd::solver {

namespace {
constexpr std::uint32_t none = 0xffffffffu;
}

LatticeKernel::LatticeKernel(const ParticleSet& p, const BondTable& bonds, const std::vector<double>& lambda,
                             bool with_damage) {
  const std::size_t n = p.size();
  const double dx = p.spacing;
  const auto is_square = [&](std::size_t i) {
    return p.region[i] == static_cast<std::uint8_t>(Region::uniform_square) && p.volume[i] == dx * dx;
  };
  const long nx = std::lround((p.xmax - p.xmin) / dx), ny = std::lround((p.ymax - p.ymin) / dx);
  // Lattice cell of every square (-1 for other cells).
  std::vector<long> col(n, -1), row(n, -1);
  std::vector<std::uint32_t> at_cell(static_cast<std::size_t>(nx * ny), none);
  for (std::size_t i = 0; i < n; ++i) {
    if (!is_square(i)) continue;
    col[i] = static_cast<long>(std::floor((p.x[i] - p.xmin) / dx));
    row[i] = static_cast<long>(std::floor((p.y[i] - p.ymin) / dx));
    if (col[i] < 0 || col[i] >= nx || row[i] < 0 || row[i] >= ny) {
      col[i] = row[i] = -1;
      continue;
    }
    at_cell[static_cast<std::size_t>(row[i] * nx + col[i])] = static_cast<std::uint32_t>(i);
  }
  // Reference: the square with the largest family made of squares only.
  std::size_t reference = n, best = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (col[i] < 0) continue;
    const auto size = bonds.offsets[i + 1] - bonds.offsets[i];
    if (size <= best) continue;
    bool all_squares = true;
    for (auto b = bonds.offsets[i]; b < bonds.offsets[i + 1] && all_squares; ++b) all_squares = col[bonds.neighbor[b]] >= 0;
    if (all_squares) reference = i, best = size;
  }
  if (reference == n) {
    for (std::uint32_t i = 0; i < n; ++i) general_.push_back(i);
    return;
  }
  std::vector<long> di, dj;
  std::vector<double> stiffness_ref;
  for (auto b = bonds.offsets[reference]; b < bonds.offsets[reference + 1]; ++b) {
    const auto j = bonds.neighbor[b];
    di.push_back(col[j] - col[reference]);
    dj.push_back(row[j] - row[reference]);
    stiffness_ref.push_back(bonds.stiffness[b] / (0.5 * (lambda[reference] + lambda[j])));
  }
  const std::size_t s = di.size();
  // Bond i->j at offset o and j->i at -o must carry the same stiffness bit
  // for bit (momentum); the reference's two values differ in the last bits.
  for (std::size_t o = 0; o < s; ++o)
    for (std::size_t m = o + 1; m < s; ++m)
      if (di[m] == -di[o] && dj[m] == -dj[o]) stiffness_ref[o] = stiffness_ref[m] = 0.5 * (stiffness_ref[o] + stiffness_ref[m]);
  long halo = 0;
  for (std::size_t o = 0; o < s; ++o) halo = std::max({halo, std::labs(di[o]), std::labs(dj[o])});
  row_length_ = nx + 2 * halo;
  const auto grid = [&](long c, long r) { return static_cast<std::int64_t>((r + halo) * row_length_ + (c + halo)); };
  for (std::size_t o = 0; o < s; ++o) {
    offset_.push_back(dj[o] * row_length_ + di[o]);
    const auto b = bonds.offsets[reference] + o;
    xi_x_.push_back(static_cast<Real>(di[o] * dx));
    xi_y_.push_back(static_cast<Real>(dj[o] * dx));
    rest_.push_back(static_cast<Real>(bonds.rest_length[b]));
    stiffness_.push_back(static_cast<Real>(stiffness_ref[o]));
    critical_extension_.push_back(static_cast<Real>(bonds.critical_stretch * bonds.rest_length[b]));
    damage_weight_.push_back(with_damage ? static_cast<Real>(bonds.damage_weight[b]) : Real(0));
  }

  // Which squares follow the stencil exactly.
  std::vector<bool> lattice(n, false);
  for (std::size_t i = 0; i < n; ++i) {
    if (col[i] < 0 || bonds.offsets[i + 1] - bonds.offsets[i] != s) continue;
    bool match = true;
    for (std::size_t o = 0; o < s && match; ++o) {
      const long c = col[i] + di[o], r = row[i] + dj[o];
      const auto b = bonds.offsets[i] + o;
      const auto j = bonds.neighbor[b];
      match = c >= 0 && c < nx && r >= 0 && r < ny && at_cell[static_cast<std::size_t>(r * nx + c)] == j &&
              bonds.stiffness[b] > 0 &&
              std::fabs(bonds.rest_length[b] - bonds.rest_length[bonds.offsets[reference] + o]) <=
                  1e-12 * bonds.rest_length[b] &&
              std::fabs(bonds.stiffness[b] - 0.5 * (lambda[i] + lambda[j]) * stiffness_ref[o]) <=
                  1e-9 * bonds.stiffness[b] &&
              (!with_damage || bonds.damage_weight[b] == bonds.damage_weight[bonds.offsets[reference] + o]);
    }
    lattice[i] = match;
  }
  // Runs of consecutive lattice particles in consecutive cells of a row.
  std::vector<bool> read_by_lattice(n, false);
  for (std::uint32_t i = 0; i < n; ++i) {
    if (!lattice[i]) {
      general_.push_back(i);
      continue;
    }
    const bool extends = !segments_.empty() && particle_.back() + 1 == i && row[particle_.back()] == row[i] &&
                         col[particle_.back()] + 1 == col[i];
    if (extends)
      ++segments_.back().length;
    else
      segments_.push_back({i, static_cast<std::uint32_t>(particle_.size()), 1, grid(col[i], row[i])});
    particle_.push_back(i);
    read_by_lattice[i] = true;
    for (auto b = bonds.offsets[i]; b < bonds.offsets[i + 1]; ++b) read_by_lattice[bonds.neighbor[b]] = true;
  }
  for (std::uint32_t i = 0; i < n; ++i)
    if (read_by_lattice[i]) grid_particle_.push_back(i), grid_cell_.push_back(grid(col[i], row[i]));

  const std::size_t cells = static_cast<std::size_t>(row_length_ * (ny + 2 * halo));
  ux_.assign(cells, Real(0));
  uy_.assign(cells, Real(0));
  lambda_.assign(cells, Real(0));
  for (std::size_t g = 0; g < grid_particle_.size(); ++g)
    lambda_[static_cast<std::size_t>(grid_cell_[g])] = static_cast<Real>(lambda[grid_particle_[g]]);
  if (with_damage) intact_.assign(s * particle_.size(), 1);
}

void LatticeKernel::load_states(const BondTable& bonds, const std::vector<std::uint8_t>& intact) {
  if (intact_.empty()) return;
  const std::size_t q_count = particle_.size();
  for (std::size_t q = 0; q < q_count; ++q) {
    const auto first = bonds.offsets[particle_[q]];
    for (std::size_t o = 0; o < offset_.size(); ++o) intact_[o * q_count + q] = intact[first + o];
  }
}

void LatticeKernel::store_states(const BondTable& bonds, std::vector<std::uint8_t>& intact) const {
  if (intact_.empty()) return;
  const std::size_t q_count = particle_.size();
  for (std::size_t q = 0; q < q_count; ++q) {
    const auto first = bonds.offsets[particle_[q]];
    for (std::size_t o = 0; o < offset_.size(); ++o) intact[first + o] = intact_[o * q_count + q];
  }
}

template <class DamageMode>
void LatticeKernel::compute(Kinematics& k, const std::vector<double>& ref_x, const std::vector<double>& ref_y,
                            const BondTable& bonds, DamageState* state) {
  constexpr bool with_damage = std::is_same_v<DamageMode, DamageOn>;
  const std::int64_t scattered = static_cast<std::int64_t>(grid_particle_.size());
#pragma omp parallel for schedule(static)
  for (std::int64_t g = 0; g < scattered; ++g) {
    const auto i = grid_particle_[g];
    ux_[static_cast<std::size_t>(grid_cell_[g])] = static_cast<Real>(k.x[i] - ref_x[i]);
    uy_[static_cast<std::size_t>(grid_cell_[g])] = static_cast<Real>(k.y[i] - ref_y[i]);
  }
  const std::size_t q_count = particle_.size(), s = offset_.size();
  const std::int64_t segments = static_cast<std::int64_t>(segments_.size());
  constexpr std::uint32_t chunk = 256;
#pragma omp parallel for schedule(dynamic, 4)
  for (std::int64_t sg = 0; sg < segments; ++sg) {
    const Segment seg = segments_[static_cast<std::size_t>(sg)];
    for (std::uint32_t start = 0; start < seg.length; start += chunk) {
      const std::uint32_t count = std::min(chunk, seg.length - start);
      // Bond forces in single precision, their sums in double: pairs of
      // opposite bond forces then cancel exactly in the momentum.
      alignas(64) double ax[chunk], ay[chunk];
      alignas(64) Real area[chunk];
      for (std::uint32_t t = 0; t < count; ++t) ax[t] = ay[t] = 0.0, area[t] = Real(0);
      const std::int64_t cell0 = seg.first_cell + start;
      const Real* ux0 = ux_.data() + cell0;
      const Real* uy0 = uy_.data() + cell0;
      const Real* lam0 = lambda_.data() + cell0;
      for (std::size_t o = 0; o < s; ++o) {
        const Real* uxj = ux0 + offset_[o];
        const Real* uyj = uy0 + offset_[o];
        const Real* lamj = lam0 + offset_[o];
        const Real xx = xi_x_[o], xy = xi_y_[o], rest = rest_[o];
        const Real half_k = Real(0.5) * stiffness_[o], limit = critical_extension_[o], weight = damage_weight_[o];
        std::uint8_t* st = with_damage ? intact_.data() + o * q_count + seg.first_lattice + start : nullptr;
#pragma omp simd
        for (std::uint32_t t = 0; t < count; ++t) {
          const Real dux = uxj[t] - ux0[t], duy = uyj[t] - uy0[t];
          const Real yx = xx + dux, yy = xy + duy;
          const Real length = std::sqrt(yx * yx + yy * yy);
          // |y| - |xi| = (|y|^2 - |xi|^2) / (|y| + |xi|), with |y|^2 - |xi|^2 formed from
          // the displacement difference: no cancellation, and one division per bond.
          const Real excess = Real(2) * (xx * dux + xy * duy) + dux * dux + duy * duy;
          const Real sum = length + rest;
          Real f = half_k * (lam0[t] + lamj[t]) * excess / (length * sum);
          if constexpr (with_damage) {
            const std::uint8_t holds = st[t] & static_cast<std::uint8_t>(excess <= limit * sum);
            st[t] = holds;
            f *= static_cast<Real>(holds);
            area[t] += weight * static_cast<Real>(holds);
          }
          ax[t] += (f * yx);
          ay[t] += (f * yy);
        }
      }
      for (std::uint32_t t = 0; t < count; ++t) {
        const std::uint32_t i = seg.first_particle + start + t;
        k.fx[i] = ax[t];
        k.fy[i] = ay[t];
        if constexpr (with_damage) {
          const double damage = 1.0 - static_cast<double>(area[t]) / bonds.family_area[i];
          state->damage[i] = damage < 1e-4 ? 0.0 : damage;  // float sums: ~1e-6 noise; one bond weighs ~1e-2
        }
      }
    }
  }
}

template void LatticeKernel::compute<DamageOn>(Kinematics&, const std::vector<double>&, const std::vector<double>&,
                                               const BondTable&, DamageState*);
template void LatticeKernel::compute<DamageOff>(Kinematics&, const std::vector<double>&, const std::vector<double>&,
                                                const BondTable&, DamageState*);

}  // namespace pd::solver
