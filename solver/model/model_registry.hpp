#pragma once
// The one place that names the models and turns the scene's run-time choices
// (model type, damage on or off) into compile-time types, once.
//
// To add a model: write its law as a type in model/NAME.hpp (like Pmb in
// pmb.hpp), then add it here: an enum value, a row of `models`, and a case in
// `with_model`. docs/architecture.md, "Adding a model", lists what else a
// model with new needs (e.g. a per-particle pre-pass) touches.
#include <stdexcept>
#include <string>

#include "effects.hpp"
#include "osb.hpp"
#include "pmb.hpp"

namespace pd::solver {

enum class ModelType { pmb, osb };

struct ModelEntry {
  ModelType type;
  const char* name;  // model.type in the scene
};
inline constexpr ModelEntry models[] = {
    {ModelType::pmb, Pmb::name},
    {ModelType::osb, Osb::name},
};

inline const char* to_string(ModelType type) {
  for (const auto& m : models)
    if (m.type == type) return m.name;
  return "?";
}

// Calls f(Model{}) for OSB with the failure variant `failure` (osb.hpp).
template <class F>
decltype(auto) with_osb(OsbFailure failure, F&& f) {
  switch (failure) {
    case OsbFailure::force_and_dilatation: return f(OsbWith<OsbFailure::force_and_dilatation>{});
    case OsbFailure::force_only: return f(OsbWith<OsbFailure::force_only>{});
    case OsbFailure::bond_term_only: return f(OsbWith<OsbFailure::bond_term_only>{});
  }
  throw std::logic_error("unknown OSB failure variant");
}

// Calls f(Model{}) for the model of `type` (`osb_failure`: OSB's failure
// variant, model.osb_failure; unused by the other models).
template <class F>
decltype(auto) with_model(ModelType type, OsbFailure osb_failure, F&& f) {
  switch (type) {
    case ModelType::pmb: return f(Pmb{});
    case ModelType::osb: return with_osb(osb_failure, f);
  }
  throw std::logic_error("unknown model type");
}

// Calls f(Model{}, Damage{}) for the model of `type` and the damage switch:
// the only place where the effects become types.
template <class F>
decltype(auto) with_model_and_effects(ModelType type, OsbFailure osb_failure, bool damage, F&& f) {
  return with_model(type, osb_failure, [&](auto model) -> decltype(auto) {
    return damage ? f(model, DamageOn{}) : f(model, DamageOff{});
  });
}

}  // namespace pd::solver
