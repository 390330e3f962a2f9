#pragma once
// The small linear algebra of the surface corrections (theory.md Secs. 3 and
// 5.7): the angular moments of a particle's weighted family are 5-vectors
// over the harmonics h(n) = (1, cos 2t, sin 2t, cos 4t, sin 4t) of the bond
// direction n = (cos t, sin t), and each particle solves a 5 x 5 system (or
// one on a subset of the harmonics) for its factors.
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>

namespace pd::solver {

// h(n) = (1, cos 2t, sin 2t, cos 4t, sin 4t) of a bond direction (dx, dy) (any length > 0).
using Harmonics = std::array<double, 5>;
inline Harmonics bond_harmonics(double dx, double dy) {
  const double r2 = dx * dx + dy * dy;
  const double c2 = (dx * dx - dy * dy) / r2, s2 = 2 * dx * dy / r2;
  return {1.0, c2, s2, c2 * c2 - s2 * s2, 2 * c2 * s2};
}

inline double harmonic_sum(const Harmonics& a, const Harmonics& h) {
  double v = 0;
  for (std::size_t k = 0; k < h.size(); ++k) v += a[k] * h[k];
  return v;
}

namespace moments {

constexpr std::size_t K = std::tuple_size<Harmonics>::value;

// int_disk |xi| dA: the zeroth moment of the continuum's full disk (the factor
// 1/4 c eps^2 common to W_i and W0 drops out); its other four moments vanish.
inline Harmonics full_disk(double horizon) { return {2.0 * M_PI * horizon * horizon * horizon / 3.0, 0, 0, 0, 0}; }

// A K x K matrix, row-major, and its sum of e u v^T.
using Matrix = std::array<double, K * K>;
inline void add_outer(Matrix& a, double e, const Harmonics& u, const Harmonics& v) {
  for (std::size_t k = 0; k < K; ++k)
    for (std::size_t m = 0; m < K; ++m) a[k * K + m] += e * u[k] * v[m];
}
inline void add_outer(Matrix& a, double e, const Harmonics& h) { add_outer(a, e, h, h); }

// A subset of the harmonics, as a bit mask (bit k: harmonic k).
using HarmonicSet = std::uint8_t;
inline constexpr HarmonicSet all_harmonics = 0x1f;
inline bool contains(HarmonicSet set, std::size_t k) { return (set >> k) & 1u; }

// Cholesky factor L (lower, in place) of a symmetric positive definite matrix,
// restricted to the rows and columns of `set` (the others are left as they
// are and never read). False when it is too close to singular for those
// moments to be set independently: some pivot squared falls below 1e-4 times
// its diagonal entry (that row's harmonic is almost a combination of the
// previous ones over the bond directions at hand).
inline bool cholesky(Matrix& a, HarmonicSet set = all_harmonics) {
  constexpr double floor = 1e-4;
  for (std::size_t k = 0; k < K; ++k) {
    if (!contains(set, k)) continue;
    double d = a[k * K + k];
    for (std::size_t m = 0; m < k; ++m)
      if (contains(set, m)) d -= a[k * K + m] * a[k * K + m];
    if (!(d > floor * a[k * K + k])) return false;
    a[k * K + k] = std::sqrt(d);
    for (std::size_t r = k + 1; r < K; ++r) {
      if (!contains(set, r)) continue;
      double s = a[r * K + k];
      for (std::size_t m = 0; m < k; ++m)
        if (contains(set, m)) s -= a[r * K + m] * a[k * K + m];
      a[r * K + k] = s / a[k * K + k];
    }
  }
  return true;
}

// Solves L L^T x = b on `set` with the factor of `cholesky` (x = 0 off the set).
inline Harmonics cholesky_solve(const Matrix& l, Harmonics b, HarmonicSet set = all_harmonics) {
  for (std::size_t k = 0; k < K; ++k) {
    if (!contains(set, k)) {
      b[k] = 0;
      continue;
    }
    for (std::size_t m = 0; m < k; ++m)
      if (contains(set, m)) b[k] -= l[k * K + m] * b[m];
    b[k] /= l[k * K + k];
  }
  for (std::size_t k = K; k-- > 0;) {
    if (!contains(set, k)) continue;
    for (std::size_t m = k + 1; m < K; ++m)
      if (contains(set, m)) b[k] -= l[m * K + k] * b[m];
    b[k] /= l[k * K + k];
  }
  return b;
}

// Solves a x = b on `set` (a general matrix) by Gaussian elimination with
// partial pivoting; x = 0 off the set. False if a pivot vanishes.
inline bool solve(Matrix a, Harmonics b, HarmonicSet set, Harmonics& x) {
  std::array<std::size_t, K> index{};
  std::size_t n = 0;
  for (std::size_t k = 0; k < K; ++k)
    if (contains(set, k)) index[n++] = k;
  for (std::size_t c = 0; c < n; ++c) {
    std::size_t pivot = c;
    for (std::size_t r = c + 1; r < n; ++r)
      if (std::fabs(a[index[r] * K + index[c]]) > std::fabs(a[index[pivot] * K + index[c]])) pivot = r;
    if (!(std::fabs(a[index[pivot] * K + index[c]]) > 0)) return false;
    if (pivot != c) {
      for (std::size_t m = 0; m < n; ++m) std::swap(a[index[c] * K + index[m]], a[index[pivot] * K + index[m]]);
      std::swap(b[index[c]], b[index[pivot]]);
    }
    for (std::size_t r = c + 1; r < n; ++r) {
      const double f = a[index[r] * K + index[c]] / a[index[c] * K + index[c]];
      for (std::size_t m = c; m < n; ++m) a[index[r] * K + index[m]] -= f * a[index[c] * K + index[m]];
      b[index[r]] -= f * b[index[c]];
    }
  }
  x = Harmonics{};
  for (std::size_t c = n; c-- > 0;) {
    double s = b[index[c]];
    for (std::size_t m = c + 1; m < n; ++m) s -= a[index[c] * K + index[m]] * x[index[m]];
    x[index[c]] = s / a[index[c] * K + index[c]];
  }
  return true;
}

}  // namespace moments
}  // namespace pd::solver
