#pragma once
// The effects a scene may switch on or off, as compile-time tags: the kernels
// are templates over them, so a switched-off effect leaves no test and no
// array in a hot loop (the choice is made once, model_registry.hpp).
//
// Damage: bonds break for good when over-stretched, and the damage index of
// every particle is kept (theory.md Sec. 1). Surface correction needs no tag:
// it is folded into the bond stiffness at set-up (factor 1 when off).
namespace pd::solver {

struct DamageOn {
  static constexpr bool enabled = true;
};
struct DamageOff {
  static constexpr bool enabled = false;
};

}  // namespace pd::solver
