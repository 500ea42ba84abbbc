#include "dynamics/contact_stress.h"

#include <cmath>
#include <numbers>

#include "contact/hertz_pressure.h"

namespace camdyn {

namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;

}  // namespace

std::optional<LineContact> line_contact(const ContactConfig& contact) {
  if (!contact.from_materials || !contact.from_materials->width) return std::nullopt;
  const MaterialsConfig& m = *contact.from_materials;
  return LineContact{effective_modulus(m.E1, m.nu1, m.E2, m.nu2), *m.width};
}

PressurePeak peak_rigid_contact_pressure(const Model& model, const LineContact& contact, double omega) {
  const double follower_curvature = model.follower.circle() ? 1.0 / model.follower.radius : 0.0;  // [1/m]
  auto pressure = [&](double theta) {
    const double rho = model.cam->kinematics(theta).radius_of_curvature;  // [m]
    const double cam_curvature = std::isfinite(rho) && rho != 0.0 ? 1.0 / rho : 0.0;
    return hertz_line_pressure(rigid_normal_force(model, theta, omega), contact.width, contact.e_star,
                               cam_curvature + follower_curvature);
  };
  constexpr int kSamples = 3600;
  double best = -1.0;
  int best_i = 0;
  for (int i = 0; i < kSamples; ++i) {
    const double p = pressure(kTwoPi * i / kSamples);
    if (p > best) best = p, best_i = i;
  }
  double a = kTwoPi * (best_i - 1) / kSamples, b = kTwoPi * (best_i + 1) / kSamples;
  const double r = (std::sqrt(5.0) - 1.0) / 2.0;
  for (int it = 0; it < 50; ++it) {
    const double x1 = b - r * (b - a), x2 = a + r * (b - a);
    if (pressure(x1) > pressure(x2))
      b = x2;
    else
      a = x1;
  }
  PressurePeak peak{best, std::fmod(kTwoPi + kTwoPi * best_i / kSamples, kTwoPi) * 180.0 / std::numbers::pi};
  const double refined = 0.5 * (a + b);
  if (const double p = pressure(refined); p > peak.pressure)
    peak = {p, std::fmod(kTwoPi + refined, kTwoPi) * 180.0 / std::numbers::pi};
  return peak;
}

}  // namespace camdyn
