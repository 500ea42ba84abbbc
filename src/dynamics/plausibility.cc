#include "dynamics/plausibility.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>

#include "common/errors.h"
#include "contact/force_law.h"
#include "dynamics/coordinate_units.h"
#include "dynamics/rigid_jump_speed.h"
#include "scene/follower_shape.h"

namespace camdyn {

namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;
constexpr double kRadToDeg = 180.0 / std::numbers::pi;

/// Lengths above this are almost surely given in millimetres [m].
constexpr double kMaxPlausibleLength = 1.0;
/// Pressure angle above which a cam drives its follower badly [deg].
constexpr double kMaxPlausiblePressureAngleDeg = 30.0;
/// Usual contact stiffness: polymers on steel to hardened steel on steel [N/m^n].
constexpr double kMinPlausibleStiffness = 1e7, kMaxPlausibleStiffness = 1e13;
/// A circle below this radius next to a too-large penetration is the slip,
/// not the stiffness [m].
constexpr double kSmallCircleRadius = 1e-3;
/// An acceleration that changes by more than this fraction of its peak
/// between two neighbouring samples (0.05° apart) jumps: a jerk spike.
constexpr double kAccelerationJumpFraction = 0.05;
constexpr int kLawSamples = 7200;

/// Result thresholds (docs/warnings.md).
constexpr double kMaxEnergyResidual = 1e-2;        ///< [-], at any tolerance
constexpr double kEnergyResidualPerRtol = 1e4;     ///< residual above this × rtol [-]
constexpr double kMaxPenetrationOfLift = 0.02;     ///< penetration / lift [-]
constexpr double kMaxPenetrationOfRadius = 0.1;    ///< penetration / circle radius [-]
constexpr double kMaxImpactsPerRevolution = 50.0;  ///< above: chatter
constexpr double kMaxImpactsStill = 1000.0;        ///< cam held still: above, chatter
constexpr double kJumpSpeedMargin = 0.9;           ///< separation below this × jump speed: chatter
constexpr double kMaxPositionErrorOfLift = 0.01;   ///< Richardson position error / lift [-]
constexpr double kMaxPeakForceError = 0.05;        ///< Richardson relative peak-force error [-]

std::string num(double x) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.3g", x);
  return buffer;
}

/// A cam speed [rpm] to the nearest rpm or so.
std::string rpm_text(double rpm) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.5g rpm", rpm);
  return buffer;
}

double penetration_at(const ForceLaw& law, double force) {
  return force > 0.0 ? std::pow(force / law.stiffness, 1.0 / law.exponent) : 0.0;
}

std::string stiffness_unit(const ForceLaw& law) { return "N/m^" + num(law.exponent); }

/// The follower's lift in metres, the scale of a penetration at the contact:
/// an oscillating arm's angle times its length. (A position error is in the
/// unit of q and is judged against coordinate_lift instead.)
double lift_m(const Model& model) {
  const double lift = model.law->lift();
  return model.follower.oscillating() ? lift * model.follower.arm_length : lift;
}

bool explicit_start(const SceneConfig& scene) {
  const InitialConfig& init = scene.mechanism.follower.initial;
  return init.position.has_value() || init.velocity != 0.0;
}

void unit_slip_warnings(const SceneConfig& scene, const Model& model, std::vector<PlausibilityWarning>& out) {
  if (std::optional<PlausibilityWarning> slip = unit_slip(scene)) {
    out.push_back(std::move(*slip));
  } else if (!model.follower.oscillating() && model.law->lift() > kMaxPlausibleLength) {
    out.push_back({"unit_slip", "mechanism.cam.motion_law",
                   "the lift is " + num(model.law->lift()) + " m, above " + num(kMaxPlausibleLength) +
                       " m: did you give millimetres? Lengths are in metres"});
  }
}

void stiffness_warning(const Model& model, std::vector<PlausibilityWarning>& out) {
  const ForceLaw& law = model.contact;
  if (law.stiffness >= kMinPlausibleStiffness && law.stiffness <= kMaxPlausibleStiffness) return;
  const ContactLoad load = contact_load(model);
  const bool low = law.stiffness < kMinPlausibleStiffness;
  std::string text = "contact stiffness " + num(law.stiffness) + " " + stiffness_unit(law) + " is outside the usual " +
                     num(kMinPlausibleStiffness) + " ... " + num(kMaxPlausibleStiffness) + " " + stiffness_unit(law);
  if (load.contact_frequency > 0.0) {
    text += ": at the peak rigid-model load " + num(load.peak_force) + " N it penetrates " +
            num(load.peak_penetration) + " m and rings at " + num(load.contact_frequency) + " Hz";
    if (model.omega > 0.0) text += " (" + num(load.contact_frequency * kTwoPi / model.omega) + " per revolution)";
  }
  text += low ? "; was it given in N/mm or for a different exponent?"
              : "; a contact this stiff only makes the run slower (give it in N/m^n)";
  out.push_back({"contact_stiffness", "mechanism.contact.stiffness", text});
}

/// An acceleration that jumps between neighbouring samples: infinite jerk.
void jerk_warning(const Model& model, std::vector<PlausibilityWarning>& out) {
  double peak = 0.0, jump = 0.0, jump_at = 0.0;
  double previous = model.law->eval(0.0).d2s;
  for (int i = 1; i <= kLawSamples; ++i) {
    const double theta = kTwoPi * i / kLawSamples;
    const double a = model.law->eval(theta).d2s;
    peak = std::max(peak, std::abs(a));
    if (std::abs(a - previous) > jump) jump = std::abs(a - previous), jump_at = theta;
    previous = a;
  }
  if (!(peak > 0.0) || jump <= kAccelerationJumpFraction * peak) return;
  out.push_back({"jerk_spike", "mechanism.cam.motion_law",
                 "the law's acceleration d2s/dtheta2 jumps by " + num(100.0 * jump / peak) +
                     " % of its peak at cam angle " + num(std::fmod(jump_at * kRadToDeg, 360.0)) +
                     " deg: the jerk is unbounded there and excites the follower; use a law with continuous "
                     "acceleration (cycloidal, polynomial_345, ...)"});
}

void chatter_warnings(const SceneConfig& scene, const Model& model, const SimulationResult& result,
                      std::vector<PlausibilityWarning>& out) {
  const Metrics& m = result.metrics;
  // Numerical chatter makes onsets that are mostly grazes and re-entries
  // (dynamics/contact_events.h), not impacts: count every onset in the window.
  const auto onsets = std::count_if(result.events.begin(), result.events.end(),
                                    [&](const ContactEvent& e) { return e.onset && e.time >= result.evaluated_from; });
  if (onsets == 0) return;
  const auto impacts = static_cast<double>(onsets);
  const std::string count = std::to_string(onsets) + " contact onsets (" + std::to_string(m.impact_count) + " impacts)";
  const std::string tighten =
      "; tighten integrator.rtol and integrator.atol (a run at 100x tighter tolerances tells "
      "physics from numerics)";
  const double window = result.end_time - result.evaluated_from;  // [s]
  const double revolutions = model.omega > 0.0 ? window * model.omega / kTwoPi : 0.0;
  if (revolutions > 0.0 && impacts > kMaxImpactsPerRevolution * revolutions)
    out.push_back({"chatter", "integrator.rtol",
                   count + " in " + num(revolutions) + " evaluated revolutions (" + num(impacts / revolutions) +
                       " per revolution) is numerical chatter rather than bouncing" + tighten});
  else if (revolutions == 0.0 && impacts > kMaxImpactsStill)
    out.push_back({"chatter", "integrator.rtol", count + " with the cam held still is numerical chatter" + tighten});
  if (model.omega > 0.0 && !explicit_start(scene) && !model.drive.shaft()) {
    const double rpm = model.omega * 60.0 / kTwoPi;
    const double jump = damped_jump_speed_rpm(model);
    if (std::isfinite(jump) && rpm < kJumpSpeedMargin * jump)
      out.push_back({"chatter", "integrator.rtol",
                     "the follower separates (" + count + ") at " + rpm_text(rpm) +
                         ", below the rigid-model jump speed " + rpm_text(jump) +
                         ": on the rigid model the cam holds it there, so the separations are numerical" + tighten});
  } else if (model.omega > 0.0 && !explicit_start(scene) && std::isfinite(m.jump_speed_rpm) &&
             model.omega * 60.0 / kTwoPi < kJumpSpeedMargin * m.jump_speed_rpm && impacts > kMaxImpactsPerRevolution) {
    // A shaft drive's speed varies, so separation below the jump speed may be
    // real: only a high count of impacts is suspicious then.
    out.push_back({"chatter", "integrator.rtol",
                   "the follower separates (" + count + ") at a nominal " + rpm_text(model.omega * 60.0 / kTwoPi) +
                       ", below the rigid-model jump speed " + rpm_text(m.jump_speed_rpm) + tighten});
  }
}

void accuracy_warnings(const SceneConfig& scene, const Model& model, const SimulationResult& result,
                       std::vector<PlausibilityWarning>& out) {
  const double residual = result.metrics.energy_residual;
  const double rtol = scene.integrator.rtol;
  if (std::isfinite(residual) && (residual > kMaxEnergyResidual || residual > kEnergyResidualPerRtol * rtol))
    out.push_back({"energy_residual", "integrator.rtol",
                   "the energy balance does not close: residual " + num(residual) + " (at rtol " + num(rtol) +
                       " expect below " + num(std::min(kMaxEnergyResidual, kEnergyResidualPerRtol * rtol)) +
                       "); the results are not accurate: tighten integrator.rtol and integrator.atol"});
  // The error is in q (docs/model.md §5), so is the lift it is judged against:
  // an arm's rad against its lift in rad.
  const ErrorEstimate& e = result.error;
  const double lift = coordinate_lift(model);
  const CoordinateUnits units = coordinate_units(model);
  if (e.richardson && lift > 0.0 && e.position > kMaxPositionErrorOfLift * lift)
    out.push_back({"error_estimate", "integrator.rtol",
                   "the error estimate (a run at 100x tighter tolerance) differs by " +
                       CoordinateUnits::with_unit(e.position, units.position) + " in position, " +
                       num(100.0 * e.position / lift) + " % of the lift (" +
                       CoordinateUnits::with_unit(lift, units.position) + "): tighten integrator.rtol"});
  if (e.richardson && e.peak_contact_force > kMaxPeakForceError)
    out.push_back({"error_estimate", "integrator.rtol",
                   "the error estimate puts the peak contact force " + num(100.0 * e.peak_contact_force) +
                       " % off: tighten integrator.rtol and integrator.atol"});
}

void penetration_warning(const Model& model, const SimulationResult& result, std::vector<PlausibilityWarning>& out) {
  const double delta = result.metrics.max_penetration;  // [m]
  const double lift = lift_m(model);
  const double radius = model.follower.circle() ? model.follower.radius : 0.0;
  const bool of_lift = lift > 0.0 && delta > kMaxPenetrationOfLift * lift;
  const bool of_radius = radius > 0.0 && delta > kMaxPenetrationOfRadius * radius;
  if (!of_lift && !of_radius) return;
  const double allowed =
      std::min(lift > 0.0 ? kMaxPenetrationOfLift * lift : std::numeric_limits<double>::infinity(),
               radius > 0.0 ? kMaxPenetrationOfRadius * radius : std::numeric_limits<double>::infinity());  // [m]
  const ForceLaw& law = model.contact;
  // K needed for the peak force at the allowed penetration: F = K δ^n.
  const double needed = result.metrics.peak_contact_force / std::pow(allowed, law.exponent);
  out.push_back(
      {"penetration", "mechanism.contact.stiffness",
       "the contact penetrates up to " + num(delta) + " m, " +
           (of_lift ? num(100.0 * delta / lift) + " % of the lift" : "") + (of_lift && of_radius ? ", " : "") +
           (of_radius
                ? num(100.0 * delta / radius) + " % of the " + std::string(model.follower.traits().label) + " radius"
                : "") +
           ": the contact is too soft for a rigid-body model to mean much; a stiffness of at least " + num(needed) +
           " " + stiffness_unit(law) + " keeps it below " + num(allowed) + " m"});
}

/// The peak penetration in the units of the follower coordinate q against
/// what the integrator's error test resolves in q: atol + rtol |q|.
struct ContactResolution {
  double delta_q = 0.0, resolution = 0.0;
  CoordinateUnits units;
  bool unresolved() const { return resolution > 0.0 && delta_q > 0.0 && delta_q < resolution; }
  std::string text() const {
    return (units.oscillating ? " (" + num(delta_q) + " " + units.position + " of arm rotation)" : std::string()) +
           ", below what integrator.rtol and atol resolve (" + num(resolution) + " " + units.position + ")";
  }
};

ContactResolution contact_resolution(const SceneConfig& scene, const Model& model, const ContactLoad& load) {
  ContactResolution r;
  const IntegratorConfig& ic = scene.integrator;
  if (ic.method == IntegrationMethod::rk4 || load.peak_penetration <= 0.0) return r;
  const double g_q = std::abs(model.cam->kinematics(model.theta0).g_q);  // [m per unit of q]
  const double q_scale = std::max(std::abs(model.law->min_s()), std::abs(model.law->max_s()));
  r.resolution = ic.atol + ic.rtol * q_scale;
  r.delta_q = g_q > 0.0 ? load.peak_penetration / g_q : load.peak_penetration;
  r.units = coordinate_units(model);
  return r;
}

void tolerance_warning(const SceneConfig& scene, const Model& model, std::vector<PlausibilityWarning>& out) {
  const ContactLoad load = contact_load(model);
  const ContactResolution r = contact_resolution(scene, model, load);
  if (model.contact.stiffness > kMaxPlausibleStiffness || !r.unresolved()) return;
  out.push_back({"tolerance", "integrator.atol",
                 "the peak rigid-model load " + num(load.peak_force) + " N penetrates the contact " +
                     num(load.peak_penetration) + " m" + r.text() +
                     ": the integrator cannot see the contact and will report chatter as impacts; tighten "
                     "integrator.atol and integrator.rtol"});
}

}  // namespace

std::optional<PlausibilityWarning> unit_slip(const SceneConfig& scene) {
  const MechanismConfig& mech = scene.mechanism;
  auto slip = [](const std::string& field, const std::string& what, double value) {
    return PlausibilityWarning{"unit_slip", field,
                               what + " " + num(value) + " m is above " + num(kMaxPlausibleLength) +
                                   " m: did you give millimetres? Lengths are in metres"};
  };
  if (mech.cam.base_radius > kMaxPlausibleLength)
    return slip("mechanism.cam.base_radius", "base radius", mech.cam.base_radius);
  const MotionLawConfig& law = mech.cam.motion_law;
  for (std::size_t i = 0; i < law.segments.size(); ++i)
    if (law.segments[i].lift && *law.segments[i].lift > kMaxPlausibleLength)
      return slip("mechanism.cam.motion_law.segments[" + std::to_string(i) + "].lift", "lift", *law.segments[i].lift);
  if (law.spline)
    for (std::size_t i = 0; i < law.spline->lift.size(); ++i)
      if (std::abs(law.spline->lift[i]) > kMaxPlausibleLength)
        return slip("mechanism.cam.motion_law.spline.lift[" + std::to_string(i) + "]", "lift", law.spline->lift[i]);
  const ShapeConfig& shape = mech.follower.shape;
  const FollowerShapeTraits traits = follower_shape_traits(shape.type);
  if (traits.takes_radius() && shape.radius > kMaxPlausibleLength)
    return slip("mechanism.follower.shape.radius", std::string(traits.label) + " radius", shape.radius);
  if (traits.takes_face_width() && shape.face_width > kMaxPlausibleLength)
    return slip("mechanism.follower.shape.face_width", "face width", shape.face_width);
  return std::nullopt;
}

void rethrow_naming_unit_slip(const SceneConfig& scene, const std::string& file, const InputError& error) {
  const std::optional<PlausibilityWarning> slip = unit_slip(scene);
  if (!slip || slip->field == error.path()) throw error;
  throw InputError(error.file().empty() ? file : error.file(), slip->field,
                   slip->message + " (building the cam then failed: " + error.path() + ": " + error.reason() + ")");
}

ContactLoad contact_load(const Model& model) {
  ContactLoad load;
  constexpr int kSamples = 720;
  for (int i = 0; i < kSamples; ++i) {
    const double theta = kTwoPi * i / kSamples;
    load.static_force = std::max(load.static_force, rigid_normal_force(model, theta, 0.0));
    load.peak_force = std::max(load.peak_force, rigid_normal_force(model, theta, model.omega));
  }
  const double g_q = std::abs(model.cam->kinematics(model.theta0).g_q);  // [m per unit of q]
  load.effective_mass = g_q > 0.0 ? model.mass / (g_q * g_q) : model.mass;
  load.peak_penetration = penetration_at(model.contact, load.peak_force);
  if (load.peak_penetration > 0.0) {
    // Linearised contact stiffness dF/dδ = n F / δ [N/m].
    const double k_c = model.contact.exponent * load.peak_force / load.peak_penetration;
    load.contact_frequency = std::sqrt(k_c / load.effective_mass) / kTwoPi;
  }
  return load;
}

void check_plausibility(const SceneConfig& scene, const Model& model, const std::string& file) {
  const ForceLaw& law = model.contact;
  const ContactLoad load = contact_load(model);
  const double static_delta = penetration_at(law, load.static_force);  // [m]
  if (static_delta > model.penetration_limit) {
    const FollowerGeometry& fg = model.follower;
    const std::string what =
        "under the spring load alone (" + num(load.static_force) + " N, the rigid model at " +
        "low speed) the contact would penetrate " + num(static_delta) + " m, beyond the " +
        num(model.penetration_limit) + " m the contact model holds for (" +
        (fg.circle() ? "half the " + std::string(fg.traits().label) + " radius" : "a tenth of the base radius") + ")";
    if (fg.circle() && fg.radius < kSmallCircleRadius && law.stiffness >= kMinPlausibleStiffness)
      throw InputError(file, "mechanism.follower.shape.radius",
                       std::string(fg.traits().label) + " radius " + num(fg.radius) + " m: " + what +
                           "; was the radius given in the wrong unit (metres expected)?");
    const double needed = load.static_force / std::pow(model.penetration_limit, law.exponent);
    throw InputError(file, "mechanism.contact.stiffness",
                     "stiffness " + num(law.stiffness) + " " + stiffness_unit(law) +
                         " cannot carry the preload: " + what + "; it needs at least " + num(needed) + " " +
                         stiffness_unit(law) + " (usual: 1e7 ... 1e13)");
  }
  // A stiffness beyond the usual range whose penetration the tolerances do
  // not resolve is the slip; with a usual stiffness the tolerances are too
  // loose, a warning (input_warnings).
  const ContactResolution r = contact_resolution(scene, model, load);
  if (law.stiffness > kMaxPlausibleStiffness && r.unresolved())
    throw InputError(file, "mechanism.contact.stiffness",
                     "stiffness " + num(law.stiffness) + " " + stiffness_unit(law) +
                         ": even the peak rigid-model load " + num(load.peak_force) + " N penetrates only " +
                         num(load.peak_penetration) + " m" + r.text() +
                         ": the integrator could not follow the contact and would not finish; use a stiffness in "
                         "the usual 1e7 ... 1e13 (in N/m^n)");
}

std::vector<PlausibilityWarning> input_warnings(const SceneConfig& scene, const Model& model) {
  std::vector<PlausibilityWarning> out;
  unit_slip_warnings(scene, model, out);
  const CamLimitsConfig& limits = scene.mechanism.cam.limits;
  if (!limits.max_pressure_angle_deg && model.geometry.max_pressure_angle_deg > kMaxPlausiblePressureAngleDeg)
    out.push_back({"pressure_angle", "mechanism.cam.base_radius",
                   "the pressure angle reaches " + num(model.geometry.max_pressure_angle_deg) + " deg at cam angle " +
                       num(model.geometry.max_pressure_angle_at_deg) + " deg (above " +
                       num(kMaxPlausiblePressureAngleDeg) +
                       " deg the cam mostly pushes the follower sideways): a larger base radius or a longer rise "
                       "lowers it; set mechanism.cam.limits.max_pressure_angle_deg to accept it"});
  stiffness_warning(model, out);
  tolerance_warning(scene, model, out);
  jerk_warning(model, out);
  const ContactConfig& contact = scene.mechanism.contact;
  if (force_form(contact.model) != ForceForm::hysteresis && contact.restitution != ContactConfig{}.restitution)
    out.push_back(
        {"ignored_field", "mechanism.contact.restitution",
         "model '" + to_string(contact.model) + "' ignores the restitution (" + num(contact.restitution) + "): " +
             (force_form(contact.model) == ForceForm::viscous ? "its dissipation is the damper 'damping' [N s/m]"
                                                              : "it dissipates nothing") +
             "; for a restitution target use 'hunt_crossley', 'lankarani_nikravesh' or 'flores'"});
  return out;
}

std::vector<PlausibilityWarning> result_warnings(const SceneConfig& scene, const Model& model,
                                                 const SimulationResult& result) {
  std::vector<PlausibilityWarning> out;
  accuracy_warnings(scene, model, result, out);
  penetration_warning(model, result, out);
  chatter_warnings(scene, model, result, out);
  return out;
}

std::vector<PlausibilityWarning> run_warnings(const SceneConfig& scene, const Model& model,
                                              const SimulationResult& result) {
  std::vector<PlausibilityWarning> out = input_warnings(scene, model);
  for (PlausibilityWarning& w : result_warnings(scene, model, result)) out.push_back(std::move(w));
  return out;
}

std::string warning_line(const PlausibilityWarning& w) {
  return "warning: " + (w.field.empty() ? std::string() : w.field + ": ") + w.message;
}

}  // namespace camdyn
