#include "contact/force_law.h"

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

#include "contact/hertz_pressure.h"

namespace camdyn {

// ---------------------------------------------------------------- the laws
// A new law: its word in scene/scene.h, a case in force_form()
// (scene/contact_law_form.cc) and in chi() below.

double ForceLaw::chi() const {
  const double e = restitution;
  switch (model) {
    case ContactModel::hertz:
    case ContactModel::kelvin_voigt:
      return 0.0;
    case ContactModel::hunt_crossley:
      return 1.5 * (1.0 - e);
    case ContactModel::lankarani_nikravesh:
      return 0.75 * (1.0 - e * e);
    case ContactModel::flores:
      return 1.6 * (1.0 - e) / e;
  }
  throw std::invalid_argument("not a ContactModel value");
}

double ForceLaw::elastic_force(double delta) const {
  return delta > 0.0 ? stiffness * contact_power(delta, exponent) : 0.0;
}

double ForceLaw::elastic_energy(double delta) const {
  return delta > 0.0 ? stiffness * delta * contact_power(delta, exponent) / (exponent + 1.0) : 0.0;
}

double ForceLaw::clamp_switch(double delta, double delta_rate, double v0) const {
  switch (force_form(model)) {
    case ForceForm::elastic:
      return 1.0;
    case ForceForm::viscous:
      // Odd extension of K δ^n keeps the function continuous through δ = 0.
      return stiffness * std::copysign(std::pow(std::abs(delta), exponent), delta) + damping * delta_rate;
    case ForceForm::hysteresis:
      return 1.0 + chi() * delta_rate / v0;
  }
  throw std::invalid_argument("not a ForceForm value");
}

double stiffness_from_materials(double E1, double nu1, double E2, double nu2, double R1, double R2, bool line_contact,
                                double width) {
  const double e_star = effective_modulus(E1, nu1, E2, nu2);
  if (line_contact) return std::numbers::pi / 4.0 * e_star * width;
  const double r_star = 1.0 / (1.0 / R1 + 1.0 / R2);
  return 4.0 / 3.0 * e_star * std::sqrt(r_star);
}

}  // namespace camdyn
