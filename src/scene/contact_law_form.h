// The form of each contact law's normal force, in one place (docs/model.md,
// the contact laws): the one switch over ContactModel that says which laws
// are elastic, viscous or hysteresis-damped. The loader asks it which keys a
// law takes (io/config.cc); the force law asks it how to compute
// (contact/force_law.h, whose χ is the other switch over ContactModel).
#pragma once

#include <string>

#include "scene/scene.h"  // ContactModel

namespace camdyn {

/// The form of a law's normal force F_n (docs/model.md §3).
enum class ForceForm {
  elastic,     ///< K δ^n: no damping, no clamp switch (hertz)
  viscous,     ///< K δ^n + c δ̇ with the config's 'damping' c [N s/m] (kelvin_voigt)
  hysteresis,  ///< K δ^n (1 + χ δ̇ / v₀), χ from the restitution e (ForceLaw::chi())
};

/// The form of `model`'s force. A law missing here is a compiler error (-Wswitch).
ForceForm force_form(ContactModel model);

/// The config words of the laws of `form`, each quoted and joined by " or "
/// ("'kelvin_voigt'"), for messages.
std::string law_words(ForceForm form);

}  // namespace camdyn
