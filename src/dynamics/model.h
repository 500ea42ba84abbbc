// The cam-follower mechanism as an ODE (docs/model.md §5): an immutable Model
// (built in dynamics/model_assembly.cc; its rigid-model jump speed is
// dynamics/rigid_jump_speed.h)
// assembled from the scene with only what the scene needs, a mutable
// Workspace reused across runs, and free functions that evaluate it
// (Pinocchio style). The state is, in this order and only where needed:
//   q [m | rad], q̇            follower coordinate (translating: y above its lowest
//                             position; oscillating: arm rotation φ) and its rate
//   u [rad]                   contact pair parameter, differential tracking only
//   v [rad | m]               follower profile parameter, general pair form with differential tracking only
//   Ω [rad/s]                 roller spin, only with roller inertia and friction
//   θ_c [rad], ω_c [rad/s]    cam angle and speed, shaft drive only
//   θ_m [rad], ω_m [rad/s]    motor angle and speed, torque–speed motor only
// The contact is a circle follower (roller, mushroom: its centre against the
// cam's centre curve, contact/point_curve_tracking.h) or a flat face (a line
// against the cam contour, contact/line_curve_tracking.h); either way against
// a PeriodicCurve, so a cam given as a contour plugs in unchanged. With
// `contact.pair_form: "general"` the same contact goes through the general
// two-parameter tracker (contact/profile_pair_tracking.h) instead: the cam
// contour against the follower's circle or face segment, for verification of
// the reductions (no follower shape needs it).
// Energy flows (drive work, damper, contact hysteresis, friction) are
// quadratures (docs/model.md §7), integrated beside the state.
#pragma once

#include <Eigen/Core>
#include <cassert>
#include <cstddef>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "contact/force_law.h"
#include "contact/friction.h"
#include "contact/hertz_pressure.h"
#include "contact/point_curve_tracking.h"
#include "dynamics/cam_geometry.h"
#include "dynamics/follower_forces.h"
#include "dynamics/follower_train.h"
#include "dynamics/friction_elements.h"
#include "dynamics/root_roles.h"
#include "dynamics/separation_cause.h"
#include "dynamics/shaft_drive.h"
#include "dynamics/state_layout.h"
#include "scene/scene.h"

namespace camdyn {

/// The index of each of a run's quadratures (Model::kQuadratures, docs/model.md §7).
namespace quadrature {
inline constexpr std::size_t drive_work = 0;       ///< W_drive [J]
inline constexpr std::size_t damper_work = 1;      ///< W_damper [J]
inline constexpr std::size_t hysteresis_work = 2;  ///< W_hysteresis [J]
inline constexpr std::size_t friction_work = 3;    ///< W_friction [J]
inline constexpr std::size_t separation = 4;       ///< ∫ max(g, 0) dt [m s]
inline constexpr std::size_t external_work = 5;    ///< W_external [J]: the gas loads' work on the bodies
}  // namespace quadrature

/// The mechanism: its design's geometry (dynamics/cam_geometry.h, built once
/// and shared; a Model copies its pointers) and the bodies and force elements
/// assembled for one cam speed.
struct Model : CamGeometry {
  double omega = 0.0;   ///< nominal cam speed |θ̇| [rad/s] (0: cam held still); motor speed with a shaft
  double theta0 = 0.0;  ///< cam angle at t = 0 [rad]

  double mass = 0.0;      ///< generalised inertia M: follower mass [kg] or arm inertia [kg m²]
  FollowerForces forces;  ///< the return spring, the damper and gravity on q (dynamics/follower_forces.h)

  ForceLaw contact;
  /// The contact's materials where the scene gives them (`contact.stiffness.from_materials`):
  /// the Hertz pressure of the stress metrics (dynamics/contact_stress.h); none otherwise.
  std::optional<HertzContact> hertz;
  ContactFriction friction;  ///< sliding friction at the contact, the roller's spin (dynamics/friction_elements.h)
  SupportFriction support;   ///< guide or pivot friction (dynamics/friction_elements.h)

  ShaftDrive drive;  ///< the cam's drive: constant speed or a shaft from a motor (dynamics/shaft_drive.h)
  /// Seats, stops, springs with mass and the bodies after the follower
  /// (dynamics/follower_train.h); empty for a scene without them.
  FollowerTrain train;
  /// The lash at the cam and the take-up windows that classify a separation
  /// (dynamics/separation_cause.h); `applies` false without a seat.
  TakeUpWindow take_up;
  /// The jump speed of the held, linearised train [rpm] (dynamics/train_jump_speed.h),
  /// for a train with coordinates of its own; speed-independent, so made once.
  double train_jump_speed_rpm = 0.0;
  /// jump_speed_rpm(*this) [rpm], made when the model is assembled and again
  /// by set_scene_parameters (NaN: not made, model_jump_speed_rpm makes it): every
  /// run's metrics carry it, and a Poincaré map's runs are one revolution.
  double rigid_jump_speed_rpm = std::numeric_limits<double>::quiet_NaN();

  Tracking tracking = Tracking::differential;
  double tracking_gain = 0.0;      ///< α of ḟ = −α f [1/s]
  double penetration_limit = 0.0;  ///< a larger δ means the contact model no longer applies [m]

  StateLayout layout;  ///< which states this model has, where, and their names
  /// W_drive, W_damper, W_hysteresis, W_friction [J], ∫ max(g, 0) dt [m s]
  /// and W_external [J]: indexed by the names in `quadrature`.
  static constexpr int kQuadratures = 6;

  std::vector<std::string> elements;  ///< force elements assembled

  /// Nominal cam angle at time t [rad]: the cam's with constant-speed drive,
  /// the motor's (without the shaft's twist) with a shaft.
  double theta(double t) const { return theta0 + omega * t; }
  /// Number of root functions (docs/model.md §6): the cam contact's, then the train's gaps.
  int root_count() const { return contact_roots() + train.roots; }
  /// What root function r (0 ≤ r < root_count()) watches. The owners declare
  /// their roots in this order: the cam contact its gap, then its force clamp
  /// switch where the law has one; the train its gaps, root 0 first.
  RootSlot root_slot(int r) const {
    assert(r >= 0 && r < root_count());
    if (r == 0) return {RootRole::contact_gap, 0};
    if (r == 1 && contact.has_clamp_switch()) return {RootRole::contact_clamp, 0};
    return {RootRole::train_gap, r - contact_roots()};
  }
  /// The number of the root function with this role and index within its
  /// owner (root_slot()'s inverse), −1 where the model has none.
  int root_of(RootRole role, int index = 0) const {
    switch (role) {
      case RootRole::contact_gap:
        return index == 0 ? 0 : -1;
      case RootRole::contact_clamp:
        return index == 0 && contact.has_clamp_switch() ? 1 : -1;
      case RootRole::train_gap:
        return index >= 0 && index < train.roots ? contact_roots() + index : -1;
    }
    return -1;
  }
  /// The most root functions a model has: the cam contact's two and the train's most
  /// (the size of the arrays a run's root values and directions are kept in).
  static constexpr int kMaxRoots = 2 + TrainLimits::kMaxRoots;
  /// Whether state_jacobian() is available (the reduced pair forms; the general
  /// one leaves the Jacobian to the integrator's difference quotients).
  bool exact_jacobian() const { return pair_form == PairForm::reduced; }

 private:
  /// Root functions the cam contact declares: its gap, and the clamp switch where the law has one.
  int contact_roots() const { return contact.has_clamp_switch() ? 2 : 1; }
};

/// The linear parts of the model's follower forces (FollowerForces::linear_parts
/// at the model's inertia): what every closed form reads; none when some
/// element has none, or the train has a force given against time or the cam
/// angle (a gas load, FollowerTrain::time_dependent), and the closed forms
/// are then off.
inline std::optional<FollowerLinearParts> follower_linear_parts(const Model& model) {
  if (model.train.time_dependent()) return std::nullopt;
  return model.forces.linear_parts(model.mass);
}

/// Assembles the model of a scene. Throws InputError for a cam that cannot be
/// made or a contact law that cannot be built; `file` names the config.
/// Builds the scene's geometry (build_cam_geometry) first.
Model build_model(const SceneConfig& scene, const std::string& file);

/// The same on a geometry already built from a scene with the same motion
/// law, cam, follower geometry and limits as `scene` (the cam speed and the
/// mechanism's masses, springs, contact and drive may differ): to the bit the
/// model build_model(scene, file) makes, without building the geometry again.
Model build_model(const CamGeometry& geometry, const SceneConfig& scene, const std::string& file);

/// build_model(*geometry, scene, file) where a geometry is given, else build_model(scene, file).
Model build_model(const std::shared_ptr<const CamGeometry>& geometry, const SceneConfig& scene,
                  const std::string& file);

/// How many models build_model() has assembled in this process (every
/// overload counts once), for tests that a study assembles its model once
/// and sets each speed in place.
long model_builds();

/// Sets the cam speed in place to `scene.mechanism.cam.rpm` (the rest of
/// `scene` as the model was built from), with the checks that depend on it
/// (the contact stress limit, what the solver cannot run): the model is then
/// the one build_model(scene, file) makes, to the bit. What depends on ω is
/// Model::omega and Model::tracking_gain; the jump speeds, the train and the
/// take-up windows do not. The jump_map and speed_limit studies run every
/// speed this way on a copy of the study's model.
void set_cam_speed(Model& model, const SceneConfig& scene, const std::string& file);

/// The train of `scene` built on `model`'s core states, or nothing when its
/// structure (bodies, spring lumps, elements, their states and roots)
/// differs from the model's train: then build the model again. Throws the
/// InputError build_model() would for the train's values.
std::optional<FollowerTrain> train_of_same_structure(const Model& model, const SceneConfig& scene,
                                                     const std::string& file);

/// Sets a train from train_of_same_structure() in place, with the rest of
/// `scene` as the model holds it (its follower parameters already set), and
/// makes again what the train and the follower's parameters give: the
/// take-up windows, the rigid and held-train jump speeds, and the checks of
/// build_model(). The model is then the one build_model(scene, file) makes,
/// to the bit (tests/study/scene_parameters_test.cc).
void set_train(Model& model, FollowerTrain train, const SceneConfig& scene, const std::string& file);

/// Sets every number of `scene` in place on a model built from a scene of the
/// same structure and geometry (Pinocchio's model / data split): the cam's
/// speed and initial angle, the mass, spring, damper, gravity, contact law,
/// friction and drive with
/// build_model()'s own assembly, and a follower train's masses, links,
/// seats, lashes and springs with set_train(); the rigid jump speed made
/// again. The model is then the one build_model(scene, file) makes, to the
/// bit. Returns false, the model untouched, when `scene` changes the
/// structure (a friction element or the spin state switched on or off, a
/// train's bodies, lumps, elements or roots): build the model again. The
/// values are not checked against the config's rules (the caller that sets
/// them, identification, checks them with the loader's checks); the
/// checks that need the train are made with it (set_train). Allocates
/// nothing without a train unless the list of elements changes.
bool set_scene_parameters(Model& model, const SceneConfig& scene, const std::string& file);

/// Mutable per-run data, reused between runs.
struct Workspace {
  double v0 = 0.01;          ///< approach speed of the current contact episode [m/s]
  double u_warm = 0.0;       ///< Newton warm start: pair parameter at the last accepted state
  long tracking_resets = 0;  ///< global re-initialisations of the pair
  double motor_phase = 0.0;  ///< constant-speed motor with a shaft: θ_m = θ(t) + motor_phase [rad]
  double v_warm = 0.0;       ///< general pair form: follower profile parameter at the last accepted state
  /// General pair form: the global search's samples and scratch, made for
  /// the profiles below (held, so that a workspace made for another model's
  /// profiles is recognised and remade, never reused).
  std::shared_ptr<PairTrackerWorkspace> pair_search;
  std::shared_ptr<const PairProfile> pair_search_cam, pair_search_follower;
  TrainWorkspace train;           ///< the train's approach speeds (dynamics/follower_train.h)
  TrainEvaluation train_scratch;  ///< the train at the Jacobian's state
};

/// A workspace for this model with everything evaluate() needs allocated
/// (the general pair form's search samples): make one per worker and reuse
/// it for every run of the model (simulate() resets the per-run state).
Workspace make_workspace(const Model& model);

/// Puts the workspace into the state a fresh one made for this model has at
/// the start of a run (simulate() calls it first). Allocates only when the
/// workspace was not made for this model's pair profiles.
void prepare_workspace(const Model& model, Workspace& ws);

/// Lists the force elements the model assembles in model.elements (summary.json `model`).
void list_elements(Model& model);

/// The follower body's pose and velocity for the general pair form: origin
/// (e, y₀ + q) for a translating follower, the pivot turned to ψ₀ + κ q for an
/// oscillating one.
BodyMotion follower_motion(const FollowerGeometry& follower, double q, double q_dot);

/// Everything the model computes at one (t, state).
struct Evaluation {
  double theta = 0.0;       ///< cam angle [rad]
  double cam_speed = 0.0;   ///< θ̇ [rad/s]
  double y = 0.0, v = 0.0;  ///< follower coordinate q [m | rad] and rate
  double spin = 0.0;        ///< roller spin Ω [rad/s] (world frame)
  TrackedPair pair;
  double pair_v = 0.0;      ///< general pair form: follower profile parameter
  double pair_drift = 0.0;  ///< size of the Newton step back to f = 0 [rad | m]: drift of differential tracking
  bool tracking_ok = true;
  double gap = 0.0, gap_rate = 0.0;  ///< g [m], ġ [m/s] (at fixed pair parameter)
  double delta = 0.0, delta_rate = 0.0;
  double normal_force = 0.0;    ///< F_n [N]
  double friction_force = 0.0;  ///< tangential force on the follower at the contact along t = J n [N]
  double slip = 0.0;            ///< slip velocity of the follower over the cam at the contact [m/s]
  double contact_offset = 0.0;  ///< contact point across the follower face from its centre [m]
  Eigen::Vector2d force_world = Eigen::Vector2d::Zero();  ///< contact force on the follower [N]
  double generalised_force = 0.0;                         ///< contact force on q [N | N m]
  double cam_torque = 0.0;                                ///< contact generalised force on the cam angle [N m]
  double guide_friction = 0.0;                            ///< guide friction force on q [N]
  double pivot_friction = 0.0;                            ///< pivot friction torque on q [N m]
  double acceleration = 0.0;                              ///< q̈
  double spin_acceleration = 0.0;
  double u_rate = 0.0;       ///< u̇ [rad/s] (differential tracking)
  double v_rate = 0.0;       ///< v̇ (general pair form, differential tracking)
  DriveRates<double> drive;  ///< shaft twist and torque, motor speed and torque, accelerations (dynamics/shaft_drive.h)
  double power_drive = 0.0, power_damper = 0.0, power_hysteresis = 0.0, power_friction = 0.0;  ///< [W]
  double power_external = 0.0;  ///< delivered by the train's gas loads [W]
  TrainEvaluation train;        ///< the train's forces and rates (only with model.train.present())
};

/// Evaluates the model. With Newton tracking the pair is solved from
/// ws.u_warm (falling back to a global search, counted in ws.tracking_resets).
/// Allocates nothing.
void evaluate(const Model& model, Workspace& ws, double t, const double* state, Evaluation& ev);

/// Right-hand side of the state from an evaluation.
void state_derivative(const Model& model, const Evaluation& ev, double* state_dot);

/// Quadrature integrands (powers) from an evaluation.
void quadrature_derivative(const Evaluation& ev, double* q_dot);

/// Exact Jacobian ∂ẋ/∂x of the state derivative at (t, state), written
/// column-major into `jacobian` (jacobian[i + n j] = ∂ẋ_i/∂x_j, n =
/// model.layout.size): the same templated right-hand side evaluated with
/// forward-mode dual numbers (dynamics/dual.h), the Newton pair parameter
/// differentiated by the implicit function theorem. Allocates nothing.
/// Checked against finite differences in tests/dynamics/jacobian_test.cc.
/// Only for model.exact_jacobian().
void state_jacobian(const Model& model, Workspace& ws, double t, const double* state, double* jacobian);

/// The root functions into g[0 .. root_count()), each by its role
/// (Model::root_slot(), dynamics/root_roles.h): the cam contact's gap g [m],
/// its force clamp switch (where the law has one), the train elements' gaps −d [m].
void root_functions(const Model& model, const Workspace& ws, const Evaluation& ev, double* g);

/// Mechanical energy terms at an evaluation [J].
struct EnergyTerms {
  double kinetic = 0.0, spring = 0.0, gravity = 0.0, contact = 0.0;
};
EnergyTerms energy_terms(const Model& model, const Evaluation& ev);

}  // namespace camdyn
