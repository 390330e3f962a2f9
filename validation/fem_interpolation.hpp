#pragma once
// Values of a FEM nodal field at arbitrary points of the plate, with the
// element's own quadratic shape functions (6-node triangle, isoparametric:
// curved edges on the holes included). Point location: a bucket grid of the
// element bounding boxes, then the inverse isoparametric map by Newton's
// method in each candidate element.
#include <array>
#include <vector>

#include "fem_mesh.hpp"

namespace pd::validation {

class FemInterpolator {
public:
  explicit FemInterpolator(const FemMesh& mesh);

  // Value of the nodal field `nodal` at (x, y); pd::Error if the point lies
  // outside the mesh by more than 1e-6 of an element.
  double value(const std::vector<double>& nodal, double x, double y) const;
  // Same for many points at once (the element search is done once per point).
  std::vector<double> values(const std::vector<double>& nodal, const std::vector<double>& x,
                             const std::vector<double>& y) const;

  // Element and natural coordinates (xi, eta) of a point.
  struct Location {
    std::size_t element = 0;
    double xi = 0, eta = 0;
  };
  Location locate(double x, double y) const;
  double value_at(const std::vector<double>& nodal, const Location& where) const;
  // Gradient (d/dx, d/dy) of the field at a located point [field unit per m]:
  // the shape functions' derivatives through the inverse Jacobian of the
  // isoparametric map (strains and stresses of the FEM solution).
  std::array<double, 2> gradient_at(const std::vector<double>& nodal, const Location& where) const;

  // The six quadratic shape functions at (xi, eta) (corners 0-2, mid-sides 01, 12, 20).
  static std::array<double, 6> shape_functions(double xi, double eta);
  // Their derivatives d/dxi (first) and d/deta (second).
  static std::array<std::array<double, 6>, 2> shape_derivatives(double xi, double eta);

private:
  const FemMesh& mesh_;
  double x0_ = 0, y0_ = 0, cell_ = 1;
  long nx_ = 1, ny_ = 1;
  std::vector<std::vector<std::uint32_t>> buckets_;
};

}  // namespace pd::validation
