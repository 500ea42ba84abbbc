// The rigid-model contact force of a model (docs/model.md §12, "Rigid figures
// of a train"): the follower held on its law. Without a train of its own
// coordinates it is the one-mass figure of docs/model.md §9
// (rigid_normal_force, exact at any cam angle). With one (train bodies, a
// spring with mass) it is the held train's cam contact force
// (dynamics/held_train.h): every link held, the spring's coils and the bodies
// behind the follower moving with it — the follower alone leaves out most of
// what the cam pushes. That force is known on a grid of angles over a
// revolution; between them it is interpolated linearly. Every rigid figure —
// the force, stress and torque curves of a report, the scene's
// `mechanism.cam.limits.max_contact_stress`, an optimize study's stress rows
// and its constraint value — comes from here.
#pragma once

#include <vector>

#include "dynamics/model.h"

namespace camdyn {

/// Whether the model's rigid figures are the held train's (a train with
/// coordinates of its own and linear parts) rather than the one-mass figure
/// (which is NaN, not available, without linear parts: a gas load).
bool rigid_figures_held(const Model& model);

/// The held train's cam contact force as the cam's generalised force on the
/// follower Q [N | N m] at the `angles` grid angles θ_i = 2π i / angles
/// (a power of two ≥ 16) at cam speed `omega` [rad/s]: the contact quantity
/// of held_train_values times the contact's lever (an arm's length; 1 for a
/// translating follower).
std::vector<double> held_contact_generalised_force(const Model& model, double omega, int angles);
/// The same for another lift law `law` on the model's held train (an
/// optimiser's design on its baseline's train, linearised at the baseline's
/// mean contact load), the harmonics cut at `tolerance` (HeldTrainResponse;
/// 0: every harmonic of the grid, the same count for every law, as a finite
/// difference between two laws needs).
std::vector<double> held_contact_generalised_force(const Model& model, const MotionLaw& law, double omega, int angles,
                                                   double tolerance = 1e-4);

/// The value at cam angle θ [rad] of a periodic function known at the grid
/// angles 2π i / values.size(): linear between them (exact at them).
double on_revolution_grid(const std::vector<double>& values, double theta);

/// The rigid-model contact force of a model at one cam speed.
class RigidContactForce {
 public:
  /// The held train's grid (0.088° apart).
  static constexpr int kHeldAngles = 4096;

  /// `omega` [rad/s] ≥ 0. On a train computes the held train's response once.
  RigidContactForce(const Model& model, double omega);

  bool held() const { return !q_.empty(); }
  double omega() const { return omega_; }
  /// The cam's generalised force on the follower Q [N | N m] at cam angle θ [rad].
  double generalised(double theta) const;
  /// The normal contact force [N]: Q / (∂g/∂q) (translating roller: P / cos φ).
  double normal(double theta) const;
  /// The drive torque on the cam [N m] without friction: T = Q s'(θ) (virtual power).
  double torque(double theta) const;

  /// The angles the figure is exact at: kHeldAngles on a train; none (every
  /// angle) for one mass.
  int grid_angles() const { return static_cast<int>(q_.size()); }
  /// Q at grid angle i [N | N m] (a train only).
  double grid_generalised(int i) const { return q_[static_cast<std::size_t>(i)]; }

 private:
  const Model* model_;
  double omega_;
  std::vector<double> q_;  ///< Q at the grid angles on a train [N | N m]; empty for one mass
};

}  // namespace camdyn
