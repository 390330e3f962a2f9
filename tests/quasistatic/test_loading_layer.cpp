// The fictitious loading layer (docs/mesher.md, "Loading layers"; docs/scenes.md,
// "Which loading to use when"): a strip pulled through layers outside its ends
// carries the uniform uniaxial field of its edge displacements, where rigid
// strips inside the body make it stiffer.
//
// Reference: plane-stress elasticity with the PMB model's Poisson ratio 1/3
// (docs/theory.md Sec. 1.3) and free lateral edges: the ends x = 0 and x = L
// moved by -U and +U give the homogeneous uniaxial field eps = 2U / L,
// sigma = E eps, so the reaction is E eps W t. Rigid strips one horizon deep
// inside the body leave L - 2 delta to deform, hence an apparent modulus of
// about E L / (L - 2 delta).
#include <catch2/catch.hpp>

#include <cmath>
#include <fstream>

#include "plate_grid.hpp"
#include "strip_stiffness.hpp"
#include "support.hpp"

using namespace pd::validation;

namespace {

constexpr double length = 20e-3, width = 10e-3, spacing = 0.2e-3, m = 4, edge_u = 1e-7;

pd::ParticleSet strip(const std::string& folder, bool layers) {
  const auto geo = folder + "/strip.geo";
  std::ofstream(geo) << "Point(1) = {0, 0, 0}; Point(2) = {20, 0, 0}; Point(3) = {20, 10, 0}; Point(4) = {0, 10, 0};\n"
                        "Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 1};\n"
                        "Curve Loop(1) = {1, 2, 3, 4}; Plane Surface(1) = {1};\n";
  PlateGridSpec spec;
  spec.geometry_file = geo;
  spec.grid = pd::GridKind::nbnug;
  spec.spacing = spacing;
  spec.horizon = m * spacing;
  LoadingLayers loading;
  if (layers) loading.edges = {"left", "right"};
  return make_plate_grid(spec, nullptr, loading);
}

// Modulus seen at the grips: reaction / (W t) over 2U / L.
double apparent_modulus(const TensileTest& t) { return t.stress / (2 * edge_u / length); }

}  // namespace

// Measured (20 x 10 mm, dx = 0.2 mm, delta = 0.8 mm, surface correction on):
// stress / (E eps_interior) - 1 = -0.14 % with either loading, nu 0.334;
// apparent modulus at the grips (reaction over 2U/L) +6.4 % with the in-body
// strips, -2.0 % with the layers moved rigidly (their bonds across the edge
// see the edge value, not the field beyond it: about 0.23 delta of slip per
// grip), +0.01 % with the layers moved by the field u_x = eps x.
// docs/scenes.md, "Which loading to use when", has finer grids.
TEST_CASE("loading layer: a strip pulled through layers carries the uniform uniaxial field",
          "[quasistatic][loading_layer]") {
  const auto folder = pd::quasistatic::test::fresh_folder("loading_layer");
  const double e = 3.24e9, eps = 2 * edge_u / length;

  const auto layered = strip(folder, true);
  const auto scene_layer = strip_scene(true, {x_displacement("loading_layer_left", -edge_u),
                                              x_displacement("loading_layer_right", edge_u)});
  const auto layer = tensile_test(layered, scene_layer, "loading_layer_right", 0, length);

  // The same layers moved by the uniform field itself (a linear value, docs/scenes.md).
  auto left = x_displacement("loading_layer_left", -edge_u), right = x_displacement("loading_layer_right", edge_u);
  left.x_variation.gradient = right.x_variation.gradient = {eps, 0};
  left.x_variation.origin = {0, 0};
  right.x_variation.origin = {length, 0};
  const auto linear = tensile_test(layered, strip_scene(true, {left, right}), "loading_layer_right", 0, length);

  const auto plain = strip(folder, false);
  const auto scene_strip = strip_scene(true, {x_displacement("left", -edge_u), x_displacement("right", edge_u)});
  const auto rigid = tensile_test(plain, scene_strip, "right", 0, length);

  INFO("layer: interior strain / (2U/L) - 1 = " << layer.strain / eps - 1 << ", apparent modulus / E - 1 = "
       << apparent_modulus(layer) / e - 1 << ", stress / (E eps_interior) - 1 = " << layer.modulus() / e - 1
       << ", nu " << layer.poisson_ratio() << " (" << layer.iterations << " iterations)");
  INFO("layer moved by eps x: interior strain / (2U/L) - 1 = " << linear.strain / eps - 1
       << ", apparent modulus / E - 1 = " << apparent_modulus(linear) / e - 1);
  INFO("in-body strips: interior strain / (2U/L) - 1 = " << rigid.strain / eps - 1 << ", apparent modulus / E - 1 = "
       << apparent_modulus(rigid) / e - 1 << ", stress / (E eps_interior) - 1 = " << rigid.modulus() / e - 1);
  // Inside, the field is the uniaxial one: sigma = E eps, nu = 1/3.
  CHECK(layer.modulus() == Approx(e).epsilon(0.005));
  CHECK(layer.poisson_ratio() == Approx(1.0 / 3.0).epsilon(0.02));
  // Moved by the field, the layers reproduce it: strain 2U/L, stress E 2U/L.
  CHECK(linear.strain == Approx(eps).epsilon(0.005));
  CHECK(linear.stress == Approx(e * eps).epsilon(0.005));
  // At the grips the in-body strips are stiffer; the rigid layers are closer (and a little softer).
  CHECK(apparent_modulus(rigid) / e - 1 > 0.04);
  CHECK(apparent_modulus(layer) / e - 1 < 0);
  CHECK(std::fabs(apparent_modulus(layer) / e - 1) < 0.5 * (apparent_modulus(rigid) / e - 1));
}
