// The rigid stage of an optimize study on a follower train (docs/optimize.md
// "Trains"): with every contact and link held, the train is linear, so each
// quantity the stage constrains — the cam contact force, each link force, each
// spring's frame-end force, a seated body's velocity — is at cam angle θ and
// speed ω an affine function of the design's control points c,
//   L(θ; ω) = L̄(θ; ω) + Σ_j G_j(θ; ω) c_j,
// G_j the held train's periodic response to the lift of column j
// (dynamics/held_train.h, computed once per speed and cached). The
// programmes keep the one-mass programmes' form with these rows in place of
// the rigid force M ω² s'' + c ω s' + k s + F₀.
//
// The rows live on the response grid (1024 angles per revolution) at every
// checked speed. Most never bind, so they are generated: a programme starts
// with every 128th angle at the top speed, and after each solve the angles where the solution
// breaks a row are added until none does (an angle, once added, stays for
// every later programme and speed). Seating rows are placed where the held
// train's seated body crosses its seat on the way down.
#pragma once

#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "dynamics/held_train.h"
#include "optim/linear_program.h"

namespace camdyn {
struct Model;
}

namespace camdyn::optim {

/// The limits the train rows hold.
struct TrainRowLimits {
  double contact_floor = 0.0;                  ///< P_min of the cam contact [N | N m]
  double link_floor = 0.0;                     ///< P_min of every link [N]
  std::optional<double> max_spring_force;      ///< at each spring's frame end [N]
  std::optional<double> max_seating_velocity;  ///< of a seated body where it reaches its seat [m/s]
};

/// What the held train says of one law at one speed (a dense check).
struct HeldCheck {
  double margin = 0.0;             ///< min over θ and held quantities of L − floor [N]
  std::string binding;             ///< the quantity that sets it ("cam contact", "link valve")
  double binding_angle_deg = 0.0;  ///< where
  double peak_spring_force = 0.0;  ///< largest frame-end force of any spring [N] (0: none)
  double seating_velocity = 0.0;   ///< largest |velocity| at a downward seat crossing [m/s] (0: none)
};

class TrainRows {
 public:
  static constexpr int kAngles = 1024;        ///< the response grid (511 harmonics)
  static constexpr int kSampledSpeeds = 10;   ///< a design jump-free up to ω is checked at ω k / 10
  static constexpr double kTolerance = 1e-4;  ///< of the harmonic truncation, relative to the largest force

  /// `column_lift(θ, out)` writes (s, s', s'') of every design column at θ
  /// (`columns` of them); `law0` is the design's law with every column 0.
  TrainRows(const Model& model, const MotionLaw& law0, int columns,
            const std::function<void(double, std::vector<LawSample>&)>& column_lift, TrainRowLimits limits);

  /// Adds the active rows at every ω of `omegas`: each held quantity − t ≥
  /// its floor (t the column `t`; −1: none, the rows then hold ≥ floor), and
  /// the spring and seating rows. Columns 0 … columns−1 are the design's.
  void add_rows(LinearProgram& lp, const std::vector<double>& omegas, int t) const;
  /// Adds z ≥ cam contact force at every active angle at ω (z the column `z`).
  void add_peak_rows(LinearProgram& lp, double omega, int z) const;
  /// Activates the angles where design `c` (with margin `t`) breaks a row at
  /// some ω of `omegas`, by more than 1e−9 of the force scale; returns how
  /// many were activated (0: `c` meets every row on the grid).
  int activate_violated(const std::vector<double>& c, double t, const std::vector<double>& omegas);
  /// Activates the angles where the cam contact force of design `c` at ω
  /// exceeds z (the peak rows of add_peak_rows); returns how many.
  int activate_peak(const std::vector<double>& c, double omega, double z);
  /// min over the grid and ω of `omegas` of every held quantity − floor for design `c` [N].
  double worst_margin(const std::vector<double>& c, const std::vector<double>& omegas);

  /// The speeds a design jump-free up to ω is checked at [rad/s].
  static std::vector<double> check_speeds(double omega);
  /// The largest harmonic truncation over the speeds computed so far [-], and the most harmonics used.
  double truncation() const { return truncation_; }
  /// The largest held force of the zero design at rest [N]: the programmes' force scale.
  double force_scale() const { return scale_; }
  int harmonics() const { return harmonics_; }
  /// The held train the rows are of, and the limits they hold.
  const HeldTrain& held() const { return response_->train(); }
  const TrainRowLimits& limits() const { return limits_; }

 private:
  double value(const SpeedResponse& r, std::size_t k, int i, const std::vector<double>& c) const;
  /// Activates, for quantity k, the worst angle of each run of angles whose
  /// excess(i) is above the tolerance; returns how many were new.
  int activate_runs(std::size_t k, std::size_t n, bool top, const std::function<double(int)>& excess, bool with_next);
  /// The active angles of quantity k at the n-th speed of a programme's list
  /// (the k-th sampled speed keeps its rows from one bisection step to the
  /// next); a speed none were activated at has none, but the top one of the
  /// list starts with every 128th angle.
  const std::set<int>& angles(std::size_t k, std::size_t n, bool top) const;
  static constexpr std::size_t kPeakSlot = 1000;  ///< the peak rows' own slot
  const SpeedResponse& at(double omega);

  int columns_ = 0;
  TrainRowLimits limits_;
  std::shared_ptr<HeldTrainResponse> response_;               ///< signals: law0, then each column
  std::vector<std::map<std::size_t, std::set<int>>> active_;  ///< per quantity and speed slot, its active angles
  std::vector<std::set<int>> first_;                          ///< per quantity, the angles every slot starts with
  double scale_ = 1.0;                                        ///< force scale [N]
  double truncation_ = 0.0;
  int harmonics_ = 0;
};

/// The dense check of a built law on the held train of `model` at ω [rad/s]
/// (a 2048-angle grid).
HeldCheck check_held_train(const Model& model, const MotionLaw& law, double omega, const TrainRowLimits& limits);

/// The held train's quantities of a scene's law over one revolution at
/// `rpm` (for reports): every quantity but the seated bodies' positions.
struct HeldCurves {
  std::vector<double> angles_deg;  ///< 0 … 360 [deg]
  std::vector<HeldQuantity> quantities;
  std::vector<std::vector<double>> values;  ///< per quantity, at each angle [N | m/s]
};
HeldCurves held_train_curves(const Model& model, double rpm);

/// The law's jump-free speed on the held train with the floors of `limits`
/// [rad/s] (dynamics/held_train.h held_train_jump_speed), up to `omega_max`.
double held_jump_free_speed(const Model& model, const MotionLaw& law, const TrainRowLimits& limits, double omega_max);

}  // namespace camdyn::optim
