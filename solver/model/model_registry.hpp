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

// Calls f(Model{}) for the model of `type`.
template <class F>
decltype(auto) with_model(ModelType type, F&& f) {
  switch (type) {
    case ModelType::pmb: return f(Pmb{});
    case ModelType::osb: return f(Osb{});
  }
  throw std::logic_error("unknown model type");
}

// Calls f(Model{}, Damage{}) for the model of `type` and the damage switch:
// the only place where the effects become types.
template <class F>
decltype(auto) with_model_and_effects(ModelType type, bool damage, F&& f) {
  return with_model(type, [&](auto model) -> decltype(auto) {
    return damage ? f(model, DamageOn{}) : f(model, DamageOff{});
  });
}

}  // namespace pd::solver
