// The Poincaré map's sensitivity Jacobian of a follower train with an 8-coil
// valve spring against a closed form: on the linear train of
// tests/dynamics/linear_train_case.h (a flat follower on a harmonic lift,
// Kelvin–Voigt contact, two-sided links), below its jump speed every contact
// and link stays held, the train is linear and time-invariant with a periodic
// forcing, and its map over one revolution is affine, x ↦ exp(A T) x + c.
// The Jacobian's eigenvalues (the Floquet multipliers) are therefore
// exp(λ T), λ the eigenvalues of the train's state matrix A, written from the
// reference's own rows (tests/dynamics/linear_train_reference.h), not from
// the model's Jacobian. The eigenvalues are the same in any coordinates, so
// the check needs neither the map's coordinate order nor its scales.
//
// Tolerance. The sensitivities ride on the same integration as the map at
// rtol = 1e-10, so each entry carries an error of that order times the
// revolution's amplification; 1e-6 of the spectral radius leaves a margin
// of 1e3 above it and is far below what a missing Jacobian term gives (a
// coil's stiffness left out moves the lightly damped surge multipliers by
// order one).
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <complex>
#include <numbers>
#include <vector>

#include "common/constants.h"
#include "dynamics/map_sensitivity.h"
#include "dynamics/poincare_map.h"
#include "dynamics/simulation.h"
#include "tests/dynamics/linear_train_case.h"

namespace camdyn {
namespace {

constexpr double kMultiplierAgreement = 1e-6;  // of the spectral radius (see the header comment)

TEST(MapSensitivity, EightCoilTrainMultipliersAreTheHeldTrainsClosedForm) {
  test::LinearTrainCase c = test::linear_train_case(1, false, 8);
  c.scene.integrator.rtol = 1e-10;
  c.scene.integrator.atol = 1e-14;
  const double jump = test::reference_jump_speed(c.reference, test::kLift, 1e4) * 60.0 / kTwoPi;  // [rpm]
  c.scene.mechanism.cam.rpm = 0.6 * jump;
  const Model model = build_model(c.scene, "test");
  const PoincareMap map(c.scene, model, "test");
  ASSERT_EQ(map.dimension(), 20) << "follower, valve and its 8 coil lumps, each a position and a rate";

  Workspace ws = make_workspace(model);
  SimulationOptions run;
  run.record_series = false;
  const SimulationResult transient = simulate(map.scene_for(3), model, ws, run);
  ASSERT_EQ(transient.solver.termination, Termination::converged) << transient.solver.message;
  const MapJacobian sens = sensitivity_jacobian(map, map.point(transient), 1, ws);
  ASSERT_TRUE(sens.ok) << sens.reason;
  ASSERT_EQ(sens.impacts, 0) << "the train must stay held for the map to be affine";
  ASSERT_EQ(sens.events, 0);

  const Eigen::VectorXcd lambda = test::state_matrix_eigenvalues(c.reference);
  ASSERT_EQ(lambda.size(), 20);
  std::vector<std::complex<double>> expected;
  for (const std::complex<double>& l : lambda) expected.push_back(std::exp(l * map.period()));
  const Eigen::VectorXcd found = Eigen::EigenSolver<Eigen::MatrixXd>(sens.jacobian).eigenvalues();
  double radius = 0.0;
  for (const std::complex<double>& m : expected) radius = std::max(radius, std::abs(m));
  ASSERT_GT(radius, 1e-3) << "the check needs multipliers well above the round-off";
  // Match each closed-form multiplier with the nearest one found, each used once.
  std::vector<std::complex<double>> left(found.begin(), found.end());
  for (const std::complex<double>& m : expected) {
    const auto nearest = std::min_element(
        left.begin(), left.end(), [&](const auto& a, const auto& b) { return std::abs(a - m) < std::abs(b - m); });
    EXPECT_LT(std::abs(*nearest - m), kMultiplierAgreement * radius) << "closed form " << m << ", found " << *nearest;
    left.erase(nearest);
  }
}

}  // namespace
}  // namespace camdyn
