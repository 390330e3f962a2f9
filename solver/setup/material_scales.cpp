#include "material_scales.hpp"

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <sstream>
#include <vector>

#include "error.hpp"
#include "model_registry.hpp"
#include "units.hpp"

namespace pd::solver {
namespace {

struct MaterialKey {
  const char* name;  // under [material]
  double value;      // SI
  Quantity kind;
};

// A material key with a unit by its name under [material] (the thickness for any other).
MaterialKey material_key(const MaterialSpec& m, const std::string& name) {
  if (name == "youngs_modulus") return {"youngs_modulus", m.youngs_modulus, Quantity::stress};
  if (name == "density") return {"density", m.density, Quantity::density};
  if (name == "fracture_energy") return {"fracture_energy", m.fracture_energy, Quantity::energy_per_area};
  return {"thickness", m.thickness, Quantity::length};
}

std::string key_value_text(const MaterialKey& k) {
  return "material." + std::string(k.name) + " = " + shortest_text(k.value) + " " + si_unit(k.kind);
}

// How many decades the value lies outside what solids have (0 inside).
double decades_outside(const MaterialKey& k) {
  const PlausibleRange range = plausible_range(k.kind);
  if (k.value < range.low) return std::log10(range.low) - std::log10(k.value);
  if (k.value > range.high) return std::log10(k.value) - std::log10(range.high);
  return 0;
}

// Not a finite number, or non-zero below the smallest normal double.
bool out_of_range(double value) { return !std::isfinite(value) || (value != 0 && std::fabs(value) < DBL_MIN); }

// "KEYS: QUANTITY is VALUE, beyond the range of numbers: ...", or "below
// the smallest normal number ...", and that the unit does not save it.
[[noreturn]] void refuse(const Scene& scene, std::initializer_list<const char*> keys, const std::string& quantity,
                         double value, const std::string& at_zero = "") {
  const bool overflow = !std::isfinite(value) || std::fabs(value) >= 1;
  throw Error(material_keys_described(scene, keys) + ": " + quantity + " is " + format_number(value) +
              (overflow ? ", beyond the range of numbers"
                        : ", below the smallest normal number " + format_number(DBL_MIN) +
                              (value == 0 && !at_zero.empty() ? " (" + at_zero + ")" : std::string())) +
              "; a value written with its unit is taken as given, but not one the run cannot compute with");
}

}  // namespace

namespace {

// "SOURCE: key 'material.K' = VALUE UNIT (with OTHER = VALUE UNIT, ...; NOTE)",
// K the key farthest outside its plausible range; the parentheses only
// when there are others or a note.
std::string keys_described(const Scene& scene, std::initializer_list<const char*> keys, const std::string& note) {
  std::vector<MaterialKey> named;
  for (const char* k : keys) named.push_back(material_key(scene.material, k));
  const auto blamed = std::max_element(named.begin(), named.end(), [](const MaterialKey& a, const MaterialKey& b) {
    return decades_outside(a) < decades_outside(b);
  });
  std::string inside;
  for (const auto& k : named)
    if (&k != &*blamed) inside += (inside.empty() ? "with " : ", ") + key_value_text(k);
  if (!note.empty()) inside += (inside.empty() ? "" : "; ") + note;
  return scene.source_of("material." + std::string(blamed->name)) + ": key 'material." + blamed->name + "' = " +
         shortest_text(blamed->value) + " " + si_unit(blamed->kind) + (inside.empty() ? "" : " (" + inside + ")");
}

}  // namespace

std::string material_keys_described(const Scene& scene, std::initializer_list<const char*> keys) {
  return keys_described(scene, keys, "");
}

std::string implausible_material_described(const Scene& scene, std::initializer_list<const char*> keys) {
  const MaterialKey* farthest = nullptr;
  std::vector<MaterialKey> named;
  for (const char* k : keys) named.push_back(material_key(scene.material, k));
  for (const auto& k : named)
    if (k.value != 0 && decades_outside(k) > 0 &&
        (!farthest || decades_outside(k) > decades_outside(*farthest)))
      farthest = &k;
  if (!farthest) return {};
  const PlausibleRange range = plausible_range(farthest->kind);
  std::ostringstream note;
  note << "outside " << range.what << ", " << range.low << " to " << range.high << " " << si_unit(farthest->kind);
  return keys_described(scene, keys, note.str());
}

std::vector<std::string> material_range_warnings(const MaterialSpec& m) {
  std::vector<std::string> warnings;
  for (const char* name : {"youngs_modulus", "density", "fracture_energy", "thickness"}) {
    const MaterialKey k = material_key(m, name);
    // (0: a density or fracture energy the scene may leave out.)
    if (k.value == 0 || decades_outside(k) == 0) continue;
    const PlausibleRange range = plausible_range(k.kind);
    std::ostringstream w;
    w << key_value_text(k) << " is outside " << range.what << " (" << range.low << " to " << range.high << " "
      << si_unit(k.kind) << "): written with its unit, it is taken as given; the time step, wave speed, masses "
      << "and energies of the run follow from it";
    warnings.push_back(w.str());
  }
  return warnings;
}

void check_material_scales(const Scene& scene, const ParticleSet& particles) {
  if (particles.size() == 0) return;
  const MaterialSpec& m = scene.material;
  // The model's constants at the smallest horizon (a refined child's: half
  // its parent's per level) and the largest: c ~ E / delta^3 grows as the
  // horizon shrinks, s0 ~ sqrt(G0 / (E delta)) falls as it grows.
  const auto [smallest, largest] = std::minmax_element(particles.horizon.begin(), particles.horizon.end());
  const double finest =
      scene.refinement.enabled ? std::ldexp(*smallest, -static_cast<int>(scene.refinement.levels)) : *smallest;
  for (const double horizon : {finest, *largest}) {
    const ModelSummary model = with_model(scene.model, scene.osb_failure, [&](auto law) {
      using Model = decltype(law);
      return Model::summary(Model::constants(m, horizon), m.plane);
    });
    for (const auto& [name, value] : model.constants) {
      const bool critical_stretch = name == "critical_stretch";
      const bool zero_refused = critical_stretch && scene.effects.damage;
      if (!out_of_range(value) && !(zero_refused && value == 0)) continue;
      const std::string quantity =
          "the model's " + name + " (summary.json) at the horizon " + format_number(horizon) + " m";
      if (critical_stretch)
        refuse(scene, {"fracture_energy", "youngs_modulus"}, quantity, value,
               "every bond would break at its first stretch");
      refuse(scene, {"youngs_modulus"}, quantity, value);
    }
  }
  // Forces [N], masses [kg] and energies [J] of the plate are densities times
  // the cells' volumes, area x thickness.
  double smallest_area = INFINITY, plate_area = 0;
  for (double area : particles.volume) smallest_area = std::min(smallest_area, area), plate_area += area;
  const auto check = [&](std::initializer_list<const char*> keys, const std::string& what, double per_volume) {
    const double cell = per_volume * smallest_area * m.thickness, plate = per_volume * plate_area * m.thickness;
    if (!(cell >= DBL_MIN))
      refuse(scene, keys, "the smallest cell's " + what, cell, "forces, masses and energies would be 0");
    if (!std::isfinite(plate)) refuse(scene, keys, "the plate's " + what, plate);
  };
  check({"thickness"}, "volume (its area times the thickness) [m^3]", 1.0);
  // (A quasi-static scene may leave the density out: 0, no masses.)
  if (m.density > 0) check({"density", "thickness"}, "mass (density x area x thickness) [kg]", m.density);
  check({"youngs_modulus", "thickness"}, "elastic energy scale (Young's modulus x area x thickness) [J]",
        m.youngs_modulus);
}

}  // namespace pd::solver
