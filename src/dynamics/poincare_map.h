// The once-per-revolution Poincaré map of a scene whose cam is driven at a
// set speed (docs/model.md §5 run from a given state): the state at t = k T
// (cam angle θ₀ + 2πk, T = 2π/ω) as a function of the state at t = 0. Its
// coordinates are the states that carry the motion: the follower coordinate
// and rate, the roller spin, a shaft-driven cam's angle (less the 2π per
// revolution of the drive, and less its angle at t = 0) and speed. The contact pair parameters are left
// out: they follow from the others, and each map evaluation finds them
// again. Two numbers that are not states go along beside the coordinates:
// the approach speed of a contact episode in progress (v₀ of the damping
// laws) and a constant-speed motor's phase.
//
// The periodic study (study/periodic_orbit.h) solves P^k(x) = x on it.
#pragma once

#include <span>
#include <string>
#include <vector>

#include "dynamics/model.h"
#include "dynamics/simulation.h"
#include "scene/scene.h"

namespace camdyn {

/// A point of the section: the coordinates and what goes along beside them.
struct SectionPoint {
  std::vector<double> x;        ///< PoincareMap::coordinate_names() order [SI]
  double approach_speed = 0.0;  ///< v₀ of the contact episode in progress [m/s]
  double motor_phase = 0.0;     ///< constant-speed motor of a shaft drive [rad]
};

/// One evaluation of P^k.
struct MapResult {
  SectionPoint end;     ///< the state after k revolutions
  bool ok = false;      ///< the run converged
  std::string message;  ///< why not
  long impacts = 0;     ///< contact onsets after a separation during the k revolutions
  long steps = 0;       ///< integrator steps
};

class PoincareMap {
 public:
  /// Throws InputError (naming `file`) when the scene's speed is not set by
  /// its drive: a cam standing still, or a torque–speed motor.
  PoincareMap(const SceneConfig& scene, const Model& model, const std::string& file);

  int dimension() const { return static_cast<int>(coordinates_.size()); }
  std::vector<std::string> coordinate_names() const;
  double period() const { return period_; }  ///< T = 2π/ω [s]
  const Model& model() const { return model_; }
  const SceneConfig& scene() const { return scene_; }
  /// A typical size of each coordinate (lift range, its rate at speed ω, …),
  /// which scales residuals and finite-difference steps.
  const std::vector<double>& scales() const { return scales_; }
  /// The state index of each coordinate (Model::layout), in coordinate order.
  const std::vector<int>& coordinate_indices() const { return coordinates_; }

  /// The section point of a full state reached after `revolutions` revolutions.
  SectionPoint point(const std::vector<double>& state, double approach_speed, double motor_phase,
                     int revolutions) const;
  /// The section point where a run ended (`result.end_time` a whole number of revolutions).
  SectionPoint point(const SimulationResult& result) const;
  /// The start of a run from a section point.
  StartState start(const SectionPoint& p) const;

  /// P^k(p): `k` revolutions from p, on `ws` (one per thread).
  MapResult apply(const SectionPoint& p, int k, Workspace& ws) const;
  /// The scene a run of `revolutions` revolutions uses (no discarded cycles).
  SceneConfig scene_for(double revolutions) const;
  /// max_j |a_j − b_j| / scale_j: how far apart two section points'
  /// coordinates are, the measure of every test on the section.
  double scaled_distance(std::span<const double> a, std::span<const double> b) const;

 private:
  const SceneConfig scene_;
  const Model& model_;
  double period_ = 0.0;
  double angle_per_revolution_ = 0.0;  // θ(T) − θ(0) [rad]
  std::vector<int> coordinates_;       // state indices
  std::vector<double> scales_;
};

/// max_j |d_j| / scale_j of a difference of section coordinates `d`; NaN when
/// any of them is NaN (a failed run is never "near").
double scaled_norm(std::span<const double> d, std::span<const double> scales);
/// scaled_norm of a − b, without forming it.
double scaled_distance(std::span<const double> a, std::span<const double> b, std::span<const double> scales);

}  // namespace camdyn
