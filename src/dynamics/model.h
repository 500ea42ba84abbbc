// The cam-follower mechanism as an ODE (physics.md §4): an immutable Model
// assembled from the scene with only what the scene needs, a mutable
// Workspace reused across runs, and free functions that evaluate it
// (Pinocchio style). The state is, in this order and only where needed:
//   y [m], ẏ [m/s]          follower displacement above its lowest position and its rate
//   u [rad]                 contact pair parameter, differential tracking only
//   Ω [rad/s]               roller spin, only with roller inertia and friction
// Energy flows (drive work, damper, contact hysteresis, friction) are
// quadratures (physics.md §5), integrated beside the state.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "contact/force_law.h"
#include "contact/friction.h"
#include "contact/point_curve_tracking.h"
#include "geometry/cam_roller.h"
#include "geometry/motion_law.h"
#include "io/config.h"

namespace camdyn {

enum class Tracking { differential, newton };

struct Model {
  std::shared_ptr<const MotionLaw> law;  ///< owned here; `cam.law` points into it
  TranslatingRollerCam cam;
  CamGeometryReport geometry;  ///< pressure angle and curvature, checked when the model is built
  double omega = 0.0;   ///< cam speed |θ̇| [rad/s] (0: cam held still)
  int direction = +1;   ///< σ: the cam frame is at angle σθ in the world
  double theta0 = 0.0;  ///< cam angle at t = 0 [rad]

  double mass = 0.0;            ///< follower mass m [kg]
  double spring_stiffness = 0;  ///< k [N/m]
  double spring_preload = 0;    ///< spring force at y = 0 [N]
  double damping = 0.0;         ///< viscous damper c [N s/m]
  double gravity = 0.0;         ///< g [m/s²], pulling towards the cam

  ForceLaw contact;
  FrictionLaw friction;
  double roller_inertia = 0.0;  ///< [kg m²]
  bool has_spin = false;        ///< roller spin state with friction

  Tracking tracking = Tracking::differential;
  double tracking_gain = 0.0;  ///< α of ḟ = −α f [1/s]

  // State layout (−1: not in this scene).
  int state_size = 2;
  int index_u = -1;
  int index_spin = -1;
  /// W_drive, W_damper, W_hysteresis, W_friction [J], and ∫ max(g, 0) dt [m s].
  static constexpr int kQuadratures = 5;

  std::vector<std::string> state_names;  ///< for summary.json `model`
  std::vector<std::string> elements;     ///< force elements assembled

  /// Cam angle along the motion law at time t [rad].
  double theta(double t) const { return theta0 + omega * t; }
  /// Number of root functions: gap, plus the force clamp switch where the law has one.
  int root_count() const { return contact.has_clamp_switch() ? 2 : 1; }
};

/// Assembles the model of a scene. Throws InputError for a cam that cannot be
/// made or a contact law that cannot be built; `file` names the config.
Model build_model(const SceneConfig& scene, const std::string& file);

/// Mutable per-run data, reused between runs.
struct Workspace {
  double v0 = 0.01;          ///< approach speed of the current contact episode [m/s]
  double u_warm = 0.0;       ///< Newton warm start: pair parameter at the last accepted state
  long tracking_resets = 0;  ///< global re-initialisations of the pair
};

/// Everything the model computes at one (t, state).
struct Evaluation {
  double theta = 0.0;        ///< cam angle [rad]
  double y = 0.0, v = 0.0;   ///< follower displacement [m] and rate [m/s]
  double spin = 0.0;         ///< roller spin Ω [rad/s] (world frame)
  TrackedPair pair;
  bool tracking_ok = true;
  double gap = 0.0, gap_rate = 0.0;  ///< g [m], ġ [m/s]
  double delta = 0.0, delta_rate = 0.0;
  double normal_force = 0.0;    ///< F_n [N]
  double friction_force = 0.0;  ///< tangential force on the roller along t = J n [N]
  double slip = 0.0;            ///< slip velocity of roller over cam [m/s]
  Eigen::Vector2d force_world = Eigen::Vector2d::Zero();  ///< contact force on the follower [N]
  double acceleration = 0.0;    ///< ÿ [m/s²]
  double spin_acceleration = 0.0;
  double u_rate = 0.0;          ///< u̇ [rad/s] (differential tracking)
  double power_drive = 0.0, power_damper = 0.0, power_hysteresis = 0.0, power_friction = 0.0;  ///< [W]
};

/// Evaluates the model. With Newton tracking the pair is solved from
/// ws.u_warm (falling back to a global search, counted in ws.tracking_resets).
/// Allocates nothing.
void evaluate(const Model& model, Workspace& ws, double t, const double* state, Evaluation& ev);

/// Right-hand side of the state from an evaluation.
void state_derivative(const Model& model, const Evaluation& ev, double* state_dot);

/// Quadrature integrands (powers) from an evaluation.
void quadrature_derivative(const Evaluation& ev, double* q_dot);

/// Analytic Jacobian ∂ẋ/∂x of the state derivative at (t, state), contact,
/// friction and tracking included, written column-major into `jacobian`
/// (jacobian[i + n j] = ∂ẋ_i/∂x_j, n = model.state_size). Allocates nothing.
/// Checked against finite differences in tests/dynamics/jacobian_test.cc.
void state_jacobian(const Model& model, Workspace& ws, double t, const double* state, double* jacobian);

/// Root functions: [0] gap g, [1] force clamp switch (where the law has one).
void root_functions(const Model& model, const Workspace& ws, const Evaluation& ev, double* g);

/// Mechanical energy terms at an evaluation [J].
struct EnergyTerms {
  double kinetic = 0.0, spring = 0.0, gravity = 0.0, contact = 0.0;
};
EnergyTerms energy_terms(const Model& model, const Evaluation& ev);

/// The rigid-model critical (jump) speed of physics.md §6 [rpm]:
/// min over θ with s'' < 0 of sqrt((k (s + x₀) + m g) / (−m s'')). +inf if the
/// law never decelerates.
double jump_speed_rpm(const Model& model);

}  // namespace camdyn
