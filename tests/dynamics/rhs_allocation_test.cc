// The right-hand side must not allocate (it runs millions of times per
// optimisation): a counting global operator new checks it.
#include <gtest/gtest.h>

#include <atomic>
#include <cstdlib>
#include <new>

#include "allocation_counter.h"
#include "dynamics/model.h"
#include "scenes.h"

namespace camdyn {
namespace {

/// Heap allocations made by 100 right-hand-side calls (evaluation, state and
/// quadrature derivatives, root functions) at t = t0 + 1e-4 i, plus the
/// Jacobian every tenth call when `jacobian`.
long allocations_in_rhs_calls(const Model& model, Workspace& ws, const double* y, double t0 = 0.0,
                              bool jacobian = false) {
  Evaluation ev;
  double y_dot[StateLayout::kMax], q_dot[Model::kQuadratures], g[Model::kMaxRoots];
  double jac[StateLayout::kMax * StateLayout::kMax];
  const long before = camdyn::test::allocation_count();
  for (int i = 0; i < 100; ++i) {
    const double t = t0 + 1e-4 * i;
    evaluate(model, ws, t, y, ev);
    state_derivative(model, ev, y_dot);
    quadrature_derivative(ev, q_dot);
    root_functions(model, ws, ev, g);
    if (jacobian && i % 10 == 0) state_jacobian(model, ws, t, y, jac);
  }
  return camdyn::test::allocation_count() - before;
}

TEST(RightHandSide, AllocatesNothingInEveryTrackingMode) {
  for (const Tracking tracking : {Tracking::differential, Tracking::newton}) {
    SceneConfig scene = test::cycloidal_cam_scene(1000.0, ContactModel::lankarani_nikravesh);
    scene.mechanism.contact.tracking = tracking;
    scene.mechanism.follower.shape.inertia = 1e-6;
    scene.mechanism.contact.friction.mu = 0.1;
    const Model model = build_model(scene, "test");
    Workspace ws;
    const double y[StateLayout::kMax] = {0.005, 0.3, 0.8, 100.0};
    ws.u_warm = 0.8;
    EXPECT_EQ(allocations_in_rhs_calls(model, ws, y), 0) << tracking;
  }
}

TEST(RightHandSide, AllocatesNothingForAnyFollowerFrictionOrDrive) {
  for (const std::string& kind : test::follower_kinds()) {
    for (const Tracking tracking : {Tracking::differential, Tracking::newton}) {
      SceneConfig scene = test::fully_loaded_scene(kind, 1000.0, ContactModel::lankarani_nikravesh);
      const bool oscillating = scene.mechanism.follower.motion == FollowerMotion::oscillating;
      scene.mechanism.contact.tracking = tracking;
      const Model model = build_model(scene, "test");
      Workspace ws;
      double y[StateLayout::kMax] = {};
      y[0] = oscillating ? 0.05 : 0.005;
      y[1] = 0.3;
      if (model.layout.u) y[*model.layout.u] = 0.8;
      if (model.layout.spin) y[*model.layout.spin] = 100.0;
      y[*model.layout.cam_angle] = 0.8;
      y[*model.layout.cam_speed] = 100.0;
      y[*model.layout.motor_angle] = 0.81;
      y[*model.layout.motor_speed] = 100.0;
      ws.u_warm = 0.8;
      EXPECT_EQ(allocations_in_rhs_calls(model, ws, y, 0.0, true), 0) << kind << " " << tracking;
    }
  }
}

TEST(RightHandSide, AllocatesNothingWithTheGeneralPairFormOrAContourCam) {
  // The general form's search samples are made by make_workspace (once per worker).
  for (const bool contour : {false, true}) {
    for (const Tracking tracking : {Tracking::differential, Tracking::newton}) {
      SceneConfig scene = test::follower_scene("translating_roller", 1000.0, ContactModel::lankarani_nikravesh);
      scene.mechanism.contact.tracking = tracking;
      scene.mechanism.contact.pair_form = contour ? PairFormChoice::automatic : PairFormChoice::general;
      if (contour) test::use_eccentric_disc_contour(scene, 64);
      const Model model = build_model(scene, "test");
      Workspace ws = make_workspace(model);
      double y[StateLayout::kMax] = {0.002, 0.3};
      ws.u_warm = model.pair_guess(0.8);
      if (model.layout.u) y[*model.layout.u] = ws.u_warm;
      if (model.layout.v) y[*model.layout.v] = ws.v_warm;
      EXPECT_EQ(allocations_in_rhs_calls(model, ws, y, 0.8 / model.omega), 0)
          << tracking << (contour ? " contour" : " general");
    }
  }
}

TEST(RightHandSide, AllocatesNothingWithAnEightCoilSpringTrain) {
  // A bucket tappet whose spring has mass in 8 coils with coil clash, on a
  // seat, and a valve body behind a one-sided link with its own seat: every
  // kind of train element, 19 + 2 states.
  SceneConfig scene = test::follower_scene("translating_flat", 3000.0, ContactModel::hunt_crossley);
  FollowerConfig& f = scene.mechanism.follower;
  f.spring.stiffness = 35000.0;
  f.spring.preload = 250.0;
  f.spring.mass = 0.045;
  f.spring.coils = 8;
  f.spring.clash = CoilClashConfig{0.001, 1e8};
  f.seat = test::hunt_crossley_seat(2e-4);
  TrainBodyConfig valve;
  valve.name = "valve";
  valve.mass = 0.03;
  valve.link.stiffness = 1e8;
  valve.link.lash = 1e-5;
  valve.seat = f.seat;
  scene.mechanism.train.push_back(valve);
  const Model model = build_model(scene, "test");
  ASSERT_GE(model.layout.size, 21);
  Workspace ws = make_workspace(model);
  double y[StateLayout::kMax] = {};
  y[0] = 0.001;
  y[1] = 0.3;
  if (model.layout.u) y[*model.layout.u] = 0.8;
  for (int i = model.layout.core_size; i < model.layout.size; ++i) y[i] = (i % 2 == 0 ? 1e-4 : 0.1) * (i % 3);
  ws.u_warm = 0.8;
  EXPECT_EQ(allocations_in_rhs_calls(model, ws, y, 0.0, true), 0);
}

}  // namespace
}  // namespace camdyn
