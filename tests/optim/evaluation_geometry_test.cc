// One optimiser evaluation builds its design's geometry and its model once,
// whatever the number of operating speeds: the law, the cam and its checks
// are made on the evaluating thread, the model is assembled on them at the
// first speed, and every speed sets its own on a copy (dynamics/model.h
// set_cam_speed; the contact stress constraint's model too). The simulations
// are those of models built from each speed's scene, to the bit.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "dynamics/cam_geometry.h"
#include "dynamics/model.h"
#include "dynamics/simulation.h"
#include "io/config.h"
#include "optim/optimize/objectives.h"
#include "optim/optimize/optimize_config.h"
#include "optim/simulation_pool.h"
#include "study/study.h"

namespace camdyn::optim {
namespace {

const ConfigSource kSource{"test.json", CAMDYN_SOURCE_DIR};

TEST(DesignEvaluation, ThreeOperatingSpeedsBuildTheGeometryAndTheModelOnce) {
  const Json doc = Json::parse(R"({
    "study": "optimize",
    "mechanism": {
      "cam": { "base_radius": 0.04, "rpm": 1000, "motion_law": "profiles/cycloidal_rise_return.json" },
      "follower": { "shape": { "type": "roller", "radius": 0.01 }, "mass": 0.3,
                    "spring": { "stiffness": 5000, "preload": 40 } },
      "contact": { "stiffness": { "from_materials": { "E1": 2.1e11, "nu1": 0.3, "E2": 2.1e11, "nu2": 0.3,
                                                     "width": 0.012 } }, "exponent": 1 } },
    "simulation": { "cycles": 2, "discard_cycles": 1, "output_step_deg": 1 },
    "integrator": { "rtol": 1e-6 },
    "design": { "segments": ["rise"], "control_points": 4 },
    "operating_rpm": [800, 1000, 1200],
    "objective": { "separation": 1.0 },
    "constraints": { "max_contact_stress": 5e9 }
  })");
  Json part;
  const SceneConfig scene = scene_from_study_json(doc, kSource, optimize_study_keys(), part);
  const OptimizeStudyConfig config = optimize_config_from_json(part, kSource);
  SimulationPool pool(2, "test.json");
  const DesignEvaluator evaluator(config, "test.json", pool);
  const long before = cam_geometry_builds(), models = model_builds();
  const DesignEvaluation e = evaluator.evaluate(scene, EvaluationSettings{}, true);
  EXPECT_EQ(cam_geometry_builds() - before, 1);
  ASSERT_TRUE(e.valid) << e.error;
  EXPECT_EQ(model_builds() - models, 1);
  EXPECT_GT(e.peak_contact_stress, 0.0);
  EXPECT_EQ(e.contact_stress_rpm, 1200.0);  // the rigid contact's pressure grows with the speed here
  ASSERT_EQ(e.speeds.size(), 3u);
  for (const SpeedResult& s : e.speeds) {
    SceneConfig at = scene;
    at.mechanism.cam.rpm = s.rpm;
    SimulationOptions options;
    options.record_series = false;
    const SimulationResult fresh = simulate_scene(at, "test.json", options);
    EXPECT_EQ(s.result.metrics.peak_contact_force, fresh.metrics.peak_contact_force) << s.rpm;
    EXPECT_EQ(s.result.solver.counters.steps, fresh.solver.counters.steps) << s.rpm;
  }
}

}  // namespace
}  // namespace camdyn::optim
