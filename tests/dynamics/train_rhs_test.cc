// The follower train's right-hand side (docs/model.md §12): its exact
// Jacobian (each element's ∂F/∂d, ∂F/∂ḋ assembled by dynamics/follower_train.cc,
// the core by dual numbers) against central finite differences of the
// right-hand side, with every kind of element engaged; and no allocation in
// the evaluation, the derivatives, the root functions or the Jacobian.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "allocation_counter.h"
#include "dynamics/initial_state.h"
#include "dynamics/model.h"
#include "scenes.h"

namespace camdyn {
namespace {

/// A translating roller follower with a seat, a stop and a spring with mass
/// whose coils clash, driving a valve through a one-sided link with lash and
/// a rocker tip through a two-sided joint.
SceneConfig train_scene() {
  SceneConfig s = test::cycloidal_cam_scene(1500.0, ContactModel::hunt_crossley);
  FollowerConfig& f = s.mechanism.follower;
  f.damping = 2.0;
  f.spring.mass = 0.03;
  f.spring.coils = 5;
  f.spring.damping_ratio = 0.05;
  f.spring.clash = CoilClashConfig{1e-5, 1e8};
  SeatConfig seat;
  seat.position = 2e-5;
  seat.model = ContactModel::lankarani_nikravesh;
  seat.stiffness = 1e9;
  seat.exponent = 1.5;
  f.seat = seat;
  SeatConfig stop = seat;
  stop.position = 0.05;
  f.stop = stop;
  TrainBodyConfig valve{"valve", 0.06, 1.0, {1.5, 2e7, 50.0, 1e-5, true}, {}, {}, {}, {}};
  valve.spring.stiffness = 30000.0;
  valve.spring.preload = 200.0;
  SeatConfig valve_seat;
  valve_seat.position = 5e-5;  // above the valve's kinematic lift on the base circle: resting on it
  valve_seat.model = ContactModel::kelvin_voigt;
  valve_seat.stiffness = 5e8;
  valve_seat.exponent = 1.0;
  valve_seat.damping = 2000.0;
  valve.seat = valve_seat;
  TrainBodyConfig tip{"tip", 0.02, 0.0, {1.0, 5e7, 20.0, 0.0, false}, {}, {}, {}, {}};
  tip.spring.stiffness = 5000.0;
  tip.spring.preload = 20.0;
  s.mechanism.train = {valve, tip};
  return s;
}

/// A state on the law with the train disturbed so that every element works:
/// the follower pressed into its seat, the coils closing, the link and the
/// valve seat compressed.
std::vector<double> engaged_state(const SceneConfig& scene, const Model& model, Workspace& ws) {
  std::vector<double> y(StateLayout::kMax, 0.0);
  EXPECT_FALSE(initial_state(scene, model, ws, y.data()));
  y[1] = 0.05;  // q̇ [m/s]
  for (std::size_t c = 1; c < model.train.coordinates.size(); ++c) {
    const TrainCoordinate& tc = model.train.coordinates[c];
    y[static_cast<std::size_t>(tc.position)] += 2e-5 * std::sin(1.0 + static_cast<double>(c));
    y[static_cast<std::size_t>(tc.velocity)] = 0.03 * std::cos(2.0 * static_cast<double>(c));
  }
  return y;
}

/// The exact Jacobian of `scene`'s model at `t` against central differences
/// (a shaft's cam at the nominal angle and speed).
void expect_jacobian_matches_differences(const SceneConfig& scene, double t) {
  const Model model = build_model(scene, "test");
  ASSERT_TRUE(model.exact_jacobian());
  Workspace ws = make_workspace(model);
  std::vector<double> y = engaged_state(scene, model, ws);
  if (model.layout.cam_angle) {
    y[static_cast<std::size_t>(*model.layout.cam_angle)] = model.theta(t);
    y[static_cast<std::size_t>(*model.layout.cam_speed)] = model.omega;
  }
  const int n = model.layout.size;
  ASSERT_GT(n, model.layout.core_size + 10);
  std::vector<double> jacobian(static_cast<std::size_t>(n * n));
  state_jacobian(model, ws, t, y.data(), jacobian.data());
  Evaluation ev;
  std::vector<double> up(static_cast<std::size_t>(n)), down(static_cast<std::size_t>(n));
  for (int j = 0; j < n; ++j) {
    const double h = 1e-6 * std::max(1e-3, std::abs(y[static_cast<std::size_t>(j)]));  // above the roundoff of q̈ ~ 1e5
    std::vector<double> x = y;
    x[static_cast<std::size_t>(j)] += h;
    evaluate(model, ws, t, x.data(), ev);
    state_derivative(model, ev, up.data());
    x[static_cast<std::size_t>(j)] -= 2.0 * h;
    evaluate(model, ws, t, x.data(), ev);
    state_derivative(model, ev, down.data());
    for (int i = 0; i < n; ++i) {
      const double fd = (up[static_cast<std::size_t>(i)] - down[static_cast<std::size_t>(i)]) / (2.0 * h);
      const double exact = jacobian[static_cast<std::size_t>(i + n * j)];
      EXPECT_NEAR(exact, fd, 1e-5 * std::max(1.0, std::abs(fd)))
          << model.layout.names[static_cast<std::size_t>(i)] << " by "
          << model.layout.names[static_cast<std::size_t>(j)];
    }
  }
}

TEST(FollowerTrainRhs, ExactJacobianMatchesCentralDifferences) {
  expect_jacobian_matches_differences(train_scene(), 0.0);
}

// A gas load on the valve (docs/model.md §12, "Gas load"), its pressure
// changing with the cam angle: with a shaft, the cam angle is a state, and
// the load's ∂F/∂θ enters the valve's row.
TEST(FollowerTrainRhs, ExactJacobianWithAGasLoadOnAShaft) {
  SceneConfig scene = train_scene();
  GasLoadConfig gas;
  gas.area = 7e-4;
  gas.pressure = "table";
  gas.crank_deg = {100.0, 300.0, 500.0};  // crank 0 (t = 0) inside the segment that closes the cycle
  gas.pressure_pa = {1e5, 6e5, 3e5};
  scene.mechanism.train[0].gas = gas;
  DriveConfig& d = scene.mechanism.cam.drive;
  d.type = Drive::shaft;
  d.inertia = 0.01;
  d.torsional_stiffness = 2e4;
  d.torsional_damping = 0.5;
  expect_jacobian_matches_differences(scene, 0.0);
}

TEST(FollowerTrainRhs, AllocatesNothing) {
  const SceneConfig scene = train_scene();
  const Model model = build_model(scene, "test");
  Workspace ws = make_workspace(model);
  const std::vector<double> y = engaged_state(scene, model, ws);
  Evaluation ev;
  std::vector<double> y_dot(StateLayout::kMax), q_dot(Model::kQuadratures),
      g(static_cast<std::size_t>(model.root_count()));
  std::vector<double> jacobian(static_cast<std::size_t>(model.layout.size * model.layout.size));
  const long before = test::allocation_count();
  for (int i = 0; i < 50; ++i) {
    evaluate(model, ws, 1e-4 * i, y.data(), ev);
    state_derivative(model, ev, y_dot.data());
    quadrature_derivative(ev, q_dot.data());
    root_functions(model, ws, ev, g.data());
    if (i % 10 == 0) state_jacobian(model, ws, 1e-4 * i, y.data(), jacobian.data());
  }
  EXPECT_EQ(test::allocation_count() - before, 0);
}

// A spring with mass lumped in a chain: the Jacobian's half-bandwidth
// (what the banded solver is given) does not grow with the coils, and every
// nonzero of the exact Jacobian lies within it.
TEST(FollowerTrainRhs, CoilChainJacobianStaysInAFixedBand) {
  int first_band = -1;
  for (const int coils : {4, 8, 16}) {
    SceneConfig scene = train_scene();
    scene.mechanism.train.clear();
    scene.mechanism.follower.stop.reset();
    scene.mechanism.follower.spring.coils = coils;
    const Model model = build_model(scene, "test");
    Workspace ws = make_workspace(model);
    const std::vector<double> y = engaged_state(scene, model, ws);
    const int n = model.layout.size;
    ASSERT_EQ(n, model.layout.core_size + 2 * coils);
    const int band = train_jacobian_bandwidth(model.train, model.layout.core_size);
    if (first_band < 0) first_band = band;
    EXPECT_EQ(band, first_band) << coils << " coils";
    // Neighbouring lumps couple positions to velocities two states apart: at least 3.
    EXPECT_GE(band, 3);
    std::vector<double> jacobian(static_cast<std::size_t>(n * n));
    state_jacobian(model, ws, 0.0, y.data(), jacobian.data());
    int widest = 0;
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i)
        if (jacobian[static_cast<std::size_t>(i + n * j)] != 0.0) widest = std::max(widest, std::abs(i - j));
    EXPECT_LE(widest, band) << coils << " coils";
    EXPECT_EQ(widest, band) << coils << " coils: the band is tight";
  }
}

}  // namespace
}  // namespace camdyn
