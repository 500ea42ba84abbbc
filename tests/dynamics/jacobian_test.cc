// The analytic Jacobian of the right-hand side against central finite
// differences (Ceres gradient_checker style), for every follower type,
// tracking mode, contact law, friction element and drive.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <numbers>
#include <string>

#include "dynamics/model.h"
#include "scenes.h"

namespace camdyn {
namespace {

struct JacobianCase {
  const char* kind;  ///< test::follower_scene kind
  const char* tracking;
  const char* model;
  bool friction;                         ///< contact friction (with roller inertia for a roller)
  bool guide = false;                    ///< guide friction (translating)
  bool pivot = false;                    ///< pivot friction (oscillating)
  const char* drive = "constant_speed";  ///< or "shaft" (constant-speed motor), "motor" (torque–speed motor)
};

void PrintTo(const JacobianCase& c, std::ostream* os) {
  *os << c.kind << " " << c.tracking << " " << c.model << (c.friction ? " friction" : "") << (c.guide ? " guide" : "")
      << (c.pivot ? " pivot" : "") << " " << c.drive;
}

class JacobianTest : public ::testing::TestWithParam<JacobianCase> {};

TEST_P(JacobianTest, MatchesCentralFiniteDifferences) {
  const JacobianCase c = GetParam();
  const double rpm = 1200.0;
  SceneConfig scene = test::follower_scene(c.kind, rpm, parse_enum<ContactModel>(c.model));
  const bool oscillating = scene.mechanism.follower.motion == FollowerMotion::oscillating;
  scene.mechanism.contact.tracking = parse_enum<Tracking>(c.tracking);
  scene.mechanism.follower.damping = oscillating ? 0.02 : 3.0;
  if (!oscillating) scene.mechanism.follower.offset = 0.004;  // no symmetry to hide sign errors
  if (std::string(c.model) == "kelvin_voigt") {
    scene.mechanism.contact.exponent = 1.0;
    scene.mechanism.contact.stiffness = 1e8;
    scene.mechanism.contact.damping = 50.0;
  }
  if (c.friction) {
    if (scene.mechanism.follower.shape.type == FollowerShape::roller) scene.mechanism.follower.shape.inertia = 2e-6;
    scene.mechanism.contact.friction.mu = 0.15;
    scene.mechanism.contact.friction.regularization_velocity = 0.05;
  }
  if (c.guide) scene.mechanism.follower.guide_friction = GuideFrictionConfig{0.2, 0.5};
  if (c.pivot) scene.mechanism.follower.pivot_friction = PivotFrictionConfig{0.2, 0.005, 0.01};
  const std::string drive = c.drive;
  if (drive != "constant_speed") {
    DriveConfig& d = scene.mechanism.cam.drive;
    d.type = Drive::shaft;
    d.inertia = 0.01;
    d.torsional_stiffness = 2e4;
    d.torsional_damping = 0.5;
    if (drive == "motor") d.motor = MotorConfig{Motor::torque_speed, 20.0, 1500.0, 5e-3};
  }
  const Model model = build_model(scene, "test");
  const int n = model.layout.size;
  Workspace ws;
  ws.v0 = 0.3;
  ws.motor_phase = 1e-3;
  const double omega = rpm * 2 * std::numbers::pi / 60;
  for (double theta_deg : {30.0, 75.0, 200.0, 260.0}) {
    const double t = theta_deg * std::numbers::pi / 180 / omega;
    const double theta = model.theta(t) + (model.layout.cam_angle ? 2e-3 : 0.0);  // a shaft twisted a little
    const LawSample s = model.law->eval(theta);
    // In contact with a few µm of interference, approaching at 2 cm/s, slightly off the common normal.
    Eigen::VectorXd state = Eigen::VectorXd::Zero(n);
    Eigen::VectorXd scale = Eigen::VectorXd::Ones(n);
    state(0) = s.s - (oscillating ? 5e-5 : 5e-6);
    state(1) = omega * s.ds - (oscillating ? 0.2 : 0.02);
    scale(0) = oscillating ? 1e-2 : 1e-3;
    if (model.layout.u) state(*model.layout.u) = theta + 1e-4;
    if (model.layout.cam_angle) {
      state(*model.layout.cam_angle) = theta;
      state(*model.layout.cam_speed) = 1.01 * omega;
      scale(*model.layout.cam_speed) = omega;
    }
    if (model.layout.motor_angle) {
      state(*model.layout.motor_angle) = theta + 3e-3;
      state(*model.layout.motor_speed) = 0.99 * omega;
      scale(*model.layout.motor_speed) = omega;
    }
    ws.u_warm = theta;
    if (model.layout.spin) {
      // Spin for a slip of 1 cm/s, inside the regularisation band, where friction depends on slip.
      Evaluation probe;
      evaluate(model, ws, t, state.data(), probe);  // Ω = 0: slip₀
      state(*model.layout.spin) = (probe.slip - 0.01) / model.follower.radius;
      scale(*model.layout.spin) = omega;
    }
    Eigen::MatrixXd analytic(n, n);
    state_jacobian(model, ws, t, state.data(), analytic.data());

    Evaluation ev;
    evaluate(model, ws, t, state.data(), ev);
    ASSERT_GT(ev.normal_force, 0.0) << theta_deg;
    if (c.friction) {
      ASSERT_NE(ev.friction_force, 0.0);
    }
    if (c.guide) {
      ASSERT_NE(ev.guide_friction, 0.0);
    }
    if (c.pivot) {
      ASSERT_NE(ev.pivot_friction, 0.0);
    }
    Eigen::MatrixXd numeric(n, n);
    for (int j = 0; j < n; ++j) {
      const double h = 1e-6 * scale(j);
      Eigen::VectorXd plus = state, minus = state, f_plus(n), f_minus(n);
      plus(j) += h;
      minus(j) -= h;
      evaluate(model, ws, t, plus.data(), ev);
      state_derivative(model, ev, f_plus.data());
      evaluate(model, ws, t, minus.data(), ev);
      state_derivative(model, ev, f_minus.data());
      numeric.col(j) = (f_plus - f_minus) / (2 * h);
    }
    // Central differences with h = 1e-6·scale: truncation O(h²) and rounding
    // O(ε/h · row scale) leave ~1e-6 relative agreement per entry, plus a
    // rounding floor relative to the row's largest entry (the contact
    // stiffness dwarfs the friction terms by eight decades).
    for (int i = 0; i < n; ++i) {
      const double row_scale = numeric.row(i).cwiseAbs().maxCoeff() + 1e-12;
      for (int j = 0; j < n; ++j)
        EXPECT_NEAR(analytic(i, j), numeric(i, j), 1e-5 * std::abs(numeric(i, j)) + 1e-9 * row_scale)
            << model.layout.names[i] << " by " << model.layout.names[j] << " at " << theta_deg << " deg";
    }
  }
}

INSTANTIATE_TEST_SUITE_P(
    TranslatingRoller, JacobianTest,
    ::testing::Values(JacobianCase{"translating_roller", "differential", "hertz", false},
                      JacobianCase{"translating_roller", "newton", "hertz", false},
                      JacobianCase{"translating_roller", "differential", "lankarani_nikravesh", false},
                      JacobianCase{"translating_roller", "newton", "hunt_crossley", false},
                      JacobianCase{"translating_roller", "differential", "kelvin_voigt", false},
                      JacobianCase{"translating_roller", "newton", "flores", false},
                      JacobianCase{"translating_roller", "differential", "lankarani_nikravesh", true},
                      JacobianCase{"translating_roller", "newton", "lankarani_nikravesh", true},
                      JacobianCase{"translating_roller", "newton", "lankarani_nikravesh", false, true}));

INSTANTIATE_TEST_SUITE_P(
    OtherFollowers, JacobianTest,
    ::testing::Values(JacobianCase{"translating_flat", "differential", "hertz", false},
                      JacobianCase{"translating_flat", "newton", "lankarani_nikravesh", false},
                      JacobianCase{"translating_flat", "differential", "lankarani_nikravesh", true},
                      JacobianCase{"translating_flat", "newton", "hunt_crossley", true, true},
                      JacobianCase{"translating_mushroom", "differential", "lankarani_nikravesh", true},
                      JacobianCase{"translating_mushroom", "newton", "hertz", false},
                      JacobianCase{"oscillating_roller", "differential", "lankarani_nikravesh", false},
                      JacobianCase{"oscillating_roller", "newton", "hertz", false},
                      JacobianCase{"oscillating_roller", "differential", "lankarani_nikravesh", true},
                      JacobianCase{"oscillating_roller", "newton", "lankarani_nikravesh", false, false, true},
                      JacobianCase{"oscillating_flat", "differential", "lankarani_nikravesh", true},
                      JacobianCase{"oscillating_flat", "newton", "lankarani_nikravesh", false, false, true},
                      JacobianCase{"oscillating_mushroom", "differential", "hertz", true}));

INSTANTIATE_TEST_SUITE_P(
    ShaftDrive, JacobianTest,
    ::testing::Values(JacobianCase{"translating_roller", "differential", "lankarani_nikravesh", false, false, false,
                                   "shaft"},
                      JacobianCase{"translating_roller", "newton", "hertz", true, false, false, "motor"},
                      JacobianCase{"oscillating_flat", "newton", "lankarani_nikravesh", true, false, true, "motor"},
                      JacobianCase{"translating_flat", "differential", "hertz", true, true, false, "shaft"}));

}  // namespace
}  // namespace camdyn
