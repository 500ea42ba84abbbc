#include "optim/optimize/rigid_limits.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <numbers>

#include "common/constants.h"
#include "common/errors.h"
#include "contact/hertz_pressure.h"
#include "dynamics/held_train_force.h"
#include "geometry/cam_synthesis.h"
#include "geometry/motion_law.h"

namespace camdyn::optim {

namespace {

constexpr double kStep = 1e-6;     // forward-difference step in a control point (normalised lift)
constexpr double kTarget = 0.996;  // a cut holds its ratio here: 0.4 % clear of the limit
constexpr double kNear = 0.67;     // cuts only where the ratio at c0 is above this
constexpr int kDenseSamples = 3600;

/// The cam of control points c; null when it cannot be synthesised.
std::unique_ptr<SynthesisedCam> cam_of(const DesignSpace& space, const FollowerGeometry& geometry, int direction,
                                       const std::vector<double>& c) {
  try {
    auto law = std::make_shared<const MotionLaw>(
        build_motion_law(space.scene_with_control_points(c).mechanism.cam.motion_law, ""));
    return std::make_unique<SynthesisedCam>(std::move(law), geometry, direction);
  } catch (const InputError&) {
    return nullptr;
  }
}

}  // namespace

RigidLimitProbe::RigidLimitProbe(const DesignSpace& space, const FollowerGeometry& geometry, int direction,
                                 const RigidFollower& follower, ProbedLimits limits, std::vector<double> angles)
    : space_(space),
      geometry_(geometry),
      direction_(direction),
      follower_(follower),
      limits_(std::move(limits)),
      angles_(std::move(angles)) {}

std::vector<double> RigidLimitProbe::ratios(const std::vector<double>& c) const {
  const std::unique_ptr<SynthesisedCam> cam = cam_of(space_, geometry_, direction_, c);
  std::vector<double> out;
  if (!cam) return out;
  double q = 0.0;  // P_n κ at the pressure limit [N/m]
  if (limits_.max_contact_stress)
    q = *limits_.max_contact_stress * *limits_.max_contact_stress * std::numbers::pi * limits_.contact->width /
        limits_.contact->e_star;
  const std::vector<std::vector<double>> held = held_forces(cam->law());
  for (const double theta : angles_) {
    const SynthesisedCam::Kinematics k = cam->kinematics(theta);
    if (limits_.max_pressure_angle_deg)
      out.push_back(std::abs(k.pressure_angle) / (*limits_.max_pressure_angle_deg * kDegToRad));
    const double rho = k.radius_of_curvature;  // [m]
    if (limits_.min_radius_of_curvature)
      out.push_back(std::isfinite(rho) ? *limits_.min_radius_of_curvature / std::abs(rho) : 0.0);
    if (limits_.max_contact_stress) {
      const LawSample s = cam->law().eval(theta);
      const double kappa = curvature_sum(rho, geometry_);
      for (std::size_t j = 0; j < limits_.omegas.size(); ++j) {
        const double generalised = held.empty() ? follower_.margin(limits_.omegas[j], s) + follower_.min_force
                                                : on_revolution_grid(held[j], theta);  // [N | N m]
        const double normal = generalised / k.g_q;                                     // [N]
        out.push_back(normal > 0.0 && kappa > 0.0 ? normal * kappa / q : 0.0);
      }
    }
  }
  return out;
}

bool RigidLimitProbe::broken(const std::vector<double>& c) const {
  const std::unique_ptr<SynthesisedCam> cam = cam_of(space_, geometry_, direction_, c);
  if (!cam) return false;
  CamGeometryReport report;
  try {
    report = check_cam(*cam, "");
  } catch (const InputError&) {
    return false;
  }
  if (limits_.max_pressure_angle_deg && report.max_pressure_angle_deg > *limits_.max_pressure_angle_deg) return true;
  if (limits_.min_radius_of_curvature && report.min_radius_of_curvature < *limits_.min_radius_of_curvature) return true;
  if (!limits_.max_contact_stress) return false;
  if (limits_.held) return held_pressure_broken(*cam);
  for (int i = 0; i < kDenseSamples; ++i) {
    const double theta = 2.0 * std::numbers::pi * i / kDenseSamples;
    const SynthesisedCam::Kinematics k = cam->kinematics(theta);
    const double kappa = curvature_sum(k.radius_of_curvature, geometry_);
    const LawSample s = cam->law().eval(theta);
    for (const double w : limits_.omegas) {
      const double normal = (follower_.margin(w, s) + follower_.min_force) / k.g_q;
      if (hertz_line_pressure(normal, limits_.contact->width, limits_.contact->e_star, kappa) >
          *limits_.max_contact_stress)
        return true;
    }
  }
  return false;
}

std::vector<std::vector<double>> RigidLimitProbe::held_forces(const MotionLaw& law) const {
  std::vector<std::vector<double>> out;
  if (!limits_.held || !limits_.max_contact_stress) return out;
  for (const double w : limits_.omegas)
    // Every harmonic: a cut's forward difference must not see the harmonic count change.
    out.push_back(held_contact_generalised_force(*limits_.held, law, w, RigidContactForce::kHeldAngles, 0.0));
  return out;
}

bool RigidLimitProbe::held_pressure_broken(const SynthesisedCam& cam) const {
  for (const std::vector<double>& q : held_forces(cam.law())) {
    for (std::size_t i = 0; i < q.size(); ++i) {
      const double theta = 2.0 * std::numbers::pi * static_cast<double>(i) / static_cast<double>(q.size());
      const SynthesisedCam::Kinematics k = cam.kinematics(theta);
      if (hertz_line_pressure(q[i] / k.g_q, limits_.contact->width, limits_.contact->e_star,
                              curvature_sum(k.radius_of_curvature, geometry_)) > *limits_.max_contact_stress)
        return true;
    }
  }
  return false;
}

std::vector<LimitCut> RigidLimitProbe::cuts(const std::vector<double>& c0) const {
  const std::vector<double> r0 = ratios(c0);
  std::vector<LimitCut> out;
  if (r0.empty()) return out;
  const int n = static_cast<int>(c0.size());
  std::vector<std::vector<double>> gradient(r0.size(), std::vector<double>(c0.size(), 0.0));
  for (int j = 0; j < n; ++j) {
    std::vector<double> c = c0;
    c[j] += kStep;
    const std::vector<double> r = ratios(c);
    if (r.size() != r0.size()) return {};  // the step left the synthesisable cams: no reliable slope
    for (std::size_t i = 0; i < r0.size(); ++i) gradient[i][j] = (r[i] - r0[i]) / kStep;
  }
  for (std::size_t i = 0; i < r0.size(); ++i) {
    if (!(r0[i] > kNear)) continue;
    LimitCut cut;
    double at_c0 = 0.0;
    for (int j = 0; j < n; ++j) {
      if (gradient[i][j] == 0.0) continue;
      cut.terms.emplace_back(j, gradient[i][j]);
      at_c0 += gradient[i][j] * c0[j];
    }
    if (cut.terms.empty() || !std::isfinite(at_c0)) continue;
    cut.upper = kTarget - r0[i] + at_c0;  // r0 + g·(c − c0) ≤ kTarget
    out.push_back(std::move(cut));
  }
  return out;
}

}  // namespace camdyn::optim
