// The scene: the plain typed description of a cam-follower mechanism and how
// to run it, one struct per JSON object of docs/config.md. It is
// the bottom layer that geometry, contact and dynamics take their inputs from;
// io/config.{h,cc} reads it from JSON (and prints it back), turning every word
// a config chooses by name into one of the enums below, once, at load.
// Defaults live in the member initialisers (and nowhere else).
#pragma once

#include <optional>
#include <span>
#include <string>
#include <vector>

#include "scene/enum_names.h"

namespace camdyn {

// ---------------------------------------------------------------- vocabulary
// Every choice a config makes by name is one of these enums; the words of
// docs/config.md are in each table (enum_names.h), read once at load.

/// `unset` only before a config has named it (the field is required).
enum class SegmentType { unset, rise, dwell, return_ };
inline constexpr EnumName<SegmentType> kSegmentTypeNames[] = {{SegmentType::unset, ""},
                                                              {SegmentType::rise, "rise"},
                                                              {SegmentType::dwell, "dwell"},
                                                              {SegmentType::return_, "return"}};
constexpr std::span<const EnumName<SegmentType>> enum_names(SegmentType) { return kSegmentTypeNames; }

/// The law of a rise or return segment; `none` on a dwell.
enum class SegmentLaw {
  none,
  cycloidal,
  polynomial_345,
  polynomial_4567,
  harmonic,
  modified_trapezoid,
  modified_sine,
  spline
};
inline constexpr EnumName<SegmentLaw> kSegmentLawNames[] = {{SegmentLaw::none, ""},
                                                            {SegmentLaw::cycloidal, "cycloidal"},
                                                            {SegmentLaw::polynomial_345, "polynomial_345"},
                                                            {SegmentLaw::polynomial_4567, "polynomial_4567"},
                                                            {SegmentLaw::harmonic, "harmonic"},
                                                            {SegmentLaw::modified_trapezoid, "modified_trapezoid"},
                                                            {SegmentLaw::modified_sine, "modified_sine"},
                                                            {SegmentLaw::spline, "spline"}};
constexpr std::span<const EnumName<SegmentLaw>> enum_names(SegmentLaw) { return kSegmentLawNames; }

/// The motor of a shaft drive: constant speed, or a torque falling linearly with speed.
enum class Motor { constant_speed, torque_speed };
inline constexpr EnumName<Motor> kMotorNames[] = {{Motor::constant_speed, "constant_speed"},
                                                  {Motor::torque_speed, "torque_speed"}};
constexpr std::span<const EnumName<Motor>> enum_names(Motor) { return kMotorNames; }

/// The cam at constant speed, or behind a torsionally compliant camshaft.
enum class Drive { constant_speed, shaft };
inline constexpr EnumName<Drive> kDriveNames[] = {{Drive::constant_speed, "constant_speed"}, {Drive::shaft, "shaft"}};
constexpr std::span<const EnumName<Drive>> enum_names(Drive) { return kDriveNames; }

enum class RotationDirection { ccw, cw };
inline constexpr EnumName<RotationDirection> kRotationDirectionNames[] = {{RotationDirection::ccw, "ccw"},
                                                                          {RotationDirection::cw, "cw"}};
constexpr std::span<const EnumName<RotationDirection>> enum_names(RotationDirection) { return kRotationDirectionNames; }

/// What each shape is (contact element, rolling, label, its config fields):
/// scene/follower_shape.h, the one switch over this enum.
enum class FollowerShape { roller, flat, mushroom };
inline constexpr EnumName<FollowerShape> kFollowerShapeNames[] = {
    {FollowerShape::roller, "roller"}, {FollowerShape::flat, "flat"}, {FollowerShape::mushroom, "mushroom"}};
constexpr std::span<const EnumName<FollowerShape>> enum_names(FollowerShape) { return kFollowerShapeNames; }

enum class FollowerMotion { translating, oscillating };
inline constexpr EnumName<FollowerMotion> kFollowerMotionNames[] = {{FollowerMotion::translating, "translating"},
                                                                    {FollowerMotion::oscillating, "oscillating"}};
constexpr std::span<const EnumName<FollowerMotion>> enum_names(FollowerMotion) { return kFollowerMotionNames; }

/// How Coulomb friction is smoothed through zero slip: μ tanh(v/v_reg) or a linear ramp.
enum class FrictionRegularization { tanh, linear };
inline constexpr EnumName<FrictionRegularization> kFrictionRegularizationNames[] = {
    {FrictionRegularization::tanh, "tanh"}, {FrictionRegularization::linear, "linear"}};
constexpr std::span<const EnumName<FrictionRegularization>> enum_names(FrictionRegularization) {
  return kFrictionRegularizationNames;
}

/// Normal contact force laws of docs/model.md §3 (contact/force_law.h).
enum class ContactModel { hertz, kelvin_voigt, hunt_crossley, lankarani_nikravesh, flores };
inline constexpr EnumName<ContactModel> kContactModelNames[] = {
    {ContactModel::hertz, "hertz"},
    {ContactModel::kelvin_voigt, "kelvin_voigt"},
    {ContactModel::hunt_crossley, "hunt_crossley"},
    {ContactModel::lankarani_nikravesh, "lankarani_nikravesh"},
    {ContactModel::flores, "flores"}};
constexpr std::span<const EnumName<ContactModel>> enum_names(ContactModel) { return kContactModelNames; }

/// How the contact pair parameter follows the motion (docs/model.md §2).
enum class Tracking { differential, newton };
inline constexpr EnumName<Tracking> kTrackingNames[] = {{Tracking::differential, "differential"},
                                                        {Tracking::newton, "newton"}};
constexpr std::span<const EnumName<Tracking>> enum_names(Tracking) { return kTrackingNames; }

/// `contact.pair_form`: "auto" = the one-parameter reduction for a circle or
/// line follower; "general" = the two-parameter common-normal tracker of
/// docs/model.md §2 (verification).
enum class PairFormChoice { automatic, general };
inline constexpr EnumName<PairFormChoice> kPairFormChoiceNames[] = {{PairFormChoice::automatic, "auto"},
                                                                    {PairFormChoice::general, "general"}};
constexpr std::span<const EnumName<PairFormChoice>> enum_names(PairFormChoice) { return kPairFormChoiceNames; }

enum class IntegrationMethod { cvode_bdf, cvode_adams, arkode_erk, arkode_dirk, rk4, dop853 };
inline constexpr EnumName<IntegrationMethod> kIntegrationMethodNames[] = {
    {IntegrationMethod::cvode_bdf, "cvode_bdf"},
    {IntegrationMethod::cvode_adams, "cvode_adams"},
    {IntegrationMethod::arkode_erk, "arkode_erk"},
    {IntegrationMethod::arkode_dirk, "arkode_dirk"},
    {IntegrationMethod::rk4, "rk4"},
    {IntegrationMethod::dop853, "dop853"}};
constexpr std::span<const EnumName<IntegrationMethod>> enum_names(IntegrationMethod) { return kIntegrationMethodNames; }

/// Where an implicit method's Jacobian comes from.
enum class JacobianSource { analytic, finite_difference };
inline constexpr EnumName<JacobianSource> kJacobianSourceNames[] = {
    {JacobianSource::analytic, "analytic"}, {JacobianSource::finite_difference, "finite_difference"}};
constexpr std::span<const EnumName<JacobianSource>> enum_names(JacobianSource) { return kJacobianSourceNames; }

/// How the follower's free flights are advanced: "closed_form" (the exact
/// solution of the linear flight, the integrator only for the contact phases;
/// where the flight is not linear — a shaft drive, the general pair form —
/// the integrator takes it anyway) or "integrated" (the integrator throughout).
enum class FlightMethod { closed_form, integrated };
inline constexpr EnumName<FlightMethod> kFlightMethodNames[] = {{FlightMethod::closed_form, "closed_form"},
                                                                {FlightMethod::integrated, "integrated"}};
constexpr std::span<const EnumName<FlightMethod>> enum_names(FlightMethod) { return kFlightMethodNames; }

/// "energy": the energy residual only; "richardson": also the difference to a
/// run at a 100× tighter tolerance (costs that second run).
enum class ErrorEstimateMethod { energy, richardson };
inline constexpr EnumName<ErrorEstimateMethod> kErrorEstimateMethodNames[] = {
    {ErrorEstimateMethod::energy, "energy"}, {ErrorEstimateMethod::richardson, "richardson"}};
constexpr std::span<const EnumName<ErrorEstimateMethod>> enum_names(ErrorEstimateMethod) {
  return kErrorEstimateMethodNames;
}

// ---------------------------------------------------------------- motion law

/// One segment of a piecewise motion law (`mechanism.cam.motion_law.segments[i]`).
struct SegmentConfig {
  SegmentType type = SegmentType::unset;
  SegmentLaw law = SegmentLaw::none;   ///< rise/return only (none on a dwell)
  double end_deg = 0.0;                ///< cam angle where the segment ends [deg], in (start, 360]
  std::optional<double> lift;          ///< rise/return: lift magnitude [m] (translating follower)
  std::optional<double> lift_deg;      ///< rise/return: arm rotation [deg] (oscillating follower)
  int degree = 5;                      ///< spline only: polynomial degree (>= 3)
  std::vector<double> control_points;  ///< spline only: free interior control points,
                                       ///< normalised lift (0 = segment start, 1 = end)

  bool operator==(const SegmentConfig&) const = default;
};

/// Whole-cycle periodic spline through given lifts (`motion_law.spline`).
struct PeriodicSplineConfig {
  int degree = 5;
  std::vector<double> knots_deg;  ///< increasing, within [0, 360)
  std::vector<double> lift;       ///< [m], one per knot

  bool operator==(const PeriodicSplineConfig&) const = default;
};

/// Whole-cycle lift table read from CSV (`motion_law.table`).
struct TableConfig {
  std::string file;  ///< relative to the config file that names it (resolved to absolute on load)
  std::string angle_column = "angle_deg";
  std::string lift_column = "lift";
  int degree = 5;
  /// The table's rows, read from `file` by the loader (io/config.h
  /// load_table_rows), not serialised: cam angle [deg], lift [m], and the
  /// 1-based line of each row in `file` (for messages).
  std::vector<double> angle_deg, lift;
  std::vector<int> lines;

  bool operator==(const TableConfig&) const = default;
};

/// A cam given directly as a closed list of contour points (`motion_law.contour`),
/// fitted with a smooth periodic B-spline (geometry/contour_cam.h); the follower
/// motion law is then the rigid follower's lift on that contour.
struct ContourConfig {
  std::vector<std::vector<double>> points;  ///< [[x, y], ...] in the cam frame at cam angle 0 [m], in order
  int degree = 5;                           ///< spline degree, in [3, 7]
  int control_points = 0;                   ///< per coordinate; 0 = automatic (N/2 within [2(degree + 1), 400])
  double smoothing = 0.0;                   ///< third-difference penalty weight λ >= 0 (0 = plain least squares)
  int parameter_corrections = 4;            ///< foot-point projection / refit rounds, >= 0

  bool operator==(const ContourConfig&) const = default;
};

/// `motion_law.event`: the law on [from_deg, to_deg] replaced by one clamped
/// spline (geometry/event_spline.h) whose joins match the rest of the law up
/// to s'' (s''' from degree 4 on); the rest is kept bit for bit.
struct EventSplineConfig {
  double from_deg = 0.0;               ///< start of the replaced span [deg], in [0, 360)
  double to_deg = 0.0;                 ///< its end [deg], in (from_deg, 360]
  int degree = 5;                      ///< 3 … 9
  std::vector<double> control_points;  ///< the free control points: lift values [m] (arm: [rad])

  bool operator==(const EventSplineConfig&) const = default;
};

/// Exactly one of `segments`, `spline`, `table`, `contour` is set after loading.
struct MotionLawConfig {
  std::vector<SegmentConfig> segments;
  std::optional<PeriodicSplineConfig> spline;
  std::optional<TableConfig> table;
  std::optional<ContourConfig> contour;
  std::optional<EventSplineConfig> event;  ///< with segments, spline or table: the event replaced by a spline
  std::string source;  ///< profile file it came from, if given as "profiles/NAME.json" (not serialised)

  bool operator==(const MotionLawConfig&) const = default;
};

// ---------------------------------------------------------------- mechanism

/// The motor of a shaft drive (`mechanism.cam.drive.motor`).
struct MotorConfig {
  Motor type = Motor::constant_speed;  ///< constant_speed: motor angle = ω t at cam.rpm
  double stall_torque = 0.0;           ///< torque_speed: T₀ at zero speed [N m], > 0
  double no_load_rpm = 0.0;            ///< torque_speed: speed where the torque falls to 0 [rpm], > 0
  double inertia = 0.0;                ///< torque_speed: rotor inertia J_m [kg m^2], > 0

  bool operator==(const MotorConfig&) const = default;
};

/// `mechanism.cam.drive`: the cam at constant speed, or a camshaft degree of
/// freedom driven through a torsionally compliant shaft.
struct DriveConfig {
  Drive type = Drive::constant_speed;
  double inertia = 0.0;              ///< shaft: cam + camshaft inertia J_c [kg m^2], > 0
  double torsional_stiffness = 0.0;  ///< shaft: k_s between motor and cam [N m/rad], > 0
  double torsional_damping = 0.0;    ///< shaft: c_s [N m s/rad], >= 0
  MotorConfig motor;                 ///< shaft: the motor

  bool operator==(const DriveConfig&) const = default;
};

/// `mechanism.cam.limits`: what the cam must meet to be made, checked when the
/// model is built (so `camdyn validate` and `camdyn run` refuse a cam that
/// breaks one, exit 2). null: no limit. An optimize study writes the
/// geometric constraints its design meets into optimized.json here.
struct CamLimitsConfig {
  std::optional<double> max_pressure_angle_deg;   ///< max |φ| over the cycle [deg]
  std::optional<double> min_radius_of_curvature;  ///< min |ρ| of the cam contour [m]
  std::optional<double> max_peak_jerk;            ///< max |d³s/dθ³| [m/rad³ or rad/rad³]
  /// max Hertz line-contact pressure of the rigid-model contact force at the scene's speed [Pa]
  std::optional<double> max_contact_stress;

  bool operator==(const CamLimitsConfig&) const = default;
};

struct CamConfig {
  double base_radius = 0.0;  ///< r_b [m], > 0; left out for a contour cam (derived from its points)
  double rpm = 0.0;          ///< cam speed [rev/min], >= 0 (0 holds the cam still)
  RotationDirection direction = RotationDirection::ccw;
  double initial_angle_deg = 0.0;  ///< cam angle at t = 0 [deg]
  MotionLawConfig motion_law;
  DriveConfig drive;
  CamLimitsConfig limits;

  bool operator==(const CamConfig&) const = default;
};

struct ShapeConfig {
  FollowerShape type = FollowerShape::roller;
  double radius = 0.0;      ///< roller / mushroom: r_r or R [m], > 0
  double inertia = 0.0;     ///< roller: spin inertia about its axle [kg m^2], >= 0
  double face_width = 0.0;  ///< flat: width of the face [m], > 0

  bool operator==(const ShapeConfig&) const = default;
};

/// `spring.clash`: coil clash of a spring with mass (docs/model.md §12): the
/// spring closes by (coils + 1) gap beyond its installed length before its
/// coils touch (its clearance to solid, whatever `lumps`); each of its
/// lumps + 1 segments then meets a stiff linear contact after its share,
/// (coils + 1) gap / (lumps + 1).
struct CoilClashConfig {
  double gap = 0.0;        ///< clearance to solid per coil segment: (coils + 1) gap in all [m], > 0
  double stiffness = 0.0;  ///< stiffness of the closed coils [N/m], > 0

  bool operator==(const CoilClashConfig&) const = default;
};

struct SpringConfig {
  double stiffness = 0.0;  ///< k [N/m], >= 0
  double preload = 0.0;    ///< spring force at the lowest follower position [N], >= 0
  /// Mass of the spring [kg], >= 0: 0 is a massless spring; > 0 lumps it in
  /// `lumps` equal masses (the surge model of docs/model.md §12).
  std::optional<double> mass;
  std::optional<int> coils;              ///< active coils, >= 1 (required with mass > 0): the clash clearance
  std::optional<int> lumps;              ///< lumped masses, >= 1 (default: coils)
  std::optional<double> damping_ratio;   ///< of the first fixed-fixed surge mode [-], >= 0 (default 0.02)
  std::optional<CoilClashConfig> clash;  ///< coil clash (only with mass > 0)
  /// The wire's diameter d and the coils' mean diameter D [m] (both or
  /// neither, D > d): the wire's shear stress with the Wahl factor
  /// (`peak_spring_stress`, docs/model.md §12 "Spring stress").
  std::optional<double> wire_diameter, mean_diameter;

  static constexpr double kDefaultDampingRatio = 0.02;
  /// Whether the spring has mass (is lumped).
  bool massive() const { return mass.value_or(0.0) > 0.0; }
  /// The lumped masses N of a spring with mass: `lumps`, else `coils` (as before `lumps`).
  int lump_count() const { return lumps.value_or(coils.value_or(1)); }
  /// The clash gap of one of the lump_count() + 1 segments [m]: the spring's
  /// clearance to solid, (coils + 1) gap, shared equally (gap itself when
  /// lumps = coils).
  double segment_clash_gap() const {
    const double share = static_cast<double>(coils.value_or(1) + 1) / static_cast<double>(lump_count() + 1);
    return clash ? clash->gap * share : 0.0;
  }

  bool operator==(const SpringConfig&) const = default;
};

/// `seat` / `stop`: a one-sided contact of a body against the frame at
/// `position` (docs/model.md §12), with the force laws of the cam contact.
/// A seat holds the body from below (δ = position − x), a stop from above
/// (δ = x − position).
struct SeatConfig {
  double position = 0.0;  ///< [m] (an arm: [rad]), in the body's coordinate
  ContactModel model = ContactModel::lankarani_nikravesh;
  double stiffness = 0.0;            ///< K [N/m^n], > 0
  double exponent = 1.5;             ///< n [-], > 0
  double restitution = 0.8;          ///< target e [-], in (0, 1]
  std::optional<double> damping;     ///< kelvin_voigt c [N s/m]
  double reference_velocity = 0.01;  ///< floor of v0 [m/s], > 0

  bool operator==(const SeatConfig&) const = default;
};

/// `link`: how a train body is driven by the body before it (docs/model.md §12).
struct LinkConfig {
  double ratio = 1.0;      ///< lever ratio [m/m], or [m/rad] after an oscillating arm, > 0
  double stiffness = 0.0;  ///< K [N/m], > 0
  double damping = 0.0;    ///< c [N s/m], >= 0
  double lash = 0.0;       ///< clearance taken up before the link pushes [m], >= 0 (one-sided only)
  bool one_sided = true;   ///< false: a two-sided compliant joint (no lash)

  bool operator==(const LinkConfig&) const = default;
};

/// `gas`: a pressure acting on a train body against its opening (docs/model.md
/// §12, "Gas load"): F = −A (p(φ) − p_port), φ the crank angle =
/// crank_ratio × (cam angle − tdc_deg), p read from a CSV table (columns
/// `crank_deg`, `pressure`) and repeated every cam turn (360 × crank_ratio
/// crank degrees).
struct GasLoadConfig {
  double area = 0.0;                 ///< A [m²], > 0
  std::string pressure;              ///< the table's CSV file, relative to the config (resolved on load)
  double crank_ratio = 2.0;          ///< crank turns per cam turn [-], > 0
  double tdc_deg = 0.0;              ///< cam angle where the crank angle is 0 [deg], in [0, 360)
  double port_pressure = 1.01325e5;  ///< p_port, the pressure behind the body [Pa], >= 0
  /// The table's rows, read from `pressure` by the loader (io/config.h
  /// load_table_rows), not serialised: crank angle [deg], pressure [Pa], and
  /// the 1-based line of each row in the file (for messages).
  std::vector<double> crank_deg, pressure_pa;
  std::vector<int> lines;

  bool operator==(const GasLoadConfig&) const = default;
};

/// One body of `mechanism.train`, after the follower.
struct TrainBodyConfig {
  std::string name;                  ///< column prefix in timeseries.csv; unique, not "follower"
  double mass = 0.0;                 ///< [kg], > 0
  double damping = 0.0;              ///< viscous damper to the frame [N s/m], >= 0
  LinkConfig link;                   ///< from the body before it
  SpringConfig spring;               ///< return spring to the frame (optional: zero stiffness and preload)
  std::optional<SeatConfig> seat;    ///< lower end of travel
  std::optional<SeatConfig> stop;    ///< upper end of travel
  std::optional<GasLoadConfig> gas;  ///< a gas load against its opening

  bool operator==(const TrainBodyConfig&) const = default;
};

struct InitialConfig {
  std::optional<double> position;  ///< displacement above the lowest position [m]; null = on the law, in equilibrium
  double velocity = 0.0;           ///< along the follower axis, + away from the cam [m/s]

  bool operator==(const InitialConfig&) const = default;
};

/// Guide friction of a translating follower: μ_g |side load| opposing ẏ.
struct GuideFrictionConfig {
  double mu = 0.0;                        ///< μ_g [-], >= 0
  double regularization_velocity = 1e-4;  ///< [m/s], > 0

  bool operator==(const GuideFrictionConfig&) const = default;
};

/// Pivot friction of an oscillating follower: μ_p r_pin |contact force| opposing φ̇.
struct PivotFrictionConfig {
  double mu = 0.0;                        ///< μ_p [-], >= 0
  double pin_radius = 0.0;                ///< r_pin [m], > 0
  double regularization_velocity = 1e-4;  ///< sliding speed at the pin surface [m/s], > 0

  bool operator==(const PivotFrictionConfig&) const = default;
};

struct FollowerConfig {
  FollowerMotion motion = FollowerMotion::translating;
  double offset = 0.0;        ///< translating: the follower axis is the line x = e [m]
  std::vector<double> pivot;  ///< oscillating: [x, y] of the arm pivot, cam frame at angle 0 [m]
  double arm_length = 0.0;    ///< oscillating: pivot to roller centre (flat: to the face centre) [m], > 0
  ShapeConfig shape;
  double mass = 0.0;                                  ///< translating: m [kg], > 0
  double inertia = 0.0;                               ///< oscillating: arm inertia about the pivot [kg m^2], > 0
  SpringConfig spring;                                ///< oscillating: torsional, stiffness [N m/rad] and preload [N m]
  double damping = 0.0;                               ///< viscous damper c [N s/m] (oscillating [N m s/rad]), >= 0
  std::optional<GuideFrictionConfig> guide_friction;  ///< translating only
  std::optional<PivotFrictionConfig> pivot_friction;  ///< oscillating only
  InitialConfig initial;                              ///< oscillating: position [rad], velocity [rad/s]
  std::optional<SeatConfig> seat;  ///< above the base-circle contact position: valve lash (docs/model.md §12)
  std::optional<SeatConfig> stop;  ///< upper end of travel
  /// `lash`: the cam's travel from the base circle before the valve moves [m]
  /// (an arm: [rad]), >= 0; put on the follower's seat or on the link into
  /// the first seated train body (docs/config.md, "follower.lash").
  std::optional<double> lash;

  /// The seat `lash` gives a follower that has no `seat` block: a stiff valve seat.
  static SeatConfig default_lash_seat() {
    SeatConfig s;
    s.model = ContactModel::hunt_crossley;
    s.stiffness = 1e9;  // [N/m]
    s.exponent = 1.0;
    s.restitution = 0.3;
    return s;
  }

  bool operator==(const FollowerConfig&) const = default;
};

/// Contact stiffness estimated from materials (Hertz / line contact).
struct MaterialsConfig {
  double E1 = 0.0, nu1 = 0.3;   ///< cam: Young's modulus [Pa], Poisson ratio [-]
  double E2 = 0.0, nu2 = 0.3;   ///< follower
  std::optional<double> width;  ///< contact width [m]: given = line contact (n = 1), else point contact (n = 1.5)

  bool operator==(const MaterialsConfig&) const = default;
};

struct FrictionConfig {
  double mu = 0.0;                        ///< Coulomb coefficient [-], >= 0
  double regularization_velocity = 1e-4;  ///< v_reg [m/s], > 0
  FrictionRegularization regularization = FrictionRegularization::tanh;

  bool operator==(const FrictionConfig&) const = default;
};

struct ContactConfig {
  ContactModel model = ContactModel::lankarani_nikravesh;
  std::optional<double> stiffness;                ///< K [N/m^n]; exactly one of stiffness / from_materials
  std::optional<MaterialsConfig> from_materials;  ///< JSON: "stiffness": { "from_materials": {...} }
  double exponent = 1.5;                          ///< n [-], > 0
  double restitution = 0.8;                       ///< target e [-], in (0, 1]
  std::optional<double> damping;                  ///< kelvin_voigt c [N s/m]
  double reference_velocity = 0.01;               ///< floor of v0 [m/s], > 0
  FrictionConfig friction;
  Tracking tracking = Tracking::differential;
  PairFormChoice pair_form = PairFormChoice::automatic;

  bool operator==(const ContactConfig&) const = default;
};

struct MechanismConfig {
  CamConfig cam;
  FollowerConfig follower;
  ContactConfig contact;
  std::vector<TrainBodyConfig> train;  ///< bodies after the follower, in order (docs/model.md §12)

  bool operator==(const MechanismConfig&) const = default;
};

// ---------------------------------------------------------------- run control

struct SimulationConfig {
  std::optional<double> cycles;           ///< cam revolutions (default 4 when rpm > 0)
  int discard_cycles = 1;                 ///< transient revolutions left out of the metrics
  std::optional<double> duration;         ///< [s]; required when rpm = 0, replaces cycles
  std::optional<double> output_step_deg;  ///< time-series step in cam angle [deg] (default 0.5)
  std::optional<double> output_step;      ///< time-series step [s] (required instead when rpm = 0)
  /// Report the metrics over one period of the periodic orbit the run settles
  /// on (the periodic study's shooting from the run's end) instead of over the
  /// evaluated window, when a stable orbit is found.
  bool steady_state = false;

  /// Filled in by scene_from_json when rpm > 0 and neither cycles nor duration
  /// (resp. neither output step) is given, so the resolved config shows them.
  static constexpr double kDefaultCycles = 4.0;
  static constexpr double kDefaultOutputStepDeg = 0.5;

  bool operator==(const SimulationConfig&) const = default;
};

/// The Runge–Kutta orders `integrator.order` offers (ARKStepSetOrder picks
/// ARKODE's default table of that order; docs/config.md "integrator").
inline constexpr int kErkOrders[] = {2, 3, 4, 5, 6, 8};
inline constexpr int kDirkOrders[] = {2, 3, 4, 5};

struct IntegratorConfig {
  IntegrationMethod method = IntegrationMethod::cvode_bdf;  ///< rk4 needs `step`
  std::optional<int> order;                                 ///< arkode_erk / arkode_dirk; null: ARKODE's default, 4
  double rtol = 1e-8;                                       ///< relative tolerance, in (0, 0.1]
  double atol = 1e-12;                                      ///< absolute tolerance, > 0
  std::optional<double> max_step;                           ///< [s]
  std::optional<double> step;                               ///< fixed step for rk4 [s]
  long max_steps = 5'000'000;                               ///< step budget for the whole run
  double max_wall_time_s = 600.0;                           ///< wall-time budget for one run [s]
  JacobianSource jacobian = JacobianSource::analytic;       ///< implicit methods
  ErrorEstimateMethod error_estimate = ErrorEstimateMethod::energy;
  FlightMethod flight = FlightMethod::closed_form;

  bool operator==(const IntegratorConfig&) const = default;
};

// ---------------------------------------------------------------- outputs

/// A file format of the exported cam profile (docs/export.md).
enum class ProfileFormat { csv, dxf };
inline constexpr EnumName<ProfileFormat> kProfileFormatNames[] = {{ProfileFormat::csv, "csv"},
                                                                  {ProfileFormat::dxf, "dxf"}};
constexpr std::span<const EnumName<ProfileFormat>> enum_names(ProfileFormat) { return kProfileFormatNames; }

/// `outputs.profile`: the cam written out for manufacturing (profile.csv,
/// profile.dxf; output/profile_export.h). Lengths in millimetres, as in the files.
struct ProfileOutputConfig {
  std::vector<ProfileFormat> formats = {ProfileFormat::csv, ProfileFormat::dxf};
  std::optional<int> points;                 ///< N points at equal cam-angle steps; null = by chord tolerance
  std::optional<double> chord_tolerance_mm;  ///< largest sagitta between consecutive points [mm], > 0;
                                             ///< filled in (kDefaultChordToleranceMm) when `points` is null
  std::optional<double> cutter_radius_mm;    ///< R_t > 0 [mm]: also write the tool-centre path; null = none

  static constexpr double kDefaultChordToleranceMm = 0.001;
  static constexpr double kMinChordToleranceMm = 1e-6;  ///< 1 nm: finer only multiplies the points
  static constexpr int kMinPoints = 8, kMaxPoints = 1'000'000;

  bool operator==(const ProfileOutputConfig&) const = default;
};

/// Where `outputs.valvetrain`'s figures are taken (docs/valvetrain.md): at the
/// valve (the last body of the follower train, the follower without one) or
/// at the cam (the motion law).
enum class ValvetrainAt { valve, cam };
inline constexpr EnumName<ValvetrainAt> kValvetrainAtNames[] = {{ValvetrainAt::valve, "valve"},
                                                                {ValvetrainAt::cam, "cam"}};
constexpr std::span<const EnumName<ValvetrainAt>> enum_names(ValvetrainAt) { return kValvetrainAtNames; }

/// Which valve a lobe drives: names its timing events (IVO/IVC or EVO/EVC).
enum class ValveKind { intake, exhaust };
inline constexpr EnumName<ValveKind> kValveKindNames[] = {{ValveKind::intake, "intake"},
                                                          {ValveKind::exhaust, "exhaust"}};
constexpr std::span<const EnumName<ValveKind>> enum_names(ValveKind) { return kValveKindNames; }

/// `outputs.valvetrain`: valvetrain conventions in summary.json and the report
/// (geometry/valve_timing.h, docs/valvetrain.md).
struct ValvetrainOutputConfig {
  ValvetrainAt at = ValvetrainAt::valve;  ///< the figures at the valve (default) or at the cam
  double crank_ratio = 2.0;               ///< crank revolutions per cam revolution, > 0 (2: a four-stroke engine) [-]
  double tdc_deg = 0.0;                   ///< cam angle of the crank's TDC (the gas-exchange TDC) [deg], in [0, 360)
  std::optional<ValveKind> valve;         ///< names the timing events; null: only the generic ATDC/BBDC figures
  /// Checking heights: lifts above the datum (the valve's seat, the base circle) at which durations are
  /// measured [m], each > 0.
  std::vector<double> checking_heights = {kDefaultCheckingHeight};
  /// Cam angles [deg] where the opening ramp ends and the closing ramp starts,
  /// for laws that do not mark their ramps as pieces (a spline or table); empty = from the law's pieces.
  std::vector<double> ramp_end_deg;

  static constexpr double kDefaultCheckingHeight = 0.001;  ///< 1 mm [m]

  bool operator==(const ValvetrainOutputConfig&) const = default;
};

/// `outputs`: optional files besides a study's own.
struct OutputsConfig {
  std::optional<ProfileOutputConfig> profile;        ///< null (default): no profile files
  std::optional<ValvetrainOutputConfig> valvetrain;  ///< null (default): no valvetrain figures

  bool operator==(const OutputsConfig&) const = default;
};

/// A complete `simulate` scene.
struct SceneConfig {
  std::string name = "camdyn";
  std::string study = "simulate";
  MechanismConfig mechanism;
  double gravity = 0.0;  ///< acceleration pulling the follower towards the cam (-y) [m/s^2]
  SimulationConfig simulation;
  IntegratorConfig integrator;
  OutputsConfig outputs;

  bool operator==(const SceneConfig&) const = default;
};

}  // namespace camdyn
