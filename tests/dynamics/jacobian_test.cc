// The analytic Jacobian of the right-hand side against central finite
// differences (Ceres gradient_checker style), for every tracking mode, contact
// law and with friction.
#include <cmath>
#include <numbers>

#include <Eigen/Dense>
#include <gtest/gtest.h>

#include "dynamics/model.h"
#include "scenes.h"

namespace camdyn {
namespace {

struct JacobianCase {
  const char* tracking;
  const char* model;
  bool friction;
};

class JacobianTest : public ::testing::TestWithParam<JacobianCase> {};

TEST_P(JacobianTest, MatchesCentralFiniteDifferences) {
  const JacobianCase c = GetParam();
  SceneConfig scene = test::cycloidal_cam_scene(1200.0, c.model);
  scene.mechanism.contact.tracking = c.tracking;
  scene.mechanism.follower.damping = 3.0;
  scene.mechanism.follower.offset = 0.004;  // no symmetry to hide sign errors
  if (std::string(c.model) == "kelvin_voigt") {
    scene.mechanism.contact.exponent = 1.0;
    scene.mechanism.contact.stiffness = 1e8;
    scene.mechanism.contact.damping = 50.0;
  }
  if (c.friction) {
    scene.mechanism.follower.shape.inertia = 2e-6;
    scene.mechanism.contact.friction.mu = 0.15;
    scene.mechanism.contact.friction.regularization_velocity = 0.05;
  }
  const Model model = build_model(scene, "test");
  const int n = model.state_size;
  Workspace ws;
  ws.v0 = 0.3;
  const double omega = 1200.0 * 2 * std::numbers::pi / 60;
  for (double theta_deg : {30.0, 75.0, 200.0, 260.0}) {
    const double t = theta_deg * std::numbers::pi / 180 / omega;
    const LawSample s = model.law->eval(model.theta(t));
    // In contact with 5 µm of interference, approaching at 2 cm/s, slightly off the common normal.
    Eigen::Vector4d x(s.s - 5e-6, omega * s.ds - 0.02, model.theta(t) + 1e-4, 0.0);
    Eigen::VectorXd state = x.head(n);
    ws.u_warm = model.theta(t);
    if (model.index_spin >= 0) {
      // Spin for a slip of 1 cm/s, inside the regularisation band, where friction depends on slip.
      Evaluation probe;
      evaluate(model, ws, t, state.data(), probe);  // Ω = 0: slip₀ = t·v_c + σ ω r
      state(model.index_spin) = (probe.slip - 0.01) / model.cam.roller_radius;
    }
    Eigen::MatrixXd analytic(n, n);
    state_jacobian(model, ws, t, state.data(), analytic.data());

    Evaluation ev;
    evaluate(model, ws, t, state.data(), ev);
    ASSERT_GT(ev.normal_force, 0.0);
    Eigen::MatrixXd numeric(n, n);
    const Eigen::Vector4d scale(1e-3, 1.0, 1.0, omega);
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
            << c.tracking << " " << c.model << " row " << i << " col " << j << " at " << theta_deg << " deg";
    }
  }
}

INSTANTIATE_TEST_SUITE_P(
    Modes, JacobianTest,
    ::testing::Values(JacobianCase{"differential", "hertz", false}, JacobianCase{"newton", "hertz", false},
                      JacobianCase{"differential", "lankarani_nikravesh", false},
                      JacobianCase{"newton", "hunt_crossley", false}, JacobianCase{"differential", "kelvin_voigt", false},
                      JacobianCase{"newton", "flores", false}, JacobianCase{"differential", "lankarani_nikravesh", true},
                      JacobianCase{"newton", "lankarani_nikravesh", true}),
    [](const ::testing::TestParamInfo<JacobianCase>& p) {
      return std::string(p.param.tracking) + "_" + p.param.model + (p.param.friction ? "_friction" : "");
    });

}  // namespace
}  // namespace camdyn
