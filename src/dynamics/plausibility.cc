#include "dynamics/plausibility.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

#include "common/constants.h"
#include "common/errors.h"
#include "contact/force_law.h"
#include "dynamics/coordinate_units.h"
#include "dynamics/kinematic_lift.h"
#include "dynamics/rigid_jump_speed.h"
#include "scene/follower_shape.h"

namespace camdyn {

namespace {

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

/// Follower train thresholds (docs/warnings.md, "Follower trains").
/// A seat's linearised stiffness below this × the spring rate it holds against [-].
constexpr double kMinSeatToSpringStiffness = 10.0;
/// A link's stiffness (seen at the follower) below this × the cam contact's linearised stiffness [-].
constexpr double kMinLinkToContactStiffness = 1e-3;
/// Fewer lumps than this resolve a spring's surge poorly.
constexpr int kMinSpringCoils = 4;

/// Plausibility of units (docs/warnings.md, "Units").
/// A spring compressed by more than this when installed, F₀ / k [m], has a rate in the wrong unit.
constexpr double kMaxInstalledCompression = kMaxPlausibleLength;
/// The heaviest plausible part: a valve-train part (a follower with a seat,
/// a train body, a spring's coils) [kg], any other translating follower
/// [kg], an oscillating arm about its pivot [kg m²]. Above: given in grams?
constexpr double kMaxValveTrainMass = 1.0, kMaxFollowerMass = 10.0, kMaxArmInertia = 1.0;

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
  // A follower with a seat (valve lash) rests on it over the base circle, and
  // the cam picks it up with an impact every revolution: its separations
  // after that are physics whatever the jump speed. A train with coordinates
  // has its own jump speed (dynamics/train_jump_speed.h); the rigid model's
  // leaves out its bodies and a spring with mass.
  const bool lash = !model.train.bodies.empty() && model.train.bodies[0].seat >= 0;  // follower.lash's seat too
  if (model.omega > 0.0 && !explicit_start(scene) && !model.drive.shaft() && !lash) {
    const double rpm = model.omega * 60.0 / kTwoPi;
    const bool train = model.train.has_coordinates();
    const double jump = train ? model.train_jump_speed_rpm : damped_jump_speed_rpm(model);
    if (std::isfinite(jump) && rpm < kJumpSpeedMargin * jump)
      out.push_back({"chatter", "integrator.rtol",
                     "the follower separates (" + count + ") at " + rpm_text(rpm) + ", below the " +
                         (train ? "held train's" : "rigid-model") + " jump speed " + rpm_text(jump) + ": on the " +
                         (train ? "linearised train" : "rigid model") +
                         " the cam holds it there, so the separations are numerical" + tighten});
  } else if (!lash && model.omega > 0.0 && !explicit_start(scene) && std::isfinite(m.jump_speed_rpm) &&
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

/// One body of the train as the scene gives it: its dotted path, its spring and seat.
struct BodyConfig {
  std::string path;  ///< "mechanism.follower" or "mechanism.train[i]"
  const SpringConfig* spring = nullptr;
  const SeatConfig* seat = nullptr;
  double link_ratio = 1.0;  ///< of the link from the body before it (1 for the follower)
  const LinkConfig* link = nullptr;
  double mass = 0.0;         ///< [kg], an oscillating follower's inertia [kg m²]
  bool oscillating = false;  ///< the follower as an arm: its spring in N m/rad, its mass an inertia
};

std::vector<BodyConfig> train_bodies(const SceneConfig& scene) {
  const FollowerConfig& f = scene.mechanism.follower;
  const bool arm = f.motion == FollowerMotion::oscillating;
  std::vector<BodyConfig> bodies{
      {"mechanism.follower", &f.spring, f.seat ? &*f.seat : nullptr, 1.0, nullptr, arm ? f.inertia : f.mass, arm}};
  for (std::size_t i = 0; i < scene.mechanism.train.size(); ++i) {
    const TrainBodyConfig& b = scene.mechanism.train[i];
    bodies.push_back({"mechanism.train[" + std::to_string(i) + "]", &b.spring, b.seat ? &*b.seat : nullptr,
                      b.link.ratio, &b.link, b.mass, false});
  }
  return bodies;
}

/// A seat softer than the spring it holds the body against: linearised at the
/// penetration under the spring's force at the seat, F = F₀ + k p (the
/// follower's preload is at its lowest position, a train body's at x = 0),
/// k_seat = dF/dδ = n K^(1/n) F^((n−1)/n) (K for n = 1). Below 10 k the seat
/// is no stiffer than the spring: the body sinks into it by a fair part of
/// the spring's own travel and rings on it at about the body's own frequency.
void seat_warnings(const SceneConfig& scene, const Model& model, std::vector<PlausibilityWarning>& out) {
  const std::vector<BodyConfig> bodies = train_bodies(scene);
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    const BodyConfig& b = bodies[i];
    if (!b.seat || !(b.spring->stiffness > 0.0) || !(b.seat->stiffness > 0.0)) continue;
    const double k = b.spring->stiffness, n = b.seat->exponent;
    const double load = b.spring->preload + k * b.seat->position;  // [N | N m]
    if (n != 1.0 && !(load > 0.0)) continue;                       // unloaded: no representative penetration
    const double k_seat =
        n == 1.0 ? b.seat->stiffness : n * std::pow(b.seat->stiffness, 1.0 / n) * std::pow(load, (n - 1.0) / n);
    if (k_seat >= kMinSeatToSpringStiffness * k) continue;
    const CoordinateUnits units = i == 0 ? coordinate_units(model) : CoordinateUnits{};
    const std::string rate = std::string(units.force) + "/" + units.position;
    const std::string at_load =
        n == 1.0 ? std::string() : " (linearised under the spring's " + num(load) + " " + units.force + " at the seat)";
    out.push_back({"seat_stiffness", b.path + ".seat.stiffness",
                   "the seat's stiffness " + num(k_seat) + " " + rate + at_load + " is only " + num(k_seat / k) +
                       " x the rate " + num(k) + " " + rate +
                       " of the spring it holds the body against (expect at "
                       "least " +
                       num(kMinSeatToSpringStiffness) +
                       " x): the body sinks into its seat by a fair part "
                       "of the spring's travel; a seat is a stiff contact (usual 1e8 ... 1e10 N/m^n), was it given "
                       "in N/mm?"});
  }
}

/// The static load of every spring of the train at full lift, at the cam
/// contact [N]: the follower's F₀ + k h and each body's F₀ᵢ + kᵢ Rᵢ h through
/// its lever ratios Rᵢ = r₁ ⋯ rᵢ (links taken as rigid, seats as open),
/// divided by ∂g/∂q. The rigid model's load (contact_load) leaves out the
/// train and a spring with mass.
double train_spring_load(const SceneConfig& scene, const Model& model, double g_q) {
  const double lift_q = std::max(std::abs(model.law->min_s()), std::abs(model.law->max_s()));  // h [m | rad]
  const SpringConfig& f = scene.mechanism.follower.spring;
  double load = f.preload + f.stiffness * lift_q;  // on q [N | N m]
  double ratio = 1.0;
  for (const TrainBodyConfig& b : scene.mechanism.train) {
    ratio *= b.link.ratio;
    load += ratio * (b.spring.preload + b.spring.stiffness * ratio * lift_q);
  }
  return g_q > 0.0 ? load / g_q : 0.0;
}

/// A link far more compliant than the cam contact: the link's stiffness seen
/// at the follower, K (r₁ ⋯ rᵢ)², against the cam contact's linearised
/// stiffness seen there, k_c (∂g/∂q)² with k_c = n F / δ at the larger of the
/// rigid model's peak load (contact_load) and the train's static spring load
/// at full lift (train_spring_load).
void link_warnings(const SceneConfig& scene, const Model& model, std::vector<PlausibilityWarning>& out) {
  if (scene.mechanism.train.empty()) return;
  const ForceLaw& law = model.contact;
  const double g_q = std::abs(model.cam->kinematics(model.theta0).g_q);  // [m per unit of q]
  const double load = std::max(contact_load(model).peak_force, train_spring_load(scene, model, g_q));  // [N]
  if (!(load > 0.0) || !(law.stiffness > 0.0)) return;
  const double k_c = law.exponent * std::pow(law.stiffness, 1.0 / law.exponent) *
                     std::pow(load, (law.exponent - 1.0) / law.exponent);  // n F / δ [N/m]
  const double k_c_q = k_c * g_q * g_q;                                    // at the follower [N/m | N m/rad]
  const CoordinateUnits units = coordinate_units(model);
  const std::string rate_q = std::string(units.force) + "/" + units.position;
  double ratio = 1.0;  // r₁ ⋯ rᵢ [m/m | m/rad]
  const std::vector<BodyConfig> bodies = train_bodies(scene);
  for (std::size_t i = 1; i < bodies.size(); ++i) {
    ratio *= bodies[i].link_ratio;
    const double K = bodies[i].link->stiffness, K_q = K * ratio * ratio;
    if (!(K > 0.0) || K_q >= kMinLinkToContactStiffness * k_c_q) continue;
    out.push_back({"link_stiffness", bodies[i].path + ".link.stiffness",
                   "the link's stiffness " + num(K) + " N/m (" + num(K_q) + " " + rate_q +
                       " at the follower, through the lever ratios) is " + num(K_q / k_c_q) +
                       " x the cam contact's linearised stiffness " + num(k_c_q) + " " + rate_q + " (n F / delta at " +
                       num(load) + " N; expect at least " + num(kMinLinkToContactStiffness) +
                       " x): a link softer than the contact by orders of magnitude is as soft as a spring; "
                       "was it given in N/mm?"});
  }
}

/// A spring with mass in fewer than 4 lumps: its first surge mode
/// ω₁ = 2 √(k_s N / m_s) sin(π / (2(N + 1))), k_s = (N + 1) k, lies
/// 1 − ω₁ / (π √(k / m_s)) below the continuous spring's (36 % for N = 1,
/// 16 % for N = 3), and only N modes exist.
void coil_warnings(const SceneConfig& scene, std::vector<PlausibilityWarning>& out) {
  for (const BodyConfig& b : train_bodies(scene)) {
    const SpringConfig& s = *b.spring;
    if (!s.massive() || !s.coils || s.lump_count() >= kMinSpringCoils || !(s.stiffness > 0.0)) continue;
    const int n = s.lump_count();
    const std::string key = s.lumps ? "lumps" : "coils";
    const double m_s = *s.mass, k_s = (n + 1) * s.stiffness;
    const double lumped = std::sqrt(k_s * n / m_s) * std::sin(std::numbers::pi / (2.0 * (n + 1))) / std::numbers::pi;
    const double continuous = 0.5 * std::sqrt(s.stiffness / m_s);  // [Hz]
    out.push_back({"spring_coils", b.path + ".spring." + key,
                   "a spring with mass in " + std::to_string(n) + " lump" + (n == 1 ? "" : "s") +
                       " resolves its surge poorly: its first surge mode is at " + num(lumped) + " Hz, " +
                       num(100.0 * (1.0 - lumped / continuous)) + " % below the continuous spring's " +
                       num(continuous) + " Hz, and it has only " + std::to_string(n) + " mode" + (n == 1 ? "" : "s") +
                       "; use at least " + std::to_string(kMinSpringCoils) + " " + key});
  }
}

/// A spring whose preload needs metres of installed compression, F₀ / k >
/// 1 m: a rate given in N/mm (or a preload in the wrong unit). An arm's
/// spring (N m/rad, N m) may be wound several radians: not judged.
void spring_unit_warnings(const SceneConfig& scene, std::vector<PlausibilityWarning>& out) {
  for (const BodyConfig& b : train_bodies(scene)) {
    const SpringConfig& s = *b.spring;
    if (b.oscillating || !(s.stiffness > 0.0) || !(s.preload > kMaxInstalledCompression * s.stiffness)) continue;
    out.push_back({"spring_units", b.path + ".spring.stiffness",
                   "the spring's preload " + num(s.preload) + " N at its rate " + num(s.stiffness) +
                       " N/m means it is compressed by F0/k = " + num(s.preload / s.stiffness) +
                       " m when installed (a follower's or valve's spring: millimetres to centimetres): was the rate "
                       "given in N/mm (" +
                       num(s.stiffness) + " N/mm = " + num(s.stiffness * 1e3) + " N/m)?"});
  }
}

/// A mass heavier than the kind of part it is: a valve-train part (the scene
/// has a seat or a train: tappets, valves, rockers, springs weigh 0.02 ...
/// 0.5 kg) above 1 kg, another translating follower above 10 kg, an arm
/// above 1 kg m²: most likely given in grams.
void mass_unit_warnings(const SceneConfig& scene, std::vector<PlausibilityWarning>& out) {
  const bool valve_train = scene.mechanism.follower.seat.has_value() || scene.mechanism.follower.lash.has_value() ||
                           !scene.mechanism.train.empty();
  const char* grams = ": was it given in grams? Masses are in kg";
  for (const BodyConfig& b : train_bodies(scene)) {
    const bool follower = b.link == nullptr;
    const double limit = b.oscillating ? kMaxArmInertia : valve_train ? kMaxValveTrainMass : kMaxFollowerMass;
    const std::string kind = b.oscillating ? "an oscillating arm's inertia"
                             : valve_train ? "a valve-train part's mass"
                                           : "a translating follower's mass";
    const std::string unit = b.oscillating ? " kg m^2" : " kg";
    if (b.mass > limit)
      out.push_back({"mass_units", b.path + (b.oscillating ? ".inertia" : ".mass"),
                     (follower ? "the follower's " : "the body's ") +
                         std::string(b.oscillating ? "inertia " : "mass ") + num(b.mass) + unit +
                         " is implausible: " + kind + " is at most about " + num(limit) + unit +
                         (b.oscillating ? ": was it given in g m^2 or about the wrong axis?" : grams)});
    const SpringConfig& s = *b.spring;
    if (s.mass.value_or(0.0) > (valve_train ? kMaxValveTrainMass : kMaxFollowerMass))
      out.push_back({"mass_units", b.path + ".spring.mass",
                     "the spring's mass " + num(*s.mass) + " kg is implausible: its coils weigh at most about " +
                         num(valve_train ? kMaxValveTrainMass : kMaxFollowerMass) + " kg" + grams});
  }
}

/// A checking height of `outputs.valvetrain` at or above the largest lift
/// where the figures are taken (the valve's, or the law's at the cam): its
/// duration is 0 and its angles null.
void checking_height_warnings(const SceneConfig& scene, const Model& model, std::vector<PlausibilityWarning>& out) {
  if (!scene.outputs.valvetrain) return;
  const ValvetrainOutputConfig& v = *scene.outputs.valvetrain;
  const MotionLaw& law = *model.law;
  const bool at_valve = v.at == ValvetrainAt::valve;
  double lift = law.lift();  // [m]
  if (at_valve) {
    const LiftChain chain = lift_chain(model.train, last_body(model.train));
    lift = chain.at(law.max_s()) - chain.datum(law.min_s());
  }
  for (std::size_t i = 0; i < v.checking_heights.size(); ++i) {
    const double h = v.checking_heights[i];
    if (h < lift) continue;
    out.push_back(
        {"checking_height", "outputs.valvetrain.checking_heights[" + std::to_string(i) + "]",
         "the checking height " + num(h) + " m is at or above the largest lift " + num(lift) + " m " +
             (at_valve ? "at the valve (the law through the train's ratios and lash, from its seat)" : "of the law") +
             ": the lift never reaches it, so its duration is 0; checking heights are in metres (1 mm = "
             "0.001)"});
  }
}

/// `follower.lash` against the lash the train's elements make when the scene
/// also gives a follower seat position or a link lash (follower_train.h
/// train_lash): a different cam travel before the seated body moves, or
/// that body held off its seat.
void lash_warning(const SceneConfig& scene, const Model& model, std::vector<PlausibilityWarning>& out) {
  const std::optional<double>& lash = scene.mechanism.follower.lash;
  if (!lash) return;
  const TrainLash given = train_lash(model.train);
  const double tolerance = 1e-9 * std::max(*lash, given.at_cam) + 1e-15;  // [m | rad], round-off of the ratios
  if (std::abs(given.at_cam - *lash) <= tolerance && given.held_open <= tolerance) return;
  const std::string body = given.body > 0 ? "mechanism.train[" + std::to_string(given.body - 1) + "]" : "the follower";
  const std::string unit = coordinate_units(model).position;
  std::string text = "follower.lash is " + num(*lash) + " " + unit + ", but the seat position and link lash given " +
                     "with it make the cam travel " + num(given.at_cam) + " " + unit + " from the base circle";
  if (given.body > 0) text += " before " + body + " leaves its seat";
  if (given.held_open > tolerance)
    text += ", and the follower's seat holds " + body + " " + num(given.held_open) + " m off its seat";
  out.push_back({"lash_mismatch", "mechanism.follower.lash",
                 text + ": leave out the follower's seat.position and the links' lash (follower.lash places the "
                        "lash), or make them agree"});
}

}  // namespace

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
  seat_warnings(scene, model, out);
  link_warnings(scene, model, out);
  coil_warnings(scene, out);
  spring_unit_warnings(scene, out);
  mass_unit_warnings(scene, out);
  checking_height_warnings(scene, model, out);
  lash_warning(scene, model, out);
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
