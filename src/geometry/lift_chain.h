// The lift law carried to a body of a follower train (docs/valvetrain.md,
// "Lift at the valve"; docs/model.md §12): through each link's lever ratio
// less its lash, s_i = r_i s_{i−1} − λ_i, and held at the body's seat,
// max(s_i, p_i). It is the one description of a body's kinematic lift: the
// valve figures, the train's lift error, its plots and its kinematic start
// all carry the law through it. With ratios > 0 every step is nondecreasing,
// so the carried lift peaks where the law peaks and the base circle carries
// to the body's lowest kinematic position.
#pragma once

#include <optional>
#include <vector>

namespace camdyn {

/// One body's step: from the kinematic lift of the body before it (the law's
/// s for the follower) to its own.
struct LiftStep {
  double ratio = 1.0;          ///< r_i [m/m], > 0 (1 for the follower)
  double lash = 0.0;           ///< λ_i [m], >= 0 (0 for the follower)
  std::optional<double> seat;  ///< p_i: the body's seat position [m]; none: no seat

  /// max(r_i s − λ_i, p_i), or r_i s − λ_i without a seat [m]; `previous` = s [m].
  double carry(double previous) const;
  /// Whether the body is off its seat (r_i s − λ_i > p_i, or it has none): the step passes motion on.
  bool lifted(double previous) const;
};

/// The steps from the follower (steps[0]) to one body.
struct LiftChain {
  std::vector<LiftStep> steps;

  /// The body's kinematic lift with the law at s [m]; s itself for a chain without steps.
  double at(double s) const;
  /// d(at)/ds at s: the product of the ratios while every step is lifted, else 0 [m/m].
  double slope(double s) const;
  /// Where the body's lift is measured from [m]: its seat position when it
  /// has a seat, else its position with the law on the base circle, at(min_s).
  double datum(double min_s) const;
};

}  // namespace camdyn
