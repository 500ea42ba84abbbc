// The window's extremes (docs/model.md §8: the largest gap, the peak and the
// least contact force, the deepest penetration, the largest kinematic error,
// the peak contact stress and drive torque, the face excursion, the largest
// float gap),
// followed over the integrator's steps from the model evaluated at each
// step's start, middle and end. Between those three a quantity is taken as
// the parabola through them: where its vertex lies inside the step and
// promises a new record, the caller evaluates there as well (probes()), so a
// peak between the samples is found, not cut off at the nearest sample.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <limits>

namespace camdyn {

/// The index of each quantity StepExtremes follows (docs/model.md §8).
namespace extreme {
inline constexpr std::size_t gap = 0;                  ///< the cam gap [m]
inline constexpr std::size_t contact_force = 1;        ///< the contact force [N]
inline constexpr std::size_t least_contact_force = 2;  ///< minus the contact force where it is a margin [N]
inline constexpr std::size_t penetration = 3;          ///< [m]
inline constexpr std::size_t kinematic_error = 4;      ///< |q − s| [m | rad]
inline constexpr std::size_t contact_stress = 5;       ///< the Hertz pressure [Pa]
inline constexpr std::size_t cam_torque = 6;           ///< |drive torque| [N m]
inline constexpr std::size_t face_excursion = 7;       ///< |contact offset on a flat face| [m]
inline constexpr std::size_t float_gap = 8;            ///< the gap in float [m]
inline constexpr std::size_t count = 9;
}  // namespace extreme

class StepExtremes {
 public:
  static constexpr std::size_t kCount = extreme::count;
  /// gap [m], contact force [N], minus the contact force [N], penetration
  /// [m], kinematic error [m | rad], contact stress [Pa], |drive torque|
  /// [N m], |contact offset on a flat face| [m], the gap in float [m]: each followed as a maximum
  /// (−∞ where the scene does not have it).
  using Values = std::array<double, kCount>;

  StepExtremes() { best_.fill(-std::numeric_limits<double>::infinity()); }

  /// Folds the values at one time into the records.
  void fold(const Values& x) {
    for (std::size_t k = 0; k < kCount; ++k) best_[k] = std::max(best_[k], x[k]);
  }

  /// The step's fractions s ∈ (0, 1) worth evaluating, from the values at its
  /// start `x0`, middle `xm` and end `x1`: a quantity's vertex where the
  /// parabola through them has an interior maximum above its record. Writes
  /// them to `s` (nearly equal ones once) and returns how many.
  std::size_t probes(const Values& x0, const Values& xm, const Values& x1, Values& s) const {
    std::size_t n = 0;
    for (std::size_t k = 0; k < kCount; ++k) {
      // p(σ) = x0 + b σ + a σ², through (0, x0), (½, xm), (1, x1).
      const double a = 2.0 * (x0[k] - 2.0 * xm[k] + x1[k]);
      const double b = -3.0 * x0[k] + 4.0 * xm[k] - x1[k];
      if (!(a < 0.0)) continue;  // no interior maximum
      const double vertex = -b / (2.0 * a);
      if (!(vertex > 0.0 && vertex < 1.0)) continue;
      if (!(x0[k] - b * b / (4.0 * a) > best_[k])) continue;
      const bool known = std::any_of(s.begin(), s.begin() + static_cast<std::ptrdiff_t>(n),
                                     [vertex](double other) { return std::abs(other - vertex) < 1e-3; });
      if (!known) s[n++] = vertex;
    }
    return n;
  }

  /// The records; −∞ where nothing was folded.
  const Values& best() const { return best_; }

 private:
  Values best_;
};

/// The values of one time in the order of `extreme` (−∞ where the scene does not have one).
inline StepExtremes::Values extremes_of(double gap, double contact_force, double least_contact_force,
                                        double penetration, double kinematic_error, double contact_stress,
                                        double cam_torque, double face_excursion, double float_gap) {
  StepExtremes::Values v{};
  v[extreme::gap] = gap;
  v[extreme::contact_force] = contact_force;
  v[extreme::least_contact_force] = least_contact_force;
  v[extreme::penetration] = penetration;
  v[extreme::kinematic_error] = kinematic_error;
  v[extreme::contact_stress] = contact_stress;
  v[extreme::cam_torque] = cam_torque;
  v[extreme::face_excursion] = face_excursion;
  v[extreme::float_gap] = float_gap;
  return v;
}

}  // namespace camdyn
