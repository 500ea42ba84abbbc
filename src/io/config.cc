// Config loading: each struct of config.h is mapped to and from JSON by one
// `visit` function listing its fields and their checks (io/json_archive.h).
// Checks between fields use `require`; defaults stay in config.h.
#include "io/config.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "common/errors.h"
#include "common/study_budget.h"
#include "io/csv_reader.h"
#include "io/dotted_path.h"
#include "io/input_file.h"
#include "io/json_archive.h"
#include "io/json_merge.h"
#include "io/typed_archive.h"
#include "scene/contact_law_form.h"
#include "scene/follower_shape.h"
#include "scene/study_kind.h"

namespace camdyn {

namespace fs = std::filesystem;

namespace {

/// `name` becomes the output folder out/<name>.
Check plain_name() {
  Check check;
  check.expected = "a non-empty name";
  check.text = [](const std::string& s) -> std::string {
    if (s.empty()) return "must not be empty";
    if (s == "." || s == "..") return "must be a plain name (it names the output folder)";
    if (s.find_first_of("/\\") != std::string::npos) {
      return "must not contain '/' or '\\' (it names the output folder), got " + describe_json(Json(s));
    }
    return "";
  };
  return check;
}

/// A scene's `study`: a word of the study registry (scene/study_kind.h), so a
/// mistyped one is told every study. A scene is a simulate config; the other
/// studies read their configs with their own runners (cli/run_study.cc), so
/// their words reach a scene only where it cannot run them.
Check scene_study() {
  Check check = one_of_enum<StudyKind>();
  check.text = [any_study = check.text](const std::string& s) -> std::string {
    std::string reason = any_study(s);
    if (!reason.empty() || s == enum_name(StudyKind::simulate)) return reason;
    return "study '" + s + "' is not available in this version of camdyn (see the open issues)";
  };
  return check;
}

}  // namespace

/// The smallest contact exponent n a config may give [-]: below it the run
/// does not finish (docs/warnings.md). The largest circle radius is
/// kMaxCircleToBaseRadius (scene/follower_shape.h).
constexpr double kMinContactExponent = 0.5;
/// The fastest start a follower may be given [m/s, or rad/s for an arm].
constexpr double kMaxInitialSpeed = 1e3;
/// The largest base radius [m]: no cam is larger, and the cost of a run
/// grows with it (the contact point sweeps the contour at R ω: 1e4 m takes
/// 12x the time of 1 m, 1e5 m does not finish).
constexpr double kMaxBaseRadius = 100.0;
/// The most lumped masses a spring with mass may be cut into (docs/config.md, "Follower trains").
constexpr int kMaxSpringCoils = 32;
/// The most bodies `mechanism.train` may hold after the follower.
constexpr std::size_t kMaxTrainBodies = 8;
/// The most states a train may add: 2 per body and 2 per lumped mass of every
/// spring with mass, the follower's included (the band its solver is built for).
constexpr std::int64_t kMaxTrainStates = 112;

// Conditions on one value that depend on the scene's choices are checks of
// that field (not `require`s), so that whatever checks a value without JSON
// (io/typed_archive.h: identification's fitted values) gets them too.
namespace {

/// Below kMinContactExponent, K δ^n is a step from 0 to K at first touch:
/// the integrator chatters on it without end (docs/warnings.md).
Check contact_exponent_floor() {
  Check check;
  check.expected = "a number >= " + format_shortest(kMinContactExponent);
  check.number = [](double n) -> std::string {
    if (n >= kMinContactExponent) return "";
    return "must be >= " + format_shortest(kMinContactExponent) + ", got " + format_shortest(n) +
           ": with so small an exponent the force K delta^n jumps from 0 to K at first touch and the run "
           "never finishes (1 for line contact, 1.5 for Hertz point contact)";
  };
  return check;
}

/// A law of another form than the viscous one derives its damping from the
/// restitution: any 'damping' given to it is refused (docs/config.md).
Check damping_unused_by(ContactModel model) {
  Check check;
  check.expected = "null";
  check.number = [model](double /*c*/) -> std::string {
    return "only model " + law_words(ForceForm::viscous) + " uses 'damping' (model '" + to_string(model) +
           "' derives it from 'restitution'); set it to null";
  };
  return check;
}

/// `integrator.order`: one of the orders of ARKODE's tables for `method`
/// (kErkOrders, kDirkOrders); the other methods take none (docs/config.md).
Check runge_kutta_order(IntegrationMethod method) {
  const bool erk = method == IntegrationMethod::arkode_erk;
  const std::span<const int> orders = erk ? std::span<const int>(kErkOrders) : std::span<const int>(kDirkOrders);
  std::string list;
  for (const int q : orders) list += (list.empty() ? "" : ", ") + std::to_string(q);
  Check check;
  check.expected = "one of " + list + " or null";
  check.number = [method, orders, list](double q) -> std::string {
    if (method != IntegrationMethod::arkode_erk && method != IntegrationMethod::arkode_dirk)
      return "only methods 'arkode_erk' and 'arkode_dirk' take an order (method is '" + to_string(method) +
             "'); set it to null";
    if (std::find(orders.begin(), orders.end(), q) != orders.end()) return "";
    return "method '" + to_string(method) + "' has orders " + list + ", got " + format_shortest(q);
  };
  return check;
}

/// An oscillating arm's centre of mass is not known: its gravity must be 0.
Check no_gravity_on_an_arm() {
  Check check;
  check.expected = "0";
  check.number = [](double g) -> std::string {
    if (g == 0.0) return "";
    return "gravity on an oscillating arm is not modelled (its centre of mass is not known): set it to 0 and "
           "fold the arm's weight into the spring preload";
  };
  return check;
}

/// The active coils or the lumped masses of a spring with mass: an integer in [1, kMaxSpringCoils].
Check coil_count() {
  Check check;
  check.expected = "an integer in [1, " + std::to_string(kMaxSpringCoils) + "]";
  check.number = [](double n) -> std::string {
    if (n >= 1 && n <= kMaxSpringCoils) return "";
    return "must be in [1, " + std::to_string(kMaxSpringCoils) + "], got " + format_shortest(n);
  };
  return check;
}

/// An oscillating arm's spring is torsional: its mass is not modelled.
Check no_spring_mass_on_an_arm() {
  Check check;
  check.expected = "0";
  check.number = [](double m) -> std::string {
    if (m == 0.0) return "";
    return "spring mass is modelled for a translating follower or a train body; put the valve spring on a train "
           "body (an oscillating follower's spring is torsional), got " +
           format_shortest(m);
  };
  return check;
}

/// A torsional (arm) spring's wire: the Wahl stress is a helical
/// compression spring's, so an arm's spring takes no wire dimensions.
Check no_wire_on_an_arm() {
  Check check;
  check.number = [](double) -> std::string {
    return "the spring stress is modelled for a helical spring on a translating follower or a train body; an "
           "oscillating follower's spring is torsional";
  };
  return check;
}

/// A train body's name prefixes its timeseries.csv columns (`<name>_position`):
/// a plain identifier whose columns are not the follower's or the law's.
Check train_body_name() {
  Check check;
  check.expected = "a non-empty name of letters, digits and '_'";
  check.text = [](const std::string& s) -> std::string {
    if (s.empty()) return "must not be empty";
    for (const char c : s) {
      const bool plain = (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_';
      if (!plain)
        return "must hold only letters, digits and '_' (it prefixes output columns), got " + describe_json(Json(s));
    }
    if (s == "follower" || s == "kinematic") {
      return "'" + s + "' is taken: its columns (" + s + "_position) are already in timeseries.csv";
    }
    return "";
  };
  return check;
}

/// At most kMaxTrainBodies bodies after the follower.
Check train_size() {
  Check check;
  check.expected = "at most " + std::to_string(kMaxTrainBodies) + " bodies";
  check.size = [](std::size_t n) -> std::string {
    if (n <= kMaxTrainBodies) return "";
    return "holds at most " + std::to_string(kMaxTrainBodies) + " bodies, got " + std::to_string(n);
  };
  return check;
}

}  // namespace

// ---------------------------------------------------------------- motion law

template <class A>
void visit(A& a, SegmentConfig& s) {
  a.field("type", s.type);
  if (s.type == SegmentType::dwell) {
    a.forbid({"law", "lift", "lift_deg", "degree", "control_points"}, "a dwell segment has only 'type' and 'end_deg'");
    a.field("end_deg", s.end_deg, open_closed(0, 360));
    return;
  }
  a.field("law", s.law);
  a.field("end_deg", s.end_deg, open_closed(0, 360));
  a.field("lift", s.lift, positive());
  a.field("lift_deg", s.lift_deg, positive());
  a.require(!(s.lift && s.lift_deg), "lift_deg", "give either 'lift' [m] or 'lift_deg' [deg], not both");
  // A return without a lift goes back down by the total rise (the geometry
  // module checks that rises and returns balance).
  a.require(s.type != SegmentType::rise || s.lift || s.lift_deg, "lift",
            "missing: a rise segment needs 'lift' [m] (or 'lift_deg' for an oscillating follower)");
  if (s.law == SegmentLaw::spline) {
    a.field("degree", s.degree, at_least(3));
    a.field("control_points", s.control_points);
  } else {
    a.forbid({"degree", "control_points"}, "only a segment with law 'spline' has 'degree' and 'control_points'");
  }
}

template <class A>
void visit(A& a, PeriodicSplineConfig& p) {
  a.field("degree", p.degree, at_least(3));
  a.field("knots_deg", p.knots_deg, non_empty(), closed_open(0, 360));
  a.field("lift", p.lift, non_empty());
  a.require(p.lift.size() == p.knots_deg.size(), "lift",
            "needs one lift per knot: " + std::to_string(p.knots_deg.size()) + " knots, " +
                std::to_string(p.lift.size()) + " lifts");
}

template <class A>
void visit(A& a, TableConfig& t) {
  a.path_field("file", t.file, non_empty());
  a.field("angle_column", t.angle_column, non_empty());
  a.field("lift_column", t.lift_column, non_empty());
  a.field("degree", t.degree, at_least(3));
}

template <class A>
void visit(A& a, ContourConfig& c) {
  a.field("points", c.points, non_empty());
  for (std::size_t i = 0; i < c.points.size(); ++i)
    a.require(c.points[i].size() == 2, "points[" + std::to_string(i) + "]",
              "expected [x, y] [m], got " + std::to_string(c.points[i].size()) + " numbers");
  a.field("degree", c.degree, at_least(3));
  a.field("control_points", c.control_points, non_negative());
  a.field("smoothing", c.smoothing, non_negative());
  a.field("parameter_corrections", c.parameter_corrections, non_negative());
}

template <class A>
void visit(A& a, EventSplineConfig& e) {
  a.field("from_deg", e.from_deg, closed_open(0.0, 360.0));
  a.field("to_deg", e.to_deg, open_closed(0.0, 360.0));
  a.require(e.to_deg > e.from_deg, "to_deg", "must be greater than from_deg (an event does not wrap past 360 deg)");
  a.field("degree", e.degree, at_least(3));
  a.field("control_points", e.control_points, non_empty());
}

template <class A>
void visit(A& a, MotionLawConfig& m) {
  const bool segments = a.given("segments", !m.segments.empty());
  const bool spline = a.given("spline", m.spline.has_value());
  const bool table = a.given("table", m.table.has_value());
  const bool contour = a.given("contour", m.contour.has_value());
  a.require(segments + spline + table + contour == 1, "",
            "needs exactly one of 'segments', 'spline', 'table' or 'contour'");
  if (segments) a.field("segments", m.segments, non_empty());
  if (spline) a.field("spline", m.spline);
  if (table) a.field("table", m.table);
  if (contour) a.field("contour", m.contour);
  const bool event = a.given("event", m.event.has_value());
  a.require(!event || !contour, "event", "a contour cam has no law to splice an event into");
  if (event) a.field("event", m.event);
}

// ---------------------------------------------------------------- mechanism

template <class A>
void visit(A& a, MotorConfig& m) {
  a.field("type", m.type);
  if (m.type == Motor::torque_speed) {
    a.field("stall_torque", m.stall_torque, positive());
    a.field("no_load_rpm", m.no_load_rpm, positive());
    a.field("inertia", m.inertia, positive());
  } else {
    a.forbid({"stall_torque", "no_load_rpm", "inertia"},
             "only a 'torque_speed' motor has 'stall_torque', 'no_load_rpm' and 'inertia'");
  }
}

template <class A>
void visit(A& a, DriveConfig& d) {
  a.field("type", d.type);
  if (d.type == Drive::shaft) {
    a.field("inertia", d.inertia, positive());
    a.field("torsional_stiffness", d.torsional_stiffness, positive());
    a.field("torsional_damping", d.torsional_damping, non_negative());
    a.field("motor", d.motor);
  } else {
    a.forbid({"inertia", "torsional_stiffness", "torsional_damping", "motor"},
             "only a 'shaft' drive has 'inertia', 'torsional_stiffness', 'torsional_damping' and 'motor'");
  }
}

template <class A>
void visit(A& a, CamLimitsConfig& l) {
  a.field("max_pressure_angle_deg", l.max_pressure_angle_deg, open_closed(0, 90));
  a.field("min_radius_of_curvature", l.min_radius_of_curvature, positive());
  a.field("max_peak_jerk", l.max_peak_jerk, positive());
  a.field("max_contact_stress", l.max_contact_stress, positive());
}

template <class A>
void visit(A& a, CamConfig& c) {
  // Required (> 0) unless the cam is a contour: checked with the motion law below.
  const bool base_given = a.given("base_radius", c.base_radius > 0.0);
  if (base_given) a.field("base_radius", c.base_radius, non_negative());
  a.field("rpm", c.rpm, non_negative());
  a.require(c.rpm <= kMaxCamRpm, "rpm",
            "must be at most " + format_shortest(kMaxCamRpm) + " rpm, got " + format_shortest(c.rpm));
  a.require(
      c.rpm == 0.0 || c.rpm >= kMinCamRpm, "rpm",
      "must be 0 (a cam at rest) or at least " + format_shortest(kMinCamRpm) + " rpm, got " + format_shortest(c.rpm));
  a.field("direction", c.direction);
  a.field("initial_angle_deg", c.initial_angle_deg);
  a.field_or_file("motion_law", c.motion_law, &c.motion_law.source);
  a.field("drive", c.drive);
  a.field("limits", c.limits);
  if (c.motion_law.contour) {
    a.require(!base_given || c.base_radius == 0.0, "base_radius",
              "a contour cam's base radius follows from its points: leave 'base_radius' out");
  } else if (!base_given) {
    a.require(false, "base_radius", "missing (expected a number > 0 [m])");
  } else {
    a.require(c.base_radius > 0.0, "base_radius", "must be > 0, got " + format_shortest(c.base_radius));
    a.require(c.base_radius <= kMaxBaseRadius, "base_radius",
              "must be at most " + format_shortest(kMaxBaseRadius) + " m, got " + format_shortest(c.base_radius) +
                  " m: lengths are in metres (was it given in millimetres?)");
  }
  a.require(std::abs(c.initial_angle_deg) <= 360.0, "initial_angle_deg",
            "must be within one revolution (-360 to 360), got " + format_shortest(c.initial_angle_deg));
}

/// The fields follow from the shape's description (scene/follower_shape.h):
/// a circle's 'radius', a line's 'face_width', a rolling shape's 'inertia'.
template <class A>
void visit(A& a, ShapeConfig& s) {
  a.field("type", s.type);
  const FollowerShapeTraits shape = follower_shape_traits(s.type);
  const std::string a_shape = "a " + std::string(shape.label);
  if (!shape.takes_radius())
    a.forbid({"radius"}, a_shape + " touches the cam with a line: it has 'face_width', no 'radius'");
  if (!shape.takes_face_width())
    a.forbid({"face_width"}, a_shape + " touches the cam with a circle: it has a 'radius', no 'face_width'");
  if (!shape.takes_inertia())
    a.forbid({"inertia"}, a_shape + " is fixed to the follower (it does not spin): no 'inertia'");
  if (shape.takes_radius()) a.field("radius", s.radius, positive());
  if (shape.takes_face_width()) a.field("face_width", s.face_width, positive());
  if (shape.takes_inertia()) a.field("inertia", s.inertia, non_negative());
}

template <class A>
void visit(A& a, CoilClashConfig& c) {
  a.field("gap", c.gap, positive());
  a.field("stiffness", c.stiffness, positive());
}

namespace {
/// A spring with what it acts on: an oscillating arm's spring is torsional,
/// and its mass is refused.
struct CarriedSpring {
  SpringConfig& spring;
  bool torsional = false;
};

// The surge model's fields (mass, coils, lumps, damping_ratio, clash) are written
// only when given, so a massless spring prints as it did before them. With
// mass 0 they are accepted and unused (mass toggled to compare). In the
// namespace of CarriedSpring, for the archives' argument-dependent lookup.
template <class A>
void visit(A& a, CarriedSpring& c) {
  SpringConfig& s = c.spring;
  a.field("stiffness", s.stiffness, non_negative());
  a.field("preload", s.preload, non_negative());
  if (a.given("mass", s.mass.has_value()))
    a.field("mass", s.mass, non_negative(), c.torsional ? no_spring_mass_on_an_arm() : Check{});
  if (a.given("coils", s.coils.has_value())) a.field("coils", s.coils, coil_count());
  a.require(!s.massive() || s.coils.has_value(), "coils",
            "missing: a spring with mass needs 'coils', its active coils (an integer in [1, " +
                std::to_string(kMaxSpringCoils) + "]; also the masses it is lumped in unless 'lumps' is given)");
  if (a.given("lumps", s.lumps.has_value())) a.field("lumps", s.lumps, coil_count());
  if (a.given("damping_ratio", s.damping_ratio.has_value())) a.field("damping_ratio", s.damping_ratio, non_negative());
  if (a.given("clash", s.clash.has_value())) a.field("clash", s.clash);
  if (a.given("wire_diameter", s.wire_diameter.has_value()))
    a.field("wire_diameter", s.wire_diameter, positive(), c.torsional ? no_wire_on_an_arm() : Check{});
  if (a.given("mean_diameter", s.mean_diameter.has_value()))
    a.field("mean_diameter", s.mean_diameter, positive(), c.torsional ? no_wire_on_an_arm() : Check{});
  a.require(s.wire_diameter.has_value() == s.mean_diameter.has_value(),
            s.wire_diameter ? "mean_diameter" : "wire_diameter",
            "missing: the spring stress needs both 'wire_diameter' and 'mean_diameter' [m]");
  if (s.wire_diameter && s.mean_diameter)
    a.require(*s.mean_diameter > *s.wire_diameter, "mean_diameter",
              "must be larger than wire_diameter (" + format_shortest(*s.wire_diameter) + " m), got " +
                  format_shortest(*s.mean_diameter));
}
}  // namespace

template <class A>
void visit(A& a, SpringConfig& s) {
  CarriedSpring carried{s, false};
  visit(a, carried);
}

/// A contact law's 'damping' [N s/m]: required by the viscous law, refused by
/// the others (mechanism.contact, seats and stops). `written_when_null`: the
/// field is written as null when not given (the cam contact's), else left out.
template <class A>
void contact_damping(A& a, ContactModel model, std::optional<double>& damping, bool written_when_null) {
  const bool viscous = force_form(model) == ForceForm::viscous;
  if (written_when_null || a.given("damping", damping.has_value()))
    a.field("damping", damping, non_negative(), viscous ? Check{} : damping_unused_by(model));
  if (viscous) {
    a.require(damping.has_value(), "damping", "missing: model '" + to_string(model) + "' needs 'damping' [N s/m] >= 0");
  }
}

/// A seat or a stop: the cam contact's force laws against the frame.
template <class A>
void visit(A& a, SeatConfig& s) {
  a.field("position", s.position);
  a.field("model", s.model);
  a.field("stiffness", s.stiffness, positive());
  a.field("exponent", s.exponent, open_closed(0, 5), contact_exponent_floor());
  a.field("restitution", s.restitution, open_closed(0, 1));
  contact_damping(a, s.model, s.damping, /*written_when_null=*/false);
  a.field("reference_velocity", s.reference_velocity, positive());
}

/// A body's `seat` and `stop`, each written only when given; the stop above the seat.
template <class A>
void visit_travel_limits(A& a, std::optional<SeatConfig>& seat, std::optional<SeatConfig>& stop) {
  if (a.given("seat", seat.has_value())) a.field("seat", seat);
  if (a.given("stop", stop.has_value())) a.field("stop", stop);
  if (seat && stop) {
    a.require(stop->position > seat->position, "stop.position",
              "must be above the seat (seat.position = " + format_shortest(seat->position) + "), got " +
                  format_shortest(stop->position));
  }
}

template <class A>
void visit(A& a, InitialConfig& i) {
  a.field("position", i.position, non_negative());
  a.field("velocity", i.velocity);
  // 1e300 m/s made the energy balance inf − inf = NaN, which the time-series
  // writer refused (exit 1); no follower is thrown at 1 km/s.
  a.require(std::abs(i.velocity) <= kMaxInitialSpeed, "velocity",
            "|velocity| must be at most " + format_shortest(kMaxInitialSpeed) + " (m/s, or rad/s for an arm), got " +
                format_shortest(i.velocity));
}

template <class A>
void visit(A& a, GuideFrictionConfig& g) {
  a.field("mu", g.mu, non_negative());
  a.field("regularization_velocity", g.regularization_velocity, positive());
}

template <class A>
void visit(A& a, PivotFrictionConfig& p) {
  a.field("mu", p.mu, non_negative());
  a.field("pin_radius", p.pin_radius, positive());
  a.field("regularization_velocity", p.regularization_velocity, positive());
}

template <class A>
void visit(A& a, FollowerConfig& f) {
  a.field("motion", f.motion);
  const bool oscillating = f.motion == FollowerMotion::oscillating;
  if (oscillating) {
    a.forbid({"offset", "mass", "guide_friction"},
             "an oscillating follower has 'pivot', 'arm_length', 'inertia' and 'pivot_friction' instead of "
             "'offset', 'mass' and 'guide_friction'");
    a.field("pivot", f.pivot, non_empty());
    a.require(f.pivot.empty() || f.pivot.size() == 2, "pivot",
              "expected [x, y] [m], got " + std::to_string(f.pivot.size()) + " numbers");
    a.field("arm_length", f.arm_length, positive());
  } else {
    a.forbid({"pivot", "arm_length", "inertia", "pivot_friction"},
             "'pivot', 'arm_length', 'inertia' and 'pivot_friction' are for an oscillating follower "
             "(motion: \"oscillating\")");
    a.field("offset", f.offset);
  }
  a.field("shape", f.shape);
  if (oscillating) {
    a.field("inertia", f.inertia, positive());
  } else {
    a.field("mass", f.mass, positive());
  }
  CarriedSpring spring{f.spring, oscillating};
  a.field("spring", spring);
  a.field("damping", f.damping, non_negative());
  if (oscillating) {
    a.field("pivot_friction", f.pivot_friction);
  } else {
    a.field("guide_friction", f.guide_friction);
  }
  a.field("initial", f.initial);
  visit_travel_limits(a, f.seat, f.stop);
  // Written only when given, so a scene without it prints as before.
  if (a.given("lash", f.lash.has_value())) a.field("lash", f.lash, non_negative());
}

template <class A>
void visit(A& a, MaterialsConfig& m) {
  a.field("E1", m.E1, positive());
  a.field("nu1", m.nu1, open_closed(-1, 0.5));
  a.field("E2", m.E2, positive());
  a.field("nu2", m.nu2, open_closed(-1, 0.5));
  a.field("width", m.width, positive());
}

template <class A>
void visit(A& a, FrictionConfig& f) {
  a.field("mu", f.mu, non_negative());
  a.field("regularization_velocity", f.regularization_velocity, positive());
  a.field("regularization", f.regularization);
}

namespace {
/// The JSON shape `"stiffness": { "from_materials": {...} }`, over the
/// contact's own block (so that a field found in it is the scene's).
struct StiffnessFromMaterials {
  MaterialsConfig& from_materials;
};
template <class A>
void visit(A& a, StiffnessFromMaterials& s) {
  a.field("from_materials", s.from_materials);
}
}  // namespace

template <class A>
void visit(A& a, ContactConfig& c) {
  a.field("model", c.model);
  if (a.given_object("stiffness", c.from_materials.has_value())) {
    if (!c.from_materials) c.from_materials.emplace();
    StiffnessFromMaterials wrapper{*c.from_materials};
    a.field("stiffness", wrapper);
    c.stiffness.reset();
  } else {
    a.field("stiffness", c.stiffness, positive());
    c.from_materials.reset();
  }
  a.require(c.stiffness || c.from_materials, "stiffness",
            "missing (expected a number > 0 [N/m^n] or { \"from_materials\": {...} })");
  a.field("exponent", c.exponent, open_closed(0, 5), contact_exponent_floor());
  a.field("restitution", c.restitution, open_closed(0, 1));
  contact_damping(a, c.model, c.damping, /*written_when_null=*/true);
  a.field("reference_velocity", c.reference_velocity, positive());
  a.field("friction", c.friction);
  a.field("tracking", c.tracking);
  a.field("pair_form", c.pair_form);
}

template <class A>
void visit(A& a, LinkConfig& l) {
  a.field("ratio", l.ratio, positive());
  a.field("stiffness", l.stiffness, positive());
  a.field("damping", l.damping, non_negative());
  a.field("lash", l.lash, non_negative());
  a.field("one_sided", l.one_sided);
  a.require(l.one_sided || l.lash == 0.0, "lash",
            "a two-sided link has no lash: set 'lash' to 0 or make the link one-sided, got " + format_shortest(l.lash));
}

template <class A>
void visit(A& a, GasLoadConfig& g) {
  a.field("area", g.area, positive());
  a.path_field("pressure", g.pressure, non_empty());
  a.field("crank_ratio", g.crank_ratio, positive());
  a.field("tdc_deg", g.tdc_deg, closed_open(0.0, 360.0));
  a.field("port_pressure", g.port_pressure, non_negative());
}

template <class A>
void visit(A& a, TrainBodyConfig& b) {
  a.field("name", b.name, train_body_name());
  a.field("mass", b.mass, positive());
  a.field("damping", b.damping, non_negative());
  const bool link = a.given("link", true);
  a.require(link, "link", "missing (expected an object with the link's 'stiffness' [N/m] > 0)");
  if (link) a.field("link", b.link);
  // Absent = no spring; written only when the body has one.
  if (a.given("spring", b.spring != SpringConfig{})) a.field("spring", b.spring);
  visit_travel_limits(a, b.seat, b.stop);
  if (a.given("gas", b.gas.has_value())) a.field("gas", b.gas);
}

namespace {

/// The lumped masses of a spring that has mass (0 for a massless one).
std::int64_t spring_lumps(const SpringConfig& s) { return s.massive() ? std::max(0, s.lump_count()) : 0; }

}  // namespace

/// `mechanism.train`, written only when it has bodies: names unique, and the
/// states of the bodies and of the springs with mass within kMaxTrainStates.
template <class A>
void visit_train(A& a, MechanismConfig& m) {
  if (a.given("train", !m.train.empty())) a.field("train", m.train, train_size());
  std::int64_t states = 2 * spring_lumps(m.follower.spring);
  for (std::size_t i = 0; i < m.train.size(); ++i) {
    const std::string& name = m.train[i].name;
    states += 2 + 2 * spring_lumps(m.train[i].spring);
    for (std::size_t j = 0; j < i && !name.empty(); ++j) {
      a.require(m.train[j].name != name, "train[" + std::to_string(i) + "].name",
                "'" + name + "' is already the name of train[" + std::to_string(j) +
                    "]: each body needs its own (it prefixes the body's timeseries.csv columns)");
    }
  }
  const char* lumps_key = m.follower.spring.lumps ? "follower.spring.lumps" : "follower.spring.coils";
  a.require(states <= kMaxTrainStates, m.train.empty() ? lumps_key : "train",
            "the train has " + std::to_string(states) +
                " states (2 per body and 2 per lumped mass of every spring with mass, the follower's included), "
                "more than the limit of " +
                std::to_string(kMaxTrainStates) +
                ": use fewer bodies or fewer lumped masses ('lumps', or 'coils' without it)");
}

template <class A>
void visit(A& a, MechanismConfig& m) {
  a.field("cam", m.cam);
  a.field("follower", m.follower);
  a.field("contact", m.contact);
  visit_train(a, m);
  const bool translating = m.follower.motion == FollowerMotion::translating;
  const bool contour = m.cam.motion_law.contour.has_value();
  a.require(translating || !contour, "follower.motion",
            "a contour cam needs a translating follower (the lift of an oscillating arm on a contour is not "
            "derived)");
  const FollowerShapeTraits shape = follower_shape_traits(m.follower.shape.type);
  if (translating && !contour && shape.circle()) {
    const double reach = m.cam.base_radius + m.follower.shape.radius;
    a.require(std::abs(m.follower.offset) < reach, "follower.offset",
              "|offset| must be < base_radius + " + std::string(shape.label) + " radius = " + format_shortest(reach) +
                  " m, got " + format_shortest(m.follower.offset));
  }
  if (!contour && shape.circle()) {
    const double limit = kMaxCircleToBaseRadius * m.cam.base_radius;  // [m]
    a.require(m.follower.shape.radius <= limit, "follower.shape.radius",
              "a " + std::string(shape.label) + " radius of " + format_shortest(m.follower.shape.radius) +
                  " m on a base circle of " + format_shortest(m.cam.base_radius) + " m (more than " +
                  format_shortest(kMaxCircleToBaseRadius) +
                  " times it) is flat to within the contact's penetration, and the contact point is lost in "
                  "rounding so the run never finishes: give the radius in metres, or use a 'flat' face");
  }
  const auto& segments = m.cam.motion_law.segments;
  for (std::size_t i = 0; i < segments.size(); ++i) {
    const std::string at = "cam.motion_law.segments[" + std::to_string(i) + "]";
    if (translating) {
      a.require(!segments[i].lift_deg, at + ".lift_deg",
                "'lift_deg' is for an oscillating follower; a translating one needs 'lift' [m]");
    } else {
      a.require(!segments[i].lift, at + ".lift",
                "an oscillating follower's law is the arm rotation: give 'lift_deg' [deg], not 'lift' [m]");
    }
  }
  if (!translating) {
    a.require(!m.cam.motion_law.spline && !m.cam.motion_law.table, "cam.motion_law",
              "an oscillating follower needs 'segments' with 'lift_deg' (a spline or table law is in metres)");
  }
}

// ---------------------------------------------------------------- run control

template <class A>
void visit(A& a, SimulationConfig& s) {
  a.field("cycles", s.cycles, positive());
  a.field("discard_cycles", s.discard_cycles, non_negative());
  a.field("duration", s.duration, positive());
  a.field("output_step_deg", s.output_step_deg, open_closed(0, 90));
  a.field("output_step", s.output_step, positive());
  a.field("steady_state", s.steady_state);
}

template <class A>
void visit(A& a, IntegratorConfig& i) {
  a.field("method", i.method);
  a.field("order", i.order, runge_kutta_order(i.method));
  a.field("rtol", i.rtol, open_closed(0, 0.1));
  a.field("atol", i.atol, positive());
  a.field("max_step", i.max_step, positive());
  a.field("step", i.step, positive());
  a.require(i.method != IntegrationMethod::rk4 || i.step, "step", "missing: method 'rk4' needs a fixed 'step' [s]");
  a.field("max_steps", i.max_steps, at_least(1));
  a.field("max_wall_time_s", i.max_wall_time_s, positive());
  a.field("jacobian", i.jacobian);
  a.field("error_estimate", i.error_estimate);
  a.field("flight", i.flight);
}

// Work a config may ask for, checked before anything runs: a run no longer
// than kMaxRevolutionsPerRun, a time series within the memory budget (both
// common/study_budget.h; else the output step was a slip, 1e-9 degrees).

/// Memory of one time-series row while a run records it [bytes]: the
/// TimeSeries columns (12 doubles), twice for the vectors' growth.
constexpr double kSeriesBytesPerRow = 2.0 * 12.0 * sizeof(double);

template <class A>
void require_output_rows(A& a, double rows, const std::string& field) {
  const double bytes = rows * kSeriesBytesPerRow;
  a.require(bytes <= memory_budget_bytes(), field,
            "would write " + (std::isfinite(rows) ? format_shortest(std::ceil(rows)) : std::string("over 1e308")) +
                " time-series rows, about " +
                (std::isfinite(bytes) ? format_shortest(std::ceil(bytes / kBytesPerMb)) : std::string("over 1e300")) +
                " MB in memory: " + memory_budget_text() +
                ": give a larger output step or a shorter run, or raise --max-memory");
}

/// Run length and output step depend on whether the cam turns.
template <class A>
void check_run_control(A& a, const SceneConfig& scene) {
  const double rpm = scene.mechanism.cam.rpm;
  const SimulationConfig& s = scene.simulation;
  if (rpm == 0) {
    const std::string still = "the cam stands still (mechanism.cam.rpm = 0): ";
    a.require(s.duration.has_value(), "simulation.duration", still + "give 'duration' [s]");
    a.require(s.output_step.has_value(), "simulation.output_step", still + "give 'output_step' [s]");
    a.require(!s.cycles, "simulation.cycles", still + "use 'duration' [s] instead of 'cycles'");
    a.require(!s.output_step_deg, "simulation.output_step_deg",
              still + "use 'output_step' [s] instead of 'output_step_deg'");
    a.require(!s.steady_state, "simulation.steady_state", still + "a periodic steady state needs a turning cam");
    if (s.duration && s.output_step) require_output_rows(a, *s.duration / *s.output_step, "simulation.output_step");
    return;
  }
  a.require(!(s.cycles && s.duration), "simulation.duration", "give either 'cycles' or 'duration', not both");
  a.require(!(s.output_step && s.output_step_deg), "simulation.output_step",
            "give either 'output_step_deg' or 'output_step', not both");
  const double cycles = s.cycles ? *s.cycles : s.duration ? *s.duration * rpm / 60.0 : SimulationConfig::kDefaultCycles;
  a.require(cycles > s.discard_cycles, "simulation.discard_cycles",
            "must be less than the number of cycles simulated (" + format_shortest(cycles) + "), got " +
                std::to_string(s.discard_cycles));
  a.require(cycles <= kMaxRevolutionsPerRun, s.duration ? "simulation.duration" : "simulation.cycles",
            "asks for " + format_shortest(cycles) + " revolutions (at most " + format_shortest(kMaxRevolutionsPerRun) +
                "): was a duration given in ms, or cycles in degrees?");
  const double period = 60.0 / std::abs(rpm);  // [s]
  a.require(std::isfinite(cycles * period), "mechanism.cam.rpm",
            "at " + format_shortest(rpm) +
                " rpm a revolution takes longer than the run's clock can count, so it "
                "would never end: give a speed a revolution can be simulated at, or 0 for a still cam with 'duration'");
  if (s.output_step) require_output_rows(a, cycles * period / *s.output_step, "simulation.output_step");
  const double step_deg = s.output_step_deg.value_or(SimulationConfig::kDefaultOutputStepDeg);
  if (!s.output_step) require_output_rows(a, cycles * 360.0 / step_deg, "simulation.output_step_deg");
}

template <class A>
void visit(A& a, ProfileOutputConfig& p) {
  a.field("formats", p.formats, non_empty());
  a.field("points", p.points, at_least(ProfileOutputConfig::kMinPoints));
  a.require(!p.points || *p.points <= ProfileOutputConfig::kMaxPoints, "points",
            "must be <= " + std::to_string(ProfileOutputConfig::kMaxPoints) + ", got " +
                std::to_string(p.points.value_or(0)));
  a.field("chord_tolerance_mm", p.chord_tolerance_mm, at_least(ProfileOutputConfig::kMinChordToleranceMm));
  a.field("cutter_radius_mm", p.cutter_radius_mm, positive());
  a.require(!(p.points && p.chord_tolerance_mm), "chord_tolerance_mm",
            "give either 'points' or 'chord_tolerance_mm', not both");
}

template <class A>
void visit(A& a, ValvetrainOutputConfig& v) {
  a.field("at", v.at);
  a.field("crank_ratio", v.crank_ratio, positive());
  a.field("tdc_deg", v.tdc_deg, closed_open(0, 360));
  a.field("valve", v.valve);
  a.field("checking_heights", v.checking_heights, non_empty(), positive());
  a.field("ramp_end_deg", v.ramp_end_deg, closed_open(0, 360));
  a.require(v.ramp_end_deg.empty() || v.ramp_end_deg.size() == 2, "ramp_end_deg",
            "give two cam angles [deg], where the opening ramp ends and where the closing ramp starts, got " +
                std::to_string(v.ramp_end_deg.size()));
}

template <class A>
void visit(A& a, OutputsConfig& o) {
  a.field("profile", o.profile);
  a.field("valvetrain", o.valvetrain);
}

template <class A>
void visit(A& a, SceneConfig& s) {
  a.field("name", s.name, plain_name());
  a.field("study", s.study, scene_study());
  a.allow("description", Json::value_t::string);
  a.forbid({"extends"}, "'extends' is resolved when the file is loaded (load_config_json)");
  a.field("mechanism", s.mechanism);
  a.field("gravity", s.gravity,
          s.mechanism.follower.motion == FollowerMotion::translating ? Check{} : no_gravity_on_an_arm());
  a.field("simulation", s.simulation);
  a.field("integrator", s.integrator);
  a.field("outputs", s.outputs);
  a.require(!s.outputs.valvetrain || s.mechanism.follower.motion == FollowerMotion::translating, "outputs.valvetrain",
            "valvetrain figures are lifts in metres: they need a translating follower (an oscillating arm's lift is "
            "an angle)");
  check_run_control(a, s);
}

// ---------------------------------------------------------------- loading

namespace {

std::string directory_of(const std::string& file) { return fs::absolute(fs::path(file)).parent_path().string(); }

/// Makes the relative file names of a config that is extended absolute
/// against its own directory, before its content is merged into a config that
/// may live elsewhere.
void rebase_paths(Json& document, const std::string& dir) {
  if (!document.contains("mechanism") || !document["mechanism"].is_object()) return;
  Json& mechanism = document["mechanism"];
  if (!mechanism.contains("cam") || !mechanism["cam"].is_object()) return;
  Json& cam = mechanism["cam"];
  if (!cam.contains("motion_law")) return;
  Json& law = cam["motion_law"];
  if (law.is_string()) {
    // Only when it is there: otherwise the cwd / repository fallbacks still apply.
    const fs::path candidate = fs::path(dir) / law.get<std::string>();
    std::error_code ec;
    if (!fs::path(law.get<std::string>()).is_absolute() && fs::is_regular_file(candidate, ec)) {
      law = absolute_path(law.get<std::string>(), dir);
    }
  } else if (law.is_object() && law.contains("table") && law["table"].is_object()) {
    Json& table = law["table"];
    if (table.contains("file") && table["file"].is_string() && !table["file"].get<std::string>().empty()) {
      table["file"] = absolute_path(table["file"].get<std::string>(), dir);
    }
  }
}

Json load_with_extends(const std::string& file, std::vector<std::string>& chain) {
  std::error_code ec;
  chain.push_back(fs::weakly_canonical(fs::absolute(file), ec).string());
  Json document = read_json_file(file);
  if (!document.is_object()) {
    throw InputError(file, "", "expected a JSON object at the top level, got " + describe_json(document));
  }
  const auto it = document.find("extends");
  if (it != document.end()) {
    if (!it->is_string() || it->get<std::string>().empty()) {
      throw InputError(file, "extends", "expected a file name, got " + describe_json(*it));
    }
    const std::string name = it->get<std::string>();
    // The file system would read the name only up to a NUL: another file.
    if (name.find('\0') != std::string::npos)
      throw InputError(file, "extends", "a file name cannot hold a NUL character (\\u0000), got " + describe_json(*it));
    const std::string parent = absolute_path(name, directory_of(file));
    const std::string canonical = fs::weakly_canonical(parent, ec).string();
    for (const std::string& seen : chain) {
      if (seen != canonical) continue;
      std::string cycle;
      for (const std::string& c : chain) cycle += c + " -> ";
      throw InputError(file, "extends", "extends cycle: " + cycle + canonical);
    }
    try {
      check_input_file(parent, "extends");  // a regular file within the memory budget (io/input_file.h)
    } catch (const InputError& e) {
      throw InputError(file, "extends", "cannot read '" + name + "' (resolved to " + parent + "): " + e.reason());
    }
    Json base = load_with_extends(parent, chain);
    rebase_paths(base, directory_of(parent));
    document.erase("extends");
    merge_config(base, document);
    document = std::move(base);
  }
  chain.pop_back();
  return document;
}

}  // namespace

void set_config_value(Json& document, const std::string& dotted_path, const Json& value) {
  set_dotted_field(document, dotted_path, value);
}

Json load_config_json(const std::string& file, const std::vector<std::string>& overrides) {
  std::vector<std::string> chain;
  Json document = load_with_extends(file, chain);
  for (const std::string& assignment : overrides) apply_assignment(document, assignment);
  return document;
}

void apply_assignment(Json& document, const std::string& assignment) {
  const std::size_t equals = assignment.find('=');
  if (equals == std::string::npos) {
    throw InputError("--set", assignment, "expected KEY=VALUE");
  }
  const std::string key = assignment.substr(0, equals);
  const std::string text = assignment.substr(equals + 1);
  // A config file is UTF-8 (the JSON parser checks it); a command-line
  // argument may be any bytes, and a key or bare string that is not UTF-8
  // would make every later dump of the document throw.
  try {
    (void)Json(assignment).dump();
  } catch (const Json::type_error&) {
    const std::string shown = Json(key).dump(-1, ' ', false, Json::error_handler_t::replace);
    throw InputError("--set", shown.substr(1, shown.size() - 2), "is not valid UTF-8 text");
  }
  // JSON if it parses (numbers, true, null, arrays, objects, "quoted"), else a bare string.
  const auto depth_check = [&key](int depth, Json::parse_event_t /*event*/, Json& /*parsed*/) {
    if (depth > static_cast<int>(kMaxJsonDepth))
      throw InputError("--set", key, "nested deeper than " + std::to_string(kMaxJsonDepth) + " levels");
    return true;
  };
  Json value = Json::parse(text, depth_check, /*allow_exceptions=*/false);
  if (value.is_discarded()) value = text;
  set_config_value(document, key, value);
}

std::optional<std::string> assignment_setting(const std::vector<std::string>& overrides, const std::string& path) {
  for (auto it = overrides.rbegin(); it != overrides.rend(); ++it) {
    const std::size_t equals = it->find('=');
    if (equals == std::string::npos || equals == 0) continue;
    const std::string key = full_dotted_path(it->substr(0, equals));
    if (path == key || (path.starts_with(key) && (path[key.size()] == '.' || path[key.size()] == '['))) return *it;
  }
  return std::nullopt;
}

SceneConfig scene_from_json(const Json& json, const ConfigSource& source) {
  if (!json.is_object()) {
    throw InputError(source.file, "", "expected a JSON object at the top level, got " + describe_json(json));
  }
  SceneConfig scene;
  JsonReader reader(json, "", source);
  visit(reader, scene);
  reader.finish();
  if (scene.mechanism.cam.motion_law.table) load_table_rows(*scene.mechanism.cam.motion_law.table);
  for (std::size_t i = 0; i < scene.mechanism.train.size(); ++i)
    if (scene.mechanism.train[i].gas)
      load_gas_table_rows(*scene.mechanism.train[i].gas, "mechanism.train[" + std::to_string(i) + "].gas.pressure");
  // Defaults that depend on other fields (see SimulationConfig).
  SimulationConfig& s = scene.simulation;
  if (scene.mechanism.cam.rpm > 0) {
    if (!s.cycles && !s.duration) s.cycles = SimulationConfig::kDefaultCycles;
    if (!s.output_step_deg && !s.output_step) s.output_step_deg = SimulationConfig::kDefaultOutputStepDeg;
  }
  if (ProfileOutputConfig* p = scene.outputs.profile ? &*scene.outputs.profile : nullptr; p && !p->points)
    p->chord_tolerance_mm = p->chord_tolerance_mm.value_or(ProfileOutputConfig::kDefaultChordToleranceMm);
  return scene;
}

void load_table_rows(TableConfig& table) {
  if (table.file.empty()) return;  // build_motion_law names the missing file
  const CsvColumns csv =
      read_csv(table.file, {table.angle_column, table.lift_column}, 1, "mechanism.cam.motion_law.table.file");
  table.angle_deg = csv[table.angle_column];
  table.lift = csv[table.lift_column];
  table.lines = csv.lines;
}

void load_gas_table_rows(GasLoadConfig& gas, const std::string& at) {
  if (gas.pressure.empty()) return;
  const CsvColumns csv = read_csv(gas.pressure, {"crank_deg", "pressure"}, 2, at);
  gas.crank_deg = csv["crank_deg"];
  gas.pressure_pa = csv["pressure"];
  gas.lines = csv.lines;
}

Json to_json(const SceneConfig& scene) {
  SceneConfig copy = scene;
  JsonWriter writer;
  visit(writer, copy);
  return writer.json();
}

// ---------------------------------------------------------------- typed scenes (io/typed_archive.h)

void check_scene(const SceneConfig& scene, const std::string& file) { check_scene_fields(scene, {}, file); }

void check_scene_fields(const SceneConfig& scene, std::span<const std::string_view> paths, const std::string& file) {
  SceneConfig copy = scene;  // visit takes a mutable reference (it is shared with the reader)
  TypedChecker checker(file, paths);
  visit(checker, copy);
  checker.finish();
}

std::optional<SceneField> try_find_scene_field(SceneConfig& scene, const std::string& path) {
  FieldLocator locator(full_dotted_path(path));
  visit(locator, scene);
  return locator.result();
}

SceneField find_scene_field(SceneConfig& scene, const std::string& path, const std::string& file) {
  FieldLocator locator(full_dotted_path(path));
  visit(locator, scene);
  if (std::optional<SceneField> field = locator.result()) return *std::move(field);
  throw InputError(file, locator.error_path(), locator.error());
}

ConfigSource config_source(const std::string& file) { return ConfigSource{file, directory_of(file)}; }

SceneConfig load_scene(const std::string& file, const std::vector<std::string>& overrides) {
  return scene_from_json(load_config_json(file, overrides), config_source(file));
}

}  // namespace camdyn
