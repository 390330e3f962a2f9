#pragma once
// What the energy minimiser (ncg.hpp) needs from a problem, and nothing
// more: a total potential energy Pi(u) of the unknowns u, its residual
// (minus the gradient) and Hessian-vector products, a preconditioner and the
// force scale against which the residual is judged.
#include <cstddef>
#include <vector>

namespace pd::solver {

class EnergyProblem {
public:
  virtual ~EnergyProblem() = default;
  virtual std::size_t unknown_count() const = 0;
  // r = -dPi/du [N] on free components, 0 on constrained ones.
  virtual void residual(const std::vector<double>& u, std::vector<double>& r) = 0;
  // hd = (d^2 Pi/du^2) d on free components (0 on constrained ones).
  virtual void hessian_times(const std::vector<double>& u, const std::vector<double>& d,
                             std::vector<double>& hd) const = 0;
  // A positive diagonal approximating the Hessian (Jacobi preconditioner).
  virtual const std::vector<double>& preconditioner() const = 0;
  // s = M^-1 r with the preconditioner M: by default the diagonal above; a
  // problem may couple the components of a particle (QuasiStaticProblem on
  // the lattice kernels: 2 x 2 blocks). One call per CG iteration.
  virtual void precondition(const std::vector<double>& r, std::vector<double>& s) const {
    const auto& diagonal = preconditioner();
    s.resize(r.size());
    for (std::size_t k = 0; k < r.size(); ++k) s[k] = r[k] / diagonal[k];
  }
  // Euclidean norm [N] of the forces the body carries at the last residual():
  // the scale against which the residual is judged.
  virtual double reaction_norm() const = 0;
};

}  // namespace pd::solver
