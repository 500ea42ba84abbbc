// Normal contact force laws of docs/model.md §3: F_n = K δ^n + D(δ) δ̇, never
// adhesive (clamped at zero), with the hysteresis damping of
//   Hunt & Crossley 1975:          D = 3 K (1 − e)  / (2 v₀)   δ^n
//   Lankarani & Nikravesh 1990:    D = 3 K (1 − e²) / (4 v₀)   δ^n
//   Flores et al. 2011:            D = 8 K (1 − e)  / (5 e v₀) δ^n
// The last three share the form F = K δ^n (1 + χ δ̇ / v₀) with a model factor χ.
// What each law is (its form, its χ) is in the two switches over ContactModel,
// force_form() (scene/contact_law_form.cc) and ForceLaw::chi() (force_law.cc);
// everything else asks them (docs/architecture.md, "Adding a contact law").
#pragma once

#include <cmath>
#include <string>

#include "geometry/vec2.h"           // value()
#include "scene/contact_law_form.h"  // ForceForm, force_form()
#include "scene/scene.h"             // ContactModel

namespace camdyn {

/// δ^n [m^n] for δ > 0, with the exponents of practice (Hertz's 1.5, the
/// linear 1) by a square root or nothing instead of pow: about ten times
/// cheaper, the same to the last bit or one. For double or dual numbers.
template <class S>
S contact_power(const S& delta, double n) {
  using std::pow;
  using std::sqrt;
  if (n == 1.5) return delta * sqrt(delta);
  if (n == 1.0) return delta;
  return pow(delta, n);
}

struct ForceLaw {
  ContactModel model = ContactModel::hertz;
  double stiffness = 0.0;            ///< K [N/m^n], > 0
  double exponent = 1.5;             ///< n [-], > 0
  double restitution = 1.0;          ///< target e [-], in (0, 1]
  double damping = 0.0;              ///< c [N s/m], the viscous form only
  double reference_velocity = 0.01;  ///< floor of v₀ [m/s]

  /// χ [-] of F = K δ^n (1 + χ δ̇/v₀) for the hysteresis form, 0 otherwise.
  double chi() const;

  /// Normal force [N] at penetration δ [m] and penetration rate δ̇ [m/s] in a
  /// contact episode whose onset approach speed was v₀ [m/s] (already floored).
  /// Zero for δ ≤ 0; clamped at zero (never adhesive).
  double force(double delta, double delta_rate, double v0) const { return force_t(delta, delta_rate, v0); }

  /// force() for any scalar type S (double or the dual numbers of dynamics/dual.h).
  template <class S>
  S force_t(const S& delta, const S& delta_rate, double v0) const {
    if (!(value(delta) > 0.0)) return S(0.0);
    S f = stiffness * contact_power(delta, exponent);
    switch (force_form(model)) {
      case ForceForm::elastic:
        break;
      case ForceForm::viscous:
        f = f + damping * delta_rate;
        break;
      case ForceForm::hysteresis:
        f = f * (1.0 + chi() * delta_rate / v0);
        break;
    }
    return value(f) > 0.0 ? f : S(0.0);
  }

  /// Elastic part K δ^n [N] (0 for δ ≤ 0).
  double elastic_force(double delta) const;

  /// Elastic energy K δ^{n+1}/(n+1) [J] (0 for δ ≤ 0).
  double elastic_energy(double delta) const;

  /// A function of (δ, δ̇), smooth for all δ, whose sign is the sign of the
  /// unclamped force while δ > 0: its zeros are where the clamp switches on or
  /// off, located by the integrator's root finding. Returns 1 for hertz.
  double clamp_switch(double delta, double delta_rate, double v0) const;

  /// True when the law has a force clamp switch (a root function to watch).
  bool has_clamp_switch() const { return force_form(model) != ForceForm::elastic; }
};

/// Effective stiffness from materials: point contact (no width) gives the Hertz
/// K = (4/3) E* sqrt(R*) with n = 1.5; line contact of width L gives the
/// linearised K = (π/4) E* L with n = 1. E* = 1 / ((1−ν₁²)/E₁ + (1−ν₂²)/E₂),
/// 1/R* = 1/R₁ + 1/R₂ (R₁ the cam's base radius, R₂ the roller radius).
double stiffness_from_materials(double E1, double nu1, double E2, double nu2, double R1, double R2, bool line_contact,
                                double width);

}  // namespace camdyn
