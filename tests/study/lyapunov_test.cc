// The Lyapunov estimate with its tangent stretched by forward sensitivities
// (study/lyapunov.cc) against independent references:
// * the directional sensitivity run J·D against the whole sensitivity
//   Jacobian times D;
// * on Holmes' bouncing ball's stable period-1 orbit (a complex pair of
//   multipliers, |μ| = ρ): the tangent's λ over R revolutions against ln ρ of
//   the monodromy matrix the shooting took by central differences. Where
//   M = ρ T Rot T⁻¹ (T real: the real and imaginary parts of an
//   eigenvector), |M^R w| / |w| lies within ρ^R [1/κ, κ], κ = ‖T‖ ‖T⁻¹‖ in
//   the scaled max-norm the estimate measures with, so |λ_R − ln ρ| ≤ ln κ / R,
//   plus the difference between the two Jacobians (central differences at
//   10 √rtol agree with the sensitivities to about 1e-4, map_sensitivity_test.cc);
// * on the chaotic bouncing ball: λ by the tangent and by the neighbour
//   trajectory (the two-trajectory method, an independent estimate along a
//   trajectory that soon differs) agree within four standard errors of
//   their difference, each standard error by batch means over the
//   revolutions' stretches, and both are above chaos_threshold;
// * a model the sensitivities do not cover (friction): every revolution
//   falls back to the neighbour, counted and with the reason, and the
//   estimate is the two-trajectory one; "auto" takes the neighbour (as on
//   every map: it is the cheaper, bench/lyapunov_bench.cc).
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <complex>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

#include "map_jacobian_reference.h"
#include "study/periodic_orbit.h"
#include "study_paths.h"

namespace camdyn {
namespace {

using namespace test;  // NOLINT(google-build-using-namespace): the shared reference

// The max-norm condition number ‖T‖∞ ‖T⁻¹‖∞ (the norm induced by the max-norm is the largest row sum).
double max_norm_condition(const MatrixXd& T) {
  const auto norm = [](const MatrixXd& A) { return A.cwiseAbs().rowwise().sum().maxCoeff(); };
  return norm(T) * norm(T.inverse());
}

TEST(Lyapunov, DirectionalSensitivitiesAreTheJacobianTimesTheDirections) {
  const MapAt s = map_at(read_tight(kBouncingBall), 4);
  Workspace ws = make_workspace(s.model);
  const MapJacobian whole = sensitivity_jacobian(*s.map, s.point, 1, ws);
  ASSERT_TRUE(whole.ok) << whole.reason;
  const VectorXd scales = to_vector(s.map->scales());
  MatrixXd D(2, 2);
  D << 0.3 * scales[0], -scales[0], scales[1], 0.5 * scales[1];
  const MapJacobian product = sensitivity_product(*s.map, s.point, 1, D, ws);
  ASSERT_TRUE(product.ok) << product.reason;
  ASSERT_EQ(product.jacobian.cols(), 2);
  // The same run with other seeds: the same end, and J·D to the integration
  // tolerance (the error control weighs other columns; header of
  // map_jacobian_reference.h: two integrations agree to 1e-5 of ‖J‖ at rtol 1e-10, better at 1e-12).
  EXPECT_EQ(product.impacts, whole.impacts);
  const MatrixXd expected = whole.jacobian * D;
  EXPECT_LT((scales.cwiseInverse().asDiagonal() * (product.jacobian - expected)).norm(),
            kReferenceSpread * (scales.cwiseInverse().asDiagonal() * expected).norm())
      << product.jacobian << "\nexpected\n"
      << expected;
}

TEST(Lyapunov, OnAStableOrbitTheTangentTendsToTheLogOfTheSpectralRadius) {
  const PeriodicStudy study = read_tight(kBouncingBall);
  const MapAt s = map_at(study, 4);
  PeriodicOptions options = study.config.options;
  options.lyapunov_revolutions = 0;
  options.jacobian = JacobianMethod::finite_difference;  // the reference owes nothing to sensitivities
  const PeriodicAnalysis shot = find_periodic_orbit(*s.map, s.point, options);
  ASSERT_TRUE(shot.orbit && shot.orbit->stable && shot.orbit->period == 1);
  const std::vector<std::complex<double>>& mu = shot.orbit->multipliers;
  ASSERT_EQ(mu.size(), 2u);
  ASSERT_GT(std::abs(mu[0].imag()), 1e-3) << "the scene is meant to have a complex pair";
  const double rho = shot.orbit->spectral_radius();
  // κ of the real basis T = [Re v, Im v] of the scaled monodromy matrix.
  const Eigen::EigenSolver<MatrixXd> eigen(scaled(*s.map, shot.orbit->monodromy));
  ASSERT_EQ(eigen.info(), Eigen::Success);
  MatrixXd T(2, 2);
  T << eigen.eigenvectors().col(0).real(), eigen.eigenvectors().col(0).imag();
  const double kappa = max_norm_condition(T);

  constexpr int kR = 60;
  options.lyapunov_revolutions = kR;
  options.jacobian = JacobianMethod::sensitivity;
  const LyapunovEstimate e = estimate_lyapunov(*s.map, shot.orbit->fixed_point, options);
  EXPECT_EQ(e.method, JacobianMethod::sensitivity);
  EXPECT_EQ(e.sensitivity_revolutions, kR);
  EXPECT_EQ(e.fallback_revolutions, 0) << e.fallback_reason;
  EXPECT_EQ(e.impacts, kR);            // one a revolution
  constexpr double kJacobians = 1e-3;  // the two Jacobians' ln ρ: 1e-4 of |μ| ≈ 0.5, with margin
  EXPECT_NEAR(e.per_revolution, std::log(rho), std::log(kappa) / kR + kJacobians) << "κ " << kappa;
  // The reference trajectory is the sensitivity runs' own: each ends within
  // the runs' agreement a = 1e-6 of the map's (docs/periodic.md), and the
  // orbit contracts by ρ a revolution (within κ): it stays within κ a / (1 − ρ).
  const double distance = (to_vector(e.last.x) - to_vector(shot.orbit->fixed_point.x))
                              .cwiseQuotient(to_vector(s.map->scales()))
                              .cwiseAbs()
                              .maxCoeff();
  EXPECT_LT(distance, kappa * 1e-6 / (1 - rho));
}

// λ's standard error by batch means (study/periodic_orbit.h) against its
// closed form: ten batches whose values are all b (b = 0 … 9) have batch
// means 0 … 9, sample variance 55/6 and standard error √(55/6)/√10; a
// remainder of fewer than ten values is left out, and fewer than 20 values
// give no estimate.
TEST(Lyapunov, StandardErrorIsTheBatchMeansClosedForm) {
  std::vector<double> stretches;
  for (int b = 0; b < 10; ++b)
    for (int i = 0; i < 3; ++i) stretches.push_back(b);
  const double expected = std::sqrt(55.0 / 6.0) / std::sqrt(10.0);
  ASSERT_TRUE(lyapunov_standard_error(stretches));
  EXPECT_NEAR(*lyapunov_standard_error(stretches), expected, 1e-15);
  for (int i = 0; i < 9; ++i) stretches.push_back(1e3);  // 39 values: 3 a batch, the last 9 left out
  EXPECT_NEAR(*lyapunov_standard_error(stretches), expected, 1e-15);
  EXPECT_FALSE(lyapunov_standard_error(std::vector<double>(19, 1.0)));
  EXPECT_NEAR(*lyapunov_standard_error(std::vector<double>(20, 1.0)), 0.0, 1e-15);
}

// The class a Lyapunov estimate supports (docs/periodic.md): λ ± 2 standard
// errors wholly above chaos_threshold is chaotic, wholly within ±it
// quasi-periodic, anything else unresolved; without a standard error λ
// alone decides. The first case is the packaging arm at 1531.3 rpm, just
// past its period doubling, which λ alone called chaotic. A band wholly below
// 0 is a contraction, however slow, not a torus: unresolved.
TEST(Lyapunov, TheClassNeedsTheWholeTwoStandardErrorBand) {
  const auto estimate = [](double lambda, std::optional<double> se, bool recur = true) {
    LyapunovEstimate e;
    e.per_revolution = lambda;
    e.standard_error = se;
    e.samples_recur = recur;
    return e;
  };
  constexpr double kThreshold = 0.01;  // [1/revolution]
  EXPECT_EQ(lyapunov_class(estimate(0.0118, 0.0026), kThreshold), MotionKind::unresolved);
  EXPECT_EQ(lyapunov_class(estimate(0.0118, std::nullopt), kThreshold), MotionKind::chaotic);
  EXPECT_EQ(lyapunov_class(estimate(0.5, 0.1), kThreshold), MotionKind::chaotic);
  EXPECT_EQ(lyapunov_class(estimate(0.002, 0.001), kThreshold), MotionKind::quasi_periodic);
  EXPECT_EQ(lyapunov_class(estimate(0.0034, 0.0035), kThreshold), MotionKind::unresolved);
  EXPECT_EQ(lyapunov_class(estimate(-0.5, 0.01), kThreshold), MotionKind::unresolved);  // contracting
  EXPECT_EQ(lyapunov_class(estimate(-0.005, std::nullopt), kThreshold), MotionKind::quasi_periodic);
  EXPECT_EQ(lyapunov_class(estimate(-0.005, 0.001), kThreshold), MotionKind::unresolved);  // contracting slowly
  EXPECT_EQ(lyapunov_class(estimate(-0.003, 0.002), kThreshold), MotionKind::quasi_periodic);
  EXPECT_EQ(lyapunov_class(estimate(-0.004, 0.002), kThreshold), MotionKind::quasi_periodic);      // reaches 0
  EXPECT_EQ(lyapunov_class(estimate(0.0005, 0.0028, false), kThreshold), MotionKind::unresolved);  // drifting
  // Which evidence each unresolved class lacks, the first that fails.
  EXPECT_EQ(unresolved_reason(estimate(-0.5, 0.01)), UnresolvedReason::contracts);
  EXPECT_EQ(unresolved_reason(estimate(-0.005, 0.001, false)), UnresolvedReason::contracts);
  EXPECT_EQ(unresolved_reason(estimate(-0.02, std::nullopt)), UnresolvedReason::contracts);
  EXPECT_EQ(unresolved_reason(estimate(0.0005, 0.0028, false)), UnresolvedReason::drifts);
  EXPECT_EQ(unresolved_reason(estimate(0.0118, 0.0026)), UnresolvedReason::straddles);
  EXPECT_EQ(unresolved_reason(estimate(0.0034, 0.0035)), UnresolvedReason::straddles);
}

// A motion on a torus, sampled once a revolution, is a rotation by an
// irrational angle on a closed curve: by the three-gap theorem the first
// half's samples split the curve into gaps of at most three lengths, and
// the second half's fall inside them. A slow drift (a period-2 motion whose
// two clusters move 1e-5 of a scale every other revolution, as the packaging
// arm's just past its period doubling) leaves the first half's cloud by many
// of its spacings.
TEST(Lyapunov, ATorusRecursAndASlowDriftDoesNot) {
  const std::vector<double> scales = {1e-3, 1e-2};
  const double golden = (std::sqrt(5.0) - 1.0) / 2.0;  // [revolutions of the curve a sample]
  std::vector<std::vector<double>> torus, drift;
  for (int n = 0; n < 100; ++n) {
    const double phase = 2.0 * std::numbers::pi * golden * n;
    torus.push_back({0.25 + 2e-3 * std::cos(phase), 1.0 + 3e-2 * std::sin(phase)});
    const double side = n % 2 == 0 ? 1.0 : -1.0, grown = 1e-5 * (n / 2);  // [scales]
    drift.push_back({0.255 + side * (2.3e-3 + grown * scales[0]), 1.0 - side * grown * scales[1]});
  }
  EXPECT_TRUE(section_points_recur(torus, scales));
  EXPECT_FALSE(section_points_recur(drift, scales));
  EXPECT_FALSE(section_points_recur({torus.begin(), torus.begin() + 7}, scales));  // too few to tell
}

TEST(Lyapunov, OnTheChaoticBallTheTangentAgreesWithTheNeighbourTrajectory) {
  const PeriodicStudy study = read_tight(kChaoticBall, [](Json& doc) {
    doc["integrator"]["rtol"] = 1e-10;  // the study's own
    doc["integrator"]["atol"] = 1e-13;
  });
  const MapAt s = map_at(study, study.config.options.transient_revolutions);
  const PeriodicOptions& options = study.config.options;
  const auto estimate = [&](JacobianMethod method) {
    PeriodicOptions o = options;
    o.threads = 2;
    o.jacobian = method;
    return estimate_lyapunov(*s.map, s.point, o);
  };
  const LyapunovEstimate tangent = estimate(JacobianMethod::sensitivity);
  const LyapunovEstimate neighbour = estimate(JacobianMethod::finite_difference);
  EXPECT_EQ(tangent.method, JacobianMethod::sensitivity);
  EXPECT_EQ(neighbour.method, JacobianMethod::finite_difference);
  EXPECT_EQ(neighbour.fallback_revolutions, 0);
  EXPECT_EQ(tangent.sensitivity_revolutions + tangent.fallback_revolutions, tangent.revolutions);
  EXPECT_GT(tangent.sensitivity_revolutions, tangent.revolutions / 2) << tangent.fallback_reason;
  EXPECT_GT(tangent.per_revolution, options.chaos_threshold);
  EXPECT_GT(neighbour.per_revolution, options.chaos_threshold);
  ASSERT_TRUE(tangent.standard_error && neighbour.standard_error);
  EXPECT_GT(*tangent.standard_error, 0.0);
  const double se = std::hypot(*tangent.standard_error, *neighbour.standard_error);
  EXPECT_NEAR(tangent.per_revolution, neighbour.per_revolution, 4 * se)
      << "tangent " << tangent.per_revolution << ", neighbour " << neighbour.per_revolution;
}

TEST(Lyapunov, WithoutSensitivitiesEveryRevolutionFallsBackAndIsCounted) {
  const PeriodicStudy study = read_tight(kBouncingBall, [](Json& doc) {
    doc["mechanism"]["contact"]["friction"]["mu"] = 0.05;
    doc["integrator"]["rtol"] = 1e-10;
    doc["integrator"]["atol"] = 1e-13;
  });
  const MapAt s = map_at(study, 4);
  ASSERT_FALSE(sensitivity_unsupported(*s.map).empty());
  PeriodicOptions options = study.config.options;
  options.lyapunov_revolutions = 10;
  options.jacobian = JacobianMethod::sensitivity;
  const LyapunovEstimate forced = estimate_lyapunov(*s.map, s.point, options);
  EXPECT_EQ(forced.method, JacobianMethod::sensitivity);
  EXPECT_EQ(forced.fallback_revolutions, 10);
  EXPECT_EQ(forced.sensitivity_revolutions, 0);
  EXPECT_NE(forced.fallback_reason.find("friction"), std::string::npos) << forced.fallback_reason;
  options.jacobian = JacobianMethod::finite_difference;
  const LyapunovEstimate neighbour = estimate_lyapunov(*s.map, s.point, options);
  EXPECT_EQ(neighbour.fallback_revolutions, 0);
  // Every revolution the same neighbour step from the same state: the same λ.
  EXPECT_EQ(forced.per_revolution, neighbour.per_revolution);
  EXPECT_EQ(forced.impacts, neighbour.impacts);
  options.jacobian = JacobianMethod::automatic;
  EXPECT_FALSE(lyapunov_by_sensitivities(*s.map, options));
  const LyapunovEstimate automatic = estimate_lyapunov(*s.map, s.point, options);
  EXPECT_EQ(automatic.method, JacobianMethod::finite_difference);
  EXPECT_EQ(automatic.fallback_revolutions, 0);
  EXPECT_EQ(automatic.per_revolution, neighbour.per_revolution);
}

}  // namespace
}  // namespace camdyn
