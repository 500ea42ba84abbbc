// The follower train held (docs/model.md §12, "The held train"): every link
// held in contact, seats, stops, lash take-up and coil clash left out, and
// the cam contact held as a linear spring and damper at its mean load
// (dynamics/train_jump_speed.h linearised_train), so that the train's
// coordinates x obey the linear system
//   M ẍ + C ẋ + K x = f0 + k_in s + c_in ṡ
// driven by the lift s(θ). Every quantity the rigid stage of an optimize
// study constrains — the cam contact force, each link force, each spring's
// frame-end force, a seated body's position and velocity — is then
//   L = α s + β ṡ + a·x + b·ẋ + constant,
// linear in the lift. At cam speed ω (θ = ω t) its periodic response is the
// exact α s + β ω s' plus a sum over the lift's harmonics of the train's
// frequency response at h ω, to the harmonic where the last octave adds less
// than a stated share of the largest force (the contact's own modes included:
// a stiff contact rings at thousands of hertz, and a law whose jerk jumps
// excites it). The count is chosen per speed and reported.
#pragma once

#include <Eigen/Core>
#include <complex>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "geometry/motion_law.h"

namespace camdyn {

struct Model;

/// A monitored quantity of the held train: L = α s + β ṡ + a·x + b·ẋ + constant.
struct HeldQuantity {
  /// contact: the cam's generalised force on the follower [N | N m] (held > 0);
  /// link: a link's force [N] (held > 0); spring_end: a spring's force at its
  /// frame end [N]; seat_position [m] / seat_velocity [m/s] of a body with a seat.
  enum class Kind { contact, link, spring_end, seat_position, seat_velocity };
  Kind kind = Kind::contact;
  std::string name;                ///< "cam contact", "link valve", "spring valve", "seat valve"
  int body = 0;                    ///< index into FollowerTrain::bodies
  double seat = 0.0;               ///< seat_position: the seat's position p [m]
  double alpha = 0.0, beta = 0.0;  ///< per s [unit/m], ṡ [unit s/m]
  Eigen::VectorXd a, b;            ///< per x, ẋ
  double constant = 0.0;
  bool held() const { return kind == Kind::contact || kind == Kind::link; }
};

/// The held train of a model.
struct HeldTrain {
  Eigen::MatrixXd M, C, K;               ///< of the coordinates x (follower first) [kg], [N s/m], [N/m]
  Eigen::VectorXd f0, k_in, c_in;        ///< constant load [N], per s [N/m], per ṡ [N s/m]
  std::vector<HeldQuantity> quantities;  ///< the contact first, then links, spring ends, seat bodies
  int free_coordinates() const { return static_cast<int>(M.rows()); }
};

/// The model's held train. A model without a train has one coordinate (the
/// follower) and one quantity, the contact force. The follower's forces are
/// the sum of their linear parts: throws std::invalid_argument when some
/// follower element has none (dynamics/train_jump_speed.h).
HeldTrain held_train(const Model& model);

/// A lift function on the response grid of R angles θ_i = 2π i / R: exact
/// u, u' there, and its Fourier coefficients U_0 (the mean) and U_h,
/// h = 1 … R/2 − 1, with u = U_0 + Re Σ U_h e^{ihθ}.
struct GridSignal {
  std::vector<double> u, du;            ///< at the grid angles [m], [m/rad]
  std::vector<std::complex<double>> U;  ///< U_0 … U_{R/2−1} [m]
};

/// The signal of a function θ ↦ (u, u', …) over one revolution on `angles`
/// (a power of two, ≥ 16) grid angles; the coefficients from 4 × `angles`
/// samples (the harmonics used stop at angles / 2; aliasing brings in those
/// above 3.5 × angles, below 1e−10 of the lift for a law with a continuous s').
GridSignal grid_signal(const std::function<LawSample(double)>& f, int angles);
/// How many equally spaced samples over a revolution grid_signal takes (4 × `angles`).
int grid_signal_samples(int angles);
/// The signal of those samples (θ_j = 2π j / grid_signal_samples(angles)).
/// Throws std::invalid_argument for a wrong count.
GridSignal grid_signal_of_samples(const std::vector<LawSample>& samples, int angles);

/// The response of one speed: per quantity k, its values at the grid angles
/// for the zero lift (`fixed`) and per unit of each signal (`per_signal`).
struct SpeedResponse {
  double omega = 0.0;  ///< [rad/s]
  int harmonics = 0;   ///< of the y response
  /// Estimated truncation: the y part of the last octave of harmonics over
  /// the largest |L| of any quantity [-]: the next octave adds less.
  double truncation = 0.0;
  std::vector<Eigen::VectorXd> fixed;       ///< [k]: R values, constant + static preload response
  std::vector<Eigen::MatrixXd> per_signal;  ///< [k]: R × signals
};

/// The held train's responses at each speed, for a fixed list of signals
/// (the zero-design law first, then the design's basis functions), cached
/// per speed.
class HeldTrainResponse {
 public:
  /// Throws std::invalid_argument for a K that does not hold every coordinate.
  HeldTrainResponse(HeldTrain train, std::vector<GridSignal> signals, int angles, double tolerance = 1e-4);
  /// The response at ω [rad/s] (computed once per ω, then cached).
  const SpeedResponse& at(double omega);
  const HeldTrain& train() const { return train_; }
  int angles() const { return angles_; }
  int signals() const { return static_cast<int>(signals_.size()); }
  double tolerance() const { return tolerance_; }

 private:
  SpeedResponse compute(double omega) const;

  HeldTrain train_;
  std::vector<GridSignal> signals_;
  int angles_ = 0;
  double tolerance_ = 0.0;
  Eigen::VectorXd y_static_;  ///< K⁻¹ f0 [m]
  Eigen::VectorXd y_per_s_;   ///< K⁻¹ k_in [m/m]
  std::map<double, SpeedResponse> cache_;
};

/// The values of every quantity of `train` at the grid angles for lift
/// `signal` at ω: [k] → R values (the law's own response; for reports and
/// the jump speed). `harmonics` receives the count used.
std::vector<Eigen::VectorXd> held_train_values(const HeldTrain& train, const GridSignal& signal, double omega,
                                               int* harmonics = nullptr);

/// The speeds ω < omega_max [rad/s] at which an undamped natural frequency of
/// the train meets a significant harmonic h of `law` (√λ / h, the harmonic at
/// least 1e-3 of the largest): where the held train's forces dip.
std::vector<double> resonance_speeds(const HeldTrain& train, const GridSignal& law, double omega_max);

/// The lowest ω in (0, omega_max] at which a held quantity of the law falls
/// to `min_force` (the contact's in its own unit; links in N) [rad/s]: a scan
/// over 400 equal steps and the natural frequencies over each harmonic, then
/// bisection to `rtol`. 0 when the train does not hold even at rest; +inf
/// when nothing reaches the floor up to omega_max.
double held_train_jump_speed(const HeldTrain& train, const GridSignal& law, double omega_max, double contact_floor,
                             double link_floor, double rtol = 1e-6);

}  // namespace camdyn
