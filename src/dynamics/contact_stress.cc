#include "dynamics/contact_stress.h"

#include <cmath>
#include <numbers>
#include <vector>

#include "common/errors.h"
#include "contact/hertz_pressure.h"
#include "dynamics/rigid_jump_speed.h"
#include "geometry/extremum.h"

namespace camdyn {

std::optional<LineContact> line_contact(const ContactConfig& contact) {
  if (!contact.from_materials || !contact.from_materials->width) return std::nullopt;
  const MaterialsConfig& m = *contact.from_materials;
  return LineContact{effective_modulus(m.E1, m.nu1, m.E2, m.nu2), *m.width};
}

LineContact require_line_contact(const ContactConfig& contact, const std::string& file, const std::string& path) {
  if (const std::optional<LineContact> c = line_contact(contact)) return *c;
  throw InputError(file, path,
                   "needs the contact's materials and width (mechanism.contact.stiffness: {\"from_materials\": "
                   "{..., \"width\": ...}}): the limit is on the Hertz line-contact pressure");
}

double curvature_sum(double cam_radius_of_curvature, const FollowerGeometry& follower) {
  const double rho = cam_radius_of_curvature;
  const double cam = std::isfinite(rho) && rho != 0.0 ? 1.0 / rho : 0.0;
  return cam + (follower.circle() ? 1.0 / follower.radius : 0.0);
}

namespace {

/// The peak over the held train's grid (dynamics/held_train_force.h).
PressurePeak peak_held_contact_pressure(const Model& model, const LineContact& contact, double omega) {
  const RigidContactForce force(model, omega);
  PressurePeak peak;
  for (int i = 0; i < force.grid_angles(); ++i) {
    const double theta = kTwoPi * i / force.grid_angles();
    const SynthesisedCam::Kinematics k = model.cam->kinematics(theta);
    const double p = hertz_line_pressure(force.grid_generalised(i) / k.g_q, contact.width, contact.e_star,
                                         curvature_sum(k.radius_of_curvature, model.follower));
    if (p > peak.pressure) peak = {p, theta * 180.0 / std::numbers::pi};
  }
  return peak;
}

}  // namespace

PressurePeak peak_rigid_contact_pressure(const Model& model, const LineContact& contact, double omega) {
  if (rigid_figures_held(model)) return peak_held_contact_pressure(model, contact, omega);
  auto pressure = [&](double theta) {
    return hertz_line_pressure(rigid_normal_force(model, theta, omega), contact.width, contact.e_star,
                               curvature_sum(model.cam->kinematics(theta).radius_of_curvature, model.follower));
  };
  constexpr int kSamples = 3600;
  std::vector<double> us(kSamples), ps(kSamples);
  for (int i = 0; i < kSamples; ++i) {
    us[i] = kTwoPi * i / kSamples;
    ps[i] = pressure(us[i]);
  }
  const geometry_detail::Extremum peak = geometry_detail::refine_max(pressure, us, ps);
  const double at = std::fmod(peak.u, kTwoPi);
  return {peak.value, (at < 0.0 ? at + kTwoPi : at) * 180.0 / std::numbers::pi};
}

double contact_cam_radius_of_curvature(const Model& model, const Evaluation& ev) {
  if (model.pair_form == PairForm::general) {
    if (model.contour) return 1.0 / model.contour->curvature(model.contour_lift->at(ev.theta).u);
    return model.cam->kinematics(ev.theta).radius_of_curvature;
  }
  if (model.contour) return 1.0 / model.contour->curvature(ev.pair.u);
  return model.cam->kinematics(ev.pair.u).radius_of_curvature;
}

double contact_pressure(const Model& model, const HertzContact& contact, const Evaluation& ev) {
  if (!(ev.normal_force > 0.0)) return 0.0;
  return hertz_pressure(contact, ev.normal_force,
                        curvature_sum(contact_cam_radius_of_curvature(model, ev), model.follower));
}

double rigid_contact_pressure(const Model& model, const HertzContact& contact, const RigidContactForce& force,
                              double theta) {
  const double rho = model.contour ? 1.0 / model.contour->curvature(model.contour_lift->at(theta).u)
                                   : model.cam->kinematics(theta).radius_of_curvature;
  return hertz_pressure(contact, force.normal(theta), curvature_sum(rho, model.follower));
}

double rigid_contact_pressure(const Model& model, const HertzContact& contact, double theta, double omega) {
  return rigid_contact_pressure(model, contact, RigidContactForce(model, omega), theta);
}

double rigid_cam_torque(const Model& model, double theta, double omega) {
  return RigidContactForce(model, omega).torque(theta);
}

}  // namespace camdyn
