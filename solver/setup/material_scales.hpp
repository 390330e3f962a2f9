#pragma once
// The material's values against the range of doubles (docs/robustness.md,
// "material values beyond the range of numbers"). A value written with its
// unit is taken as given (docs/scenes.md, "Units"), but one that makes a
// quantity the run derives from it overflow, or underflow to zero, would
// run to a meaningless end: every bond broken at once (a critical stretch of
// 0), energies and reactions of 0 J and 0 N, or a time step of 0 s.
#include <initializer_list>
#include <string>
#include <vector>

#include "particle_file.hpp"
#include "scene.hpp"

namespace pd::solver {

// pd::Error naming the material key at fault, its value and the quantity
// derived from it, before the set-up, when:
// - a constant of the model (model/*.hpp, at the smallest and the largest
//   horizon the run will have) is not finite, or is non-zero and below the
//   smallest normal double (2.2e-308, where digits are lost on the way to 0);
//   the critical stretch also when it is 0 with damage on;
// - the smallest cell's volume (area x thickness), mass (x density) or
//   elastic energy scale (x Young's modulus) is below that, or the plate's
//   volume, mass or energy scale is not finite.
void check_material_scales(const Scene& scene, const ParticleSet& particles);

// Plan warnings for material values outside what solids have (units.hpp,
// plausible_range): only a value written with its unit gets there (a plain
// number is refused, scene.cpp), and it is taken as given, but the time step,
// wave speed, masses and energies follow from it. E.g. "material.density =
// 1e+300 kg/m^3 is outside the densities of solids (10 to 30000 kg/m^3): ..."
// (before 6 December 2026 such a density ran with a fixed step to exit 0,
// its kinetic energy 1e294 J hiding every other energy, without a word on it).
std::vector<std::string> material_range_warnings(const MaterialSpec& material);

// "SOURCE: key 'material.density' = 1e-300 kg/m^3 (with material.youngs_modulus
// = 1e+100 Pa)": the start of a message about a quantity derived from these
// material keys (names under [material], the first with its unit's kind),
// naming the one farthest outside its plausible range (units.hpp).
std::string material_keys_described(const Scene& scene, std::initializer_list<const char*> keys);

// The same start of a message when one of these material keys lies outside
// what solids have (the one farthest outside), with its range in the
// parentheses: "... (with material.youngs_modulus = 3.24e+09 Pa; outside the
// densities of solids, 10 to 30000 kg/m^3)"; empty when all lie inside. For
// a consequence of the material (a step count from the stable step) that
// should name the material rather than the key it shows up in.
std::string implausible_material_described(const Scene& scene, std::initializer_list<const char*> keys);

}  // namespace pd::solver
