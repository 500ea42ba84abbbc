// The periodic response of a LINEAR follower train to a periodic lift, and its
// jump speed (docs/model.md §12). With every one-sided force held (cam
// contact, links; seats and lash left out) the train is linear,
//   M ẍ + C ẋ + K x = f0 + k_in s(t) + c_in ṡ(t),
// so at cam speed ω (θ = ω t) its steady response to the lift's Fourier
// series is the sum over the harmonics of the frequency response at h ω, and
// every force that is linear in (x, ẋ, s, ṡ) is a Fourier series in θ too.
// The train's jump speed is the lowest ω at which the smallest held force over
// a revolution reaches zero. Figures are in the train's coordinates (m, or rad
// for an oscillating arm) and the lift's unit.
#pragma once

#include <Eigen/Core>
#include <complex>
#include <string>
#include <vector>

#include "geometry/motion_law.h"

namespace camdyn {

/// One monitored force of the linear train: F = a·x + b·ẋ + e s + f ṡ + constant [N | N m]
/// (x the train's coordinates, s the lift [m | rad], ṡ = ds/dt).
struct LinearForce {
  Eigen::VectorXd a;      ///< ∂F/∂x (n) [N/m]
  Eigen::VectorXd b;      ///< ∂F/∂ẋ (n) [N s/m]
  double e = 0.0;         ///< ∂F/∂s [N/m]
  double f = 0.0;         ///< ∂F/∂ṡ [N s/m]
  double constant = 0.0;  ///< F at rest with s = 0 [N]
  std::string name;       ///< for reports ("contact", "link 1", "spring 0 frame end")
};

/// A linear train M ẍ + C ẋ + K x = f0 + k_in s(t) + c_in ṡ(t) (n coordinates).
struct LinearTrain {
  Eigen::MatrixXd M;     ///< mass matrix (n×n) [kg]
  Eigen::MatrixXd C;     ///< damping matrix (n×n) [N s/m]
  Eigen::MatrixXd K;     ///< stiffness matrix (n×n) [N/m], invertible (a spring holds every coordinate)
  Eigen::VectorXd f0;    ///< constant load (n), the preloads [N]
  Eigen::VectorXd k_in;  ///< load per unit lift (n) [N/m]
  Eigen::VectorXd c_in;  ///< load per unit lift rate (n) [N s/m]
  /// Forces that must stay > 0 (cam contact, links): the jump criterion.
  std::vector<LinearForce> held;
  /// Forces whose maximum is reported (spring frame ends).
  std::vector<LinearForce> peaks;
};

/// The lift as a Fourier series over one cam revolution [m | rad]:
/// s(θ) = mean + Re Σ_{h=1..H} S[h−1] e^{i h θ}.
struct LiftHarmonics {
  double mean = 0.0;                    ///< mean lift [m]
  std::vector<std::complex<double>> S;  ///< S_h, h = 1 … H [m]
};

/// The first `harmonics` (≥ 0) harmonics of the law's lift s(θ), θ the cam
/// angle [rad], by a direct DFT of max(1024, 8·harmonics) equally spaced samples.
/// Throws std::invalid_argument for a negative count.
LiftHarmonics lift_harmonics(const MotionLaw& law, int harmonics);

/// The extremes of the monitored forces over one revolution [N], in the order of
/// LinearTrain::held and LinearTrain::peaks.
struct TrainResponse {
  std::vector<double> min_held;   ///< min over θ of each held force
  std::vector<double> max_peaks;  ///< max over θ of each peak force
};

/// Steady periodic response at cam speed `omega` ≥ 0 [rad/s] (θ = ω t):
/// x(θ) = x̄ + Re Σ X_h e^{ihθ}, K x̄ = f0 + k_in·mean,
/// X_h = (K − (hω)² M + i hω C)⁻¹ (k_in + i hω c_in) S_h; the extremes of each
/// force over a grid of max(720, 16 H) angles, refined by golden section.
/// An undamped train run exactly at a resonance gives −inf / +inf.
/// Throws std::invalid_argument for mismatched sizes, a singular K or a bad ω.
TrainResponse linear_train_response(const LinearTrain& train, const LiftHarmonics& lift, double omega);

/// The lowest ω in (0, omega_max] at which the smallest held force over a
/// revolution reaches 0 [rad/s]: a scan over 400 equal steps, with the train's
/// undamped natural frequencies over each significant harmonic added (the
/// response is not monotone near resonances), then bisection to 1e−10
/// relative. 0 when a held force is not positive even statically; +inf when
/// none reaches 0 up to omega_max or nothing is held.
double linear_train_jump_speed(const LinearTrain& train, const LiftHarmonics& lift, double omega_max);

}  // namespace camdyn
