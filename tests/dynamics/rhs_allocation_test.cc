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
    double y[4] = {0.005, 0.3, 0.8, 100.0}, y_dot[4], q_dot[Model::kQuadratures], g[2];
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

}  // namespace
}  // namespace camdyn
