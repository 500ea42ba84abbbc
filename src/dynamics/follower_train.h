// The follower train (docs/model.md §12): the bodies after the follower, the
// lumped masses of springs with mass, and the one-dimensional compliant
// elements between them and the frame — links, seats, stops, spring segments,
// coil clash, dampers. Every element is one TrainElement: a compression d
// linear in two coordinates and a force F(d, ḋ) pushing them apart, so that
// the right-hand side, the Jacobian, the events, the energy terms and the
// outputs loop over one list. Coordinate 0 is the follower's q (its own
// forces and the cam contact stay in dynamics/model.cc); the others have
// their position and velocity in the state after the follower's states.
// A scene without a seat, a stop, a spring with mass or a train body has an
// empty train, and the model is today's to the bit.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "contact/force_law.h"
#include "dynamics/state_layout.h"
#include "scene/scene.h"

namespace camdyn {

/// What an element is, for its outputs, events and metrics.
enum class TrainRole { link, seat, stop, spring, spring_segment, clash, damper, gas };

/// A gas load's pressure table (docs/model.md §12, "Gas load"): p against
/// the crank angle φ = crank_ratio (θ − θ_TDC), linear between rows and repeated every
/// cam turn (360 crank_ratio crank degrees), on an area A against the
/// pressure behind the body p_port.
struct GasLoad {
  double area = 0.0;                        ///< A [m²]
  double crank_ratio = 2.0;                 ///< crank turns per cam turn [-]
  double tdc_deg = 0.0;                     ///< cam angle where the crank angle is 0 [deg]
  double port_pressure = 0.0;               ///< p_port [Pa]
  std::vector<double> crank_deg, pressure;  ///< rows: increasing, within one period [deg], [Pa]

  /// One cam turn in crank degrees.
  double period_deg() const { return 360.0 * crank_ratio; }
  /// A (p(φ) − p_port) at the cam angle θ [rad]: the force pushing the body
  /// towards its seat [N]; its θ-derivative [N/rad] into `d_theta` if given.
  double force(double theta, double* d_theta = nullptr) const;
};

/// One compliant element: compression d = ca x_a + cb x_b + offset (a, b
/// train coordinates; −1 the frame) [m], and a force F ≥ 0 (a spring's may
/// be any sign) pushing them apart: x_a receives −ca F, x_b −cb F (virtual work).
struct TrainElement {
  /// spring: F = preload + k d + c ḋ (two-sided, always on);
  /// one_sided: F = max(0, k d + c ḋ) while d > 0;
  /// contact: the cam contact's force laws, F(δ = d, δ̇ = ḋ, v₀);
  /// gas: F = A (p(θ) − p_port) of the train's gas load `gas`, a force
  /// given against the cam angle (external: its work is W_external).
  enum class Law { spring, one_sided, contact, gas };
  Law law = Law::spring;
  TrainRole role = TrainRole::spring;
  int body = 0;  ///< the body whose output it is (0: the follower)
  int a = -1, b = -1;
  double ca = 0.0, cb = 0.0, offset = 0.0;
  double preload = 0.0, stiffness = 0.0, damping = 0.0;  ///< [N], [N/m], [N s/m]
  ForceLaw contact;                                      ///< Law::contact only
  int root = -1;  ///< its root function among the train's (one-sided and contact elements)
  int gas = -1;   ///< Law::gas: its load in FollowerTrain::gas_loads
  // Derived once the train is built (build_follower_train), so that an
  // evaluation reads the state directly: the state indices of x_a, ẋ_a, x_b,
  // ẋ_b (−1: the frame) and a spring's energy at d = 0 measured from its free
  // length, F₀² / (2k) [J].
  int position_a = -1, velocity_a = -1, position_b = -1, velocity_b = -1;
  double rest_energy = 0.0;

  bool gap_root() const { return law == Law::one_sided || law == Law::contact; }
};

/// A train coordinate: the follower (coordinate 0, its states 0 and 1) or a
/// body or spring lump with its own states.
struct TrainCoordinate {
  int position = 0, velocity = 1;  ///< state indices
  double mass = 0.0;               ///< [kg] (the follower's inertia stays in Model::mass)
};

/// A body's outputs: what timeseries.csv and the metrics name it by.
struct TrainBody {
  std::string name;  ///< "follower" for coordinate 0
  int coordinate = 0;
  int link = -1, seat = -1, stop = -1, spring_end = -1, gas = -1;  ///< element indices (−1: none)
  double ratio = 1.0;                                              ///< the link's lever ratio (1 for the follower)
  double lash = 0.0;                                               ///< the link's lash [m]
  int spring_coils = 0, spring_lumps = 0;  ///< its spring with mass: active coils, lumped masses (0: none)
  double spring_stress_per_newton = 0.0;   ///< its spring wire's shear stress per newton [Pa/N] (0: not given)
};

/// Fixed capacities, so that evaluations and runs allocate nothing.
struct TrainLimits {
  static constexpr int kMaxBodies = 9;  ///< the follower and 8 train bodies
  static constexpr int kMaxCoordinates = 1 + StateLayout::kMaxTrain / 2;
  static constexpr int kMaxRoots = 96;
};

/// The train's forces and rates at one state (double).
struct TrainEvaluation {
  double follower_force = 0.0;                                      ///< generalised force of the train on q [N | N m]
  std::array<double, TrainLimits::kMaxCoordinates> rate{};          ///< velocity of every coordinate
  std::array<double, TrainLimits::kMaxCoordinates> acceleration{};  ///< of every coordinate but the follower's
  std::array<double, TrainLimits::kMaxBodies> position{}, velocity{}, link_force{}, seat_force{}, stop_force{},
      spring_force{}, gas_force{};  ///< per body: [m], [m/s], [N] (spring: at its frame end)
  std::array<double, TrainLimits::kMaxBodies>
      spring_peak_force{};                                       ///< per body: largest |F| of its spring's segments [N]
  std::array<bool, TrainLimits::kMaxBodies> seated{};            ///< resting on its seat (seat compressed)
  std::array<double, TrainLimits::kMaxRoots> gap{}, gap_rate{};  ///< −d, −ḋ of each one-sided element [m], [m/s]
  double kinetic = 0.0, potential = 0.0;                         ///< [J], bodies and lumps, all elements
  double power_damper = 0.0, power_hysteresis = 0.0;             ///< dissipated [W]
  double power_external = 0.0;                                   ///< delivered to the bodies by the gas loads [W]
};

/// Per-run data of the train: each contact element's approach speed v₀ [m/s].
struct TrainWorkspace {
  std::array<double, TrainLimits::kMaxRoots> v0{};
};

/// The assembled train.
struct FollowerTrain {
  std::vector<TrainCoordinate> coordinates;  ///< [0] the follower
  std::vector<TrainElement> elements;
  std::vector<TrainBody> bodies;        ///< [0] the follower
  std::vector<GasLoad> gas_loads;       ///< of the Law::gas elements
  int roots = 0;                        ///< root functions (one per one-sided or contact element)
  bool follower_spring_lumped = false;  ///< the follower's own spring has mass (taken out of FollowerForces)

  bool present() const { return !elements.empty(); }
  /// Whether some element is a force given against time or the cam angle
  /// (a gas load): the train then has no time-invariant linear part, and
  /// the closed forms that need one are off (docs/model.md §12).
  bool time_dependent() const { return !gas_loads.empty(); }
  /// Whether the train has bodies or lumps beyond the follower (states of its own).
  bool has_coordinates() const { return coordinates.size() > 1; }
  /// Whether some body has a seat.
  bool has_seat() const;
  /// Whether `body` rests on a seat: its own, or a later body's through
  /// closed links (a gap below it is then lash, docs/model.md §12). A body
  /// whose link to the next is open does not rest on the next one's seat.
  bool rests_on_seat(const TrainEvaluation& e, int body) const;
};

/// Builds the train of a scene and appends its states to `layout`.
/// `inertia` [kg | kg m²] is the follower's, `oscillating` whether its
/// coordinate is an angle. Throws InputError naming the field for a train
/// whose states exceed StateLayout's capacity.
FollowerTrain build_follower_train(const SceneConfig& scene, const std::string& file, StateLayout& layout);

/// The lash of an assembled train (docs/config.md, "follower.lash"): the
/// cam's travel from the base circle before the first train body with a
/// seat leaves it, (Λ + p_k) / (r₁ ⋯ r_k) with Λ the links' lash carried to
/// that body and p_k its seat's position, or the follower seat's position if
/// that is higher (without a seated train body: the follower seat's
/// position, 0 without one) [m | rad]; and how far the follower's seat then
/// holds that body off its seat [m] (0 when it rests on it).
struct TrainLash {
  double at_cam = 0.0;
  double held_open = 0.0;
  int body = -1;  ///< the seated train body (index into FollowerTrain::bodies), −1: none
};
TrainLash train_lash(const FollowerTrain& train);

/// Appends the names of the train's elements (summary.json `model.elements`):
/// "link:valve", "seat:follower", "spring:valve" (with mass: "spring:valve:8_coils",
/// lumped otherwise than one mass a coil: "spring:valve:8_coils:16_lumps"), ...
void add_train_names(const FollowerTrain& train, std::vector<std::string>& names);

/// Resets the per-run data.
void prepare_train_workspace(const FollowerTrain& train, TrainWorkspace& ws);

/// The train at a state and the cam angle θ [rad] (the gas loads'). Allocates nothing.
void evaluate_train(const FollowerTrain& train, const TrainWorkspace& ws, double theta, const double* x,
                    TrainEvaluation& e);

/// Writes the train coordinates' rates into x_dot (not the follower's).
void train_state_derivative(const FollowerTrain& train, const TrainEvaluation& e, double* x_dot);

/// Adds the train's entries to the column-major Jacobian of the state
/// derivative (n states): every element's ∂F/∂d, ∂F/∂ḋ into the rows of the
/// accelerations of the coordinates it acts on (the follower's row included),
/// and ∂ẋ/∂ẋ = 1 for the train's positions; a gas load's ∂F/∂θ into the
/// column of the cam angle's state `cam_angle_state` where it is one (−1:
/// the cam angle is a function of time).
void add_train_jacobian(const FollowerTrain& train, const TrainWorkspace& ws, double theta, int cam_angle_state,
                        const double* x, int n, double* jacobian);

/// Puts the train's coordinates (not the follower's) at rest in static
/// equilibrium for the follower's position x[0] (Newton on the elements'
/// static forces from the kinematic positions, the gas loads at the cam angle
/// θ [rad]). Returns whether it converged; where it did not, the coordinates
/// are left at their kinematic positions.
bool train_static_state(const FollowerTrain& train, const TrainWorkspace& ws, double theta, double* x);

/// Half-bandwidth of the state Jacobian of a model with `core_size` core
/// states (coupled among themselves, the follower's rate row with every
/// coordinate an element ties to the follower): the largest |i − j| of a
/// possibly nonzero ∂ẋ_i/∂x_j.
int train_jacobian_bandwidth(const FollowerTrain& train, int core_size);

/// The approach speed of element `root`'s gap at onset, stored as its v₀ (floored).
void record_train_onset(const FollowerTrain& train, TrainWorkspace& ws, int root, double approach);

/// The element of a root function.
const TrainElement& train_element_of_root(const FollowerTrain& train, int root);

}  // namespace camdyn
