#pragma once
// The kinematics of one deformed bond (theory.md Sec. 1), written once for
// any arithmetic type: double (neighbour lists, energies, the quasi-static
// problem), float, and eight float lanes (the lattice sweep, simd.hpp).
//
// From the reference bond xi = X_j - X_i and the relative displacement
// eta = u_j - u_i: y = xi + eta, and the extension e = |y| - |xi| is formed as
// (|y|^2 - |xi|^2) / (|y| + |xi|) with |y|^2 - |xi|^2 = 2 xi.eta + eta.eta,
// free of the cancellation of |y| - |xi| (a 20 mm plate at strain 1e-5 would
// lose 9 of 16 digits in double, all of them in float). Both directions of a
// pair see the same extension bit for bit.
#include "simd.hpp"

namespace pd::solver {

template <class Real>
struct DeformedBond {
  Real yx, yy;  // current bond vector y = xi + eta [m]
  Real length;  // |y| [m]
  Real excess;  // |y|^2 - |xi|^2 [m^2]
  Real sum;     // |y| + |xi| [m]
};

template <class Real>
inline DeformedBond<Real> deformed_bond(Real xi_x, Real xi_y, Real rest_length, Real eta_x, Real eta_y) {
  using simd::fmadd;
  using std::sqrt;
  DeformedBond<Real> b;
  b.yx = xi_x + eta_x;
  b.yy = xi_y + eta_y;
  b.length = sqrt(fmadd(b.yx, b.yx, b.yy * b.yy));
  b.excess = fmadd(Real(2), fmadd(xi_x, eta_x, xi_y * eta_y), fmadd(eta_x, eta_x, eta_y * eta_y));
  b.sum = b.length + rest_length;
  return b;
}

// e = |y| - |xi| [m]
template <class Real>
inline Real extension(const DeformedBond<Real>& b) {
  return b.excess / b.sum;
}

}  // namespace pd::solver
