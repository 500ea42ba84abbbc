// The metrics of one run over its evaluated cycles (docs/model.md §8) and the one
// list of their names and units (`visit`) that every writer iterates:
// summary.json, the report's metrics table, the compare study's columns.
#pragma once

#include <optional>
#include <string>
#include <type_traits>
#include <vector>

namespace camdyn {

/// The metrics of a follower train (docs/model.md §12), each written only
/// when the scene has the element it is about.
struct TrainMetrics {
  bool links = false, seats = false, springs = false, clash = false;  ///< which elements the scene has
  double min_link_force = 0.0;            ///< [N], smallest link force while its body is off its seat
  double link_separation_fraction = 0.0;  ///< [-], time with a link open while no body from it on is seated
  double max_seating_velocity = 0.0;      ///< [m/s], largest approach speed at a seat onset
  long seat_impacts = 0;                  ///< seat onsets with approach in the window
  double peak_spring_force = 0.0;         ///< [N], largest force at the frame end of any spring
  long coil_clashes = 0;                  ///< coil clash onsets in the window
  bool gas = false;                       ///< whether some body has a gas load
  double peak_gas_force = 0.0;            ///< [N], largest |A (p − p_port)| of any gas load
  /// Valve-train verdicts (docs/valvetrain.md), with a seat (`lash`): take-up
  /// bounces (cam or link gaps opening in the take-up windows) and seat
  /// bounces (a body leaving its seat after seating) in the window, the
  /// highest a body rose off its seat in a seat bounce [m | rad], the time a
  /// link is open off every seat in float [-], and whether a body is held off
  /// its seat on the base circle.
  bool lash = false;
  long take_up_bounces = 0;
  long seat_bounces = 0;
  double max_seat_bounce_height = 0.0;
  double link_float_fraction = 0.0;
  bool held_open = false;
  std::vector<std::string> bodies;     ///< every body, the follower first
  std::vector<double> max_lift_error;  ///< per body: |x − its kinematic lift| [m | rad]
  /// Where the train lets go first in the window: "cam contact" or "link <body>"
  /// (empty: nowhere), and the cam angle there [deg].
  std::string separates_first;
  double separates_first_deg = 0.0;
};

struct Metrics {
  double separation_fraction = 0.0;
  double max_separation_gap = 0.0;  ///< [m]
  long impact_count = 0;
  double max_impact_velocity = 0.0;  ///< [m/s]
  double peak_contact_force = 0.0;   ///< [N]
  double min_contact_force = 0.0;    ///< [N]
  double max_penetration = 0.0;      ///< [m]
  double max_kinematic_error = 0.0;  ///< [m | rad]: in q
  double separation_integral = 0.0;  ///< ∫ max(g, 0) dt over the evaluated window [m s]: a smooth measure of jump
  double energy_residual = 0.0;      ///< [-]
  double max_pressure_angle_deg = 0.0;
  double min_radius_of_curvature = 0.0;  ///< [m]
  double jump_speed_rpm = 0.0;           ///< +inf when the law never decelerates (written as null)
  /// The drive (docs/model.md §8): the torque the drive puts on the cam
  /// against the contact, its largest magnitude and its RMS over the window
  /// [N m], and the power the drive delivers (the motor's with a shaft),
  /// averaged over the window [W] (NaN without the quadratures: written as null).
  double peak_cam_torque = 0.0, rms_cam_torque = 0.0;
  double mean_drive_power = 0.0;
  /// The largest Hertz pressure of the dynamic contact force [Pa]; only where
  /// the contact has materials (`contact.stiffness.from_materials`), absent otherwise.
  std::optional<double> peak_contact_stress;
  /// The largest shear stress in a spring's wire, Wahl-corrected [Pa]; only
  /// where a spring gives `wire_diameter` and `mean_diameter`, absent otherwise.
  std::optional<double> peak_spring_stress;
  /// The contact point's largest distance from the face centre [m]; only
  /// for a flat face, absent otherwise.
  std::optional<double> max_face_excursion;
  /// With a seat (docs/valvetrain.md): the part of separation_fraction that
  /// is float (opened above the ramps) [-], and its largest gap [m]; absent
  /// otherwise (every separation is then float).
  std::optional<double> float_fraction, max_float_gap;
  /// With a seat: ∫ max(g, 0) dt over the window where the cam contact
  /// floats [m s] (separation_integral less the lash and the bounces), the
  /// optimiser's smooth measure of jump; not written.
  std::optional<double> float_integral;
  /// With a follower train (seats, springs with mass, bodies): its metrics,
  /// written besides the others (not part of `visit`).
  std::optional<TrainMetrics> train;
};

/// What a writer needs to know about a metric besides its name and value.
struct MetricInfo {
  const char* unit;               ///< as the report's table prints it ("–": dimensionless)
  bool infinite_is_null = false;  ///< +inf (or NaN: not known) is a meaningful value, written to JSON as null
  /// Measured in the follower coordinate q: `unit` is a translating
  /// follower's, an arm's is rad (coordinate_units.h).
  bool in_coordinate = false;
};

/// Every metric once, in output order, as `a.field(name, value, info)` (the
/// field signature of json_archive.h's archives; MetricInfo takes the place of
/// the checks). Takes Metrics or const Metrics.
template <class A, class M>
requires std::is_same_v<std::remove_const_t<M>, Metrics>
void visit(A& a, M& m) {
  a.field("separation_fraction", m.separation_fraction, MetricInfo{"–"});
  a.field("max_separation_gap", m.max_separation_gap, MetricInfo{"m"});
  a.field("impact_count", m.impact_count, MetricInfo{"–"});
  a.field("max_impact_velocity", m.max_impact_velocity, MetricInfo{"m/s"});
  a.field("peak_contact_force", m.peak_contact_force, MetricInfo{"N"});
  a.field("min_contact_force", m.min_contact_force, MetricInfo{"N"});
  a.field("max_penetration", m.max_penetration, MetricInfo{"m"});
  a.field("max_kinematic_error", m.max_kinematic_error, MetricInfo{"m", false, true});
  a.field("separation_integral", m.separation_integral, MetricInfo{"m s"});
  a.field("energy_residual", m.energy_residual, MetricInfo{"–"});
  a.field("max_pressure_angle_deg", m.max_pressure_angle_deg, MetricInfo{"deg"});
  a.field("min_radius_of_curvature", m.min_radius_of_curvature, MetricInfo{"m"});
  a.field("jump_speed_rpm", m.jump_speed_rpm, MetricInfo{"rpm", true});
  a.field("peak_cam_torque", m.peak_cam_torque, MetricInfo{"N m"});
  a.field("rms_cam_torque", m.rms_cam_torque, MetricInfo{"N m"});
  a.field("mean_drive_power", m.mean_drive_power, MetricInfo{"W", true});
  a.field("peak_contact_stress", m.peak_contact_stress, MetricInfo{"Pa"});
  a.field("peak_spring_stress", m.peak_spring_stress, MetricInfo{"Pa"});
  a.field("max_face_excursion", m.max_face_excursion, MetricInfo{"m"});
  a.field("float_fraction", m.float_fraction, MetricInfo{"–"});
  a.field("max_float_gap", m.max_float_gap, MetricInfo{"m"});
}

/// Whether a run lets go where a jump is judged (docs/valvetrain.md): the
/// cam contact floats, or a link opens off every seat in float. Take-up
/// and seat bounces have their own metrics; without a seat every
/// separation is float.
inline bool separates(const Metrics& m) {
  const bool link = m.train && m.train->link_float_fraction > 0.0;
  return m.float_fraction.value_or(m.separation_fraction) > 0.0 || link;
}

/// Where a run lets go, for speed limits: "float" (the cam contact), "link"
/// (a link off every seat), or empty where it does not.
inline const char* separation_place(const Metrics& m) {
  if (m.float_fraction.value_or(m.separation_fraction) > 0.0) return "float";
  if (m.train && m.train->link_float_fraction > 0.0) return "link";
  return "";
}

/// Every scalar metric of a follower train that its scene has, in output
/// order, as f(name, value, count, unit) with a double value, whether it is a
/// count (a whole number, written as an integer where the format has one) and
/// its unit as the report's table prints it (an arm's forces are N m):
/// the one list summary.json, the C++ API and Python write (the per-body
/// lift errors and `separates_first` are written beside it).
template <class F>
void for_each_train_metric(const TrainMetrics& t, F&& f) {
  if (t.links) {
    f("min_link_force", t.min_link_force, false, "N");
    f("link_separation_fraction", t.link_separation_fraction, false, "–");
  }
  if (t.seats) {
    f("max_seating_velocity", t.max_seating_velocity, false, "m/s");
    f("seat_impacts", static_cast<double>(t.seat_impacts), true, "–");
  }
  if (t.springs) f("peak_spring_force", t.peak_spring_force, false, "N");
  if (t.gas) f("peak_gas_force", t.peak_gas_force, false, "N");
  if (t.clash) f("coil_clashes", static_cast<double>(t.coil_clashes), true, "–");
  if (t.lash) {
    f("take_up_bounces", static_cast<double>(t.take_up_bounces), true, "–");
    f("seat_bounces", static_cast<double>(t.seat_bounces), true, "–");
    f("max_seat_bounce_height", t.max_seat_bounce_height, false, "m");
    if (t.links) f("link_float_fraction", t.link_float_fraction, false, "–");
  }
}

/// Every train metric's name, in for_each_train_metric's order, as for a
/// train with every element (compare's columns: a scene without the element
/// leaves its cell empty).
inline std::vector<std::string> train_metric_names() {
  TrainMetrics all;
  all.links = all.seats = all.springs = all.gas = all.clash = all.lash = true;
  std::vector<std::string> names;
  for_each_train_metric(all, [&](const char* name, double, bool, const char*) { names.emplace_back(name); });
  return names;
}

namespace metrics_detail {
template <class F>
struct CallbackArchive {
  F& f;
  template <class T>
  void field(const char* name, T& value, const MetricInfo& info) {
    f(name, value, info);
  }
};
}  // namespace metrics_detail

/// `visit` for a callable: f(const char* name, T& value, const MetricInfo& info)
/// with T = long, double or std::optional<double> (const when `m` is; an
/// optional one is a metric that does not apply to every scene: left out
/// where empty, see metric_value).
template <class M, class F>
void for_each_metric(M& m, F&& f) {
  metrics_detail::CallbackArchive<std::remove_reference_t<F>> a{f};
  visit(a, m);
}

/// A metric's value as a number, or none where it does not apply (an empty optional).
template <class T>
std::optional<double> metric_value(const T& value) {
  if constexpr (std::is_same_v<T, std::optional<double>>)
    return value;
  else
    return static_cast<double>(value);
}

/// The metric names in output order.
inline std::vector<std::string> metric_names() {
  std::vector<std::string> names;
  const Metrics none;
  for_each_metric(none, [&](const char* name, const auto&, const MetricInfo&) { names.emplace_back(name); });
  return names;
}

}  // namespace camdyn
