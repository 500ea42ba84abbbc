// The right-hand side must not allocate (it runs millions of times per
// optimisation): a counting global operator new checks it.
#include <atomic>
#include <cstdlib>
#include <new>

#include <gtest/gtest.h>

#include "allocation_counter.h"

#include "dynamics/model.h"
#include "scenes.h"


namespace camdyn {
namespace {

TEST(RightHandSide, AllocatesNothingInEveryTrackingMode) {
  for (const char* tracking : {"differential", "newton"}) {
    SceneConfig scene = test::cycloidal_cam_scene(1000.0, "lankarani_nikravesh");
    scene.mechanism.contact.tracking = tracking;
    scene.mechanism.follower.shape.inertia = 1e-6;
    scene.mechanism.contact.friction.mu = 0.1;
    const Model model = build_model(scene, "test");
    Workspace ws;
    Evaluation ev;
    double y[Model::kMaxState] = {0.005, 0.3, 0.8, 100.0}, y_dot[Model::kMaxState], q_dot[Model::kQuadratures], g[2];
    ws.u_warm = 0.8;
    const long before = camdyn::test::allocation_count();
    for (int i = 0; i < 100; ++i) {
      const double t = 1e-4 * i;
      evaluate(model, ws, t, y, ev);
      state_derivative(model, ev, y_dot);
      quadrature_derivative(ev, q_dot);
      root_functions(model, ws, ev, g);
    }
    EXPECT_EQ(camdyn::test::allocation_count() - before, 0) << tracking;
  }
}

TEST(RightHandSide, AllocatesNothingForAnyFollowerFrictionOrDrive) {
  for (const std::string& kind : test::follower_kinds()) {
    for (const char* tracking : {"differential", "newton"}) {
      SceneConfig scene = test::follower_scene(kind, 1000.0, "lankarani_nikravesh");
      const bool oscillating = scene.mechanism.follower.motion == "oscillating";
      scene.mechanism.contact.tracking = tracking;
      scene.mechanism.contact.friction.mu = 0.1;
      if (scene.mechanism.follower.shape.type == "roller") scene.mechanism.follower.shape.inertia = 1e-6;
      if (oscillating) scene.mechanism.follower.pivot_friction = PivotFrictionConfig{0.1, 0.005, 1e-4};
      else scene.mechanism.follower.guide_friction = GuideFrictionConfig{0.1, 1e-4};
      scene.mechanism.cam.drive.type = "shaft";
      scene.mechanism.cam.drive.inertia = 0.01;
      scene.mechanism.cam.drive.torsional_stiffness = 1e4;
      scene.mechanism.cam.drive.motor = MotorConfig{"torque_speed", 10.0, 2000.0, 1e-3};
      const Model model = build_model(scene, "test");
      Workspace ws;
      Evaluation ev;
      double y[Model::kMaxState] = {}, y_dot[Model::kMaxState], q_dot[Model::kQuadratures], g[2];
      double jacobian[Model::kMaxState * Model::kMaxState];
      y[0] = oscillating ? 0.05 : 0.005;
      y[1] = 0.3;
      if (model.index_u >= 0) y[model.index_u] = 0.8;
      if (model.index_spin >= 0) y[model.index_spin] = 100.0;
      y[model.index_cam_angle] = 0.8;
      y[model.index_cam_speed] = 100.0;
      y[model.index_motor_angle] = 0.81;
      y[model.index_motor_speed] = 100.0;
      ws.u_warm = 0.8;
      const long before = camdyn::test::allocation_count();
      for (int i = 0; i < 100; ++i) {
        const double t = 1e-4 * i;
        evaluate(model, ws, t, y, ev);
        state_derivative(model, ev, y_dot);
        quadrature_derivative(ev, q_dot);
        root_functions(model, ws, ev, g);
        if (i % 10 == 0) state_jacobian(model, ws, t, y, jacobian);
      }
      EXPECT_EQ(camdyn::test::allocation_count() - before, 0) << kind << " " << tracking;
    }
  }
}

TEST(RightHandSide, AllocatesNothingWithTheGeneralPairFormOrAContourCam) {
  // The general form's search samples are made by prepare_workspace (once per run).
  for (const bool contour : {false, true}) {
    for (const char* tracking : {"differential", "newton"}) {
      SceneConfig scene = test::follower_scene("translating_roller", 1000.0, "lankarani_nikravesh");
      scene.mechanism.contact.tracking = tracking;
      scene.mechanism.contact.pair_form = contour ? "auto" : "general";
      if (contour) test::use_eccentric_disc_contour(scene, 64);
      const Model model = build_model(scene, "test");
      Workspace ws;
      prepare_workspace(model, ws);
      Evaluation ev;
      double y[Model::kMaxState] = {0.002, 0.3}, y_dot[Model::kMaxState], q_dot[Model::kQuadratures], g[2];
      ws.u_warm = model.pair_guess(0.8);
      if (model.index_u >= 0) y[model.index_u] = ws.u_warm;
      if (model.index_v >= 0) y[model.index_v] = ws.v_warm;
      const long before = camdyn::test::allocation_count();
      for (int i = 0; i < 100; ++i) {
        evaluate(model, ws, 0.8 / model.omega + 1e-5 * i, y, ev);
        state_derivative(model, ev, y_dot);
        quadrature_derivative(ev, q_dot);
        root_functions(model, ws, ev, g);
      }
      EXPECT_EQ(camdyn::test::allocation_count() - before, 0) << tracking << (contour ? " contour" : " general");
    }
  }
}

}  // namespace
}  // namespace camdyn
