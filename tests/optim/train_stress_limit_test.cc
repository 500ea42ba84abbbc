// An optimize study on a follower train holds its rigid figures on the held
// train (docs/model.md §12, "Rigid figures of a train"), never on the
// follower alone: on studies/valvetrain/optimize_train.json with steel line
// contact, the stage's pressure probe sees a design over a
// constraints.max_contact_stress that the held train's pressure (computed
// here from held_train + held_train_values) breaks and the follower alone
// does not, and the required preload keeps the held train's contact and link
// forces at P_min up to the top speed.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "common/constants.h"
#include "contact/hertz_pressure.h"
#include "dynamics/held_train.h"
#include "dynamics/held_train_force.h"
#include "io/config.h"
#include "optim/optimize/design.h"
#include "optim/optimize/optimize.h"
#include "optim/optimize/rigid_design.h"
#include "optim/optimize/rigid_limits.h"

namespace camdyn::optim {
namespace {

const std::string kTrainStudy = std::string(CAMDYN_SOURCE_DIR) + "/studies/valvetrain/optimize_train.json";

OptimizeStudy steel_train_study(std::vector<std::string> overrides) {
  overrides.insert(overrides.begin(),
                   {"mechanism.contact={\"model\": \"kelvin_voigt\", \"exponent\": 1, \"damping\": 300, "
                    "\"stiffness\": {\"from_materials\": {\"E1\": 2.1e11, \"nu1\": 0.3, \"E2\": 2.1e11, "
                    "\"nu2\": 0.3, \"width\": 0.012}}}"});
  return read_optimize_study(load_config_json(kTrainStudy, overrides),
                             ConfigSource{kTrainStudy, CAMDYN_SOURCE_DIR "/studies/valvetrain"});
}

/// The held train's peak Hertz pressure of `scene` over the study's speeds
/// [Pa]: a flat tappet (κ = 1 / (r_b + s + s''), lever 1) on 20 mm base circle.
double held_peak_pressure(const OptimizeStudy& study, const SceneConfig& scene) {
  const Model model = build_model(scene, "test.json");
  const int n = RigidContactForce::kHeldAngles;
  const GridSignal law = grid_signal([&](double theta) { return model.law->eval(theta); }, n);
  const double e_star = 2.1e11 / (2.0 * (1.0 - 0.3 * 0.3));  // [Pa]
  double peak = 0.0;
  for (const double rpm : study.config.operating_rpm) {
    const Eigen::VectorXd p = held_train_values(held_train(model), law, rpm * kTwoPi / 60.0)[0];
    for (int i = 0; i < n; ++i) {
      const LawSample s = model.law->eval(kTwoPi * i / n);
      peak = std::max(peak, hertz_line_pressure(p[i], 0.012, e_star, 1.0 / (0.02 + s.s + s.d2s)));
    }
  }
  return peak;
}

// The stage's pressure rows come from the probe (optim/optimize/rigid_limits.h):
// given the baseline's held train it finds the unlimited design over a limit
// 1 % below its held pressure, where the follower alone (the tappet on its own
// spring, as the stage held it before) is far under.
TEST(TrainStressLimit, ProbeSeesTheHeldTrainsPressure) {
  const OptimizeStudy free = steel_train_study({});
  const DesignSpace space(free.baseline, free.config.design, "optimize_train.json");
  const RigidStageResult a = run_rigid_stage(free.baseline, free.config, space, "optimize_train.json");
  ASSERT_TRUE(a.design.have);
  const double unlimited = held_peak_pressure(free, space.scene(a.design.x));
  const double limit = 0.99 * unlimited;
  const Model model = build_model(free.baseline, "optimize_train.json");
  ProbedLimits limits;
  limits.contact = line_contact(free.baseline.mechanism.contact);
  limits.max_contact_stress = limit;
  for (const double rpm : free.config.operating_rpm) limits.omegas.push_back(rpm * kTwoPi / 60.0);
  limits.held = &model;
  std::vector<double> angles;
  for (int i = 0; i < 720; ++i) angles.push_back(kTwoPi * i / 720.0);
  const RigidFollower f = *rigid_follower(model, 10.0);
  EXPECT_TRUE(
      RigidLimitProbe(space, model.follower, model.direction, f, limits, angles).broken(a.design.control_points));
  limits.held = nullptr;  // the follower alone
  EXPECT_FALSE(
      RigidLimitProbe(space, model.follower, model.direction, f, limits, angles).broken(a.design.control_points));
}

// With a Kelvin–Voigt contact of exponent 1 the held train's linearisation
// does not depend on the preload: the sized preload brings the smallest held
// contact or link force to P_min (10 N) at the speed it binds, and no lower
// at any speed up to the top one.
TEST(TrainStressLimit, RequiredPreloadIsTheHeldTrainsWithItsUnit) {
  const OptimizeStudy study = steel_train_study({});
  const SceneSpringSizing s = size_scene_spring(study.baseline, study.config, "optimize_train.json");
  ASSERT_TRUE(s.available) << s.reason;
  EXPECT_EQ(s.spring, "mechanism.train[0].spring");  // the tappet's own spring would unload the link
  EXPECT_EQ(s.unit, "N");
  EXPECT_TRUE(std::isnan(s.required_stiffness));
  SceneConfig sized = study.baseline;
  sized.mechanism.train[0].spring.preload = s.required_preload;
  const Model model = build_model(sized, "test.json");
  const HeldTrain held = held_train(model);
  const GridSignal law = grid_signal([&](double theta) { return model.law->eval(theta); }, 1024);
  const double top = 6000.0 * kTwoPi / 60.0;  // [rad/s]
  double least = kInf;
  for (int k = 0; k <= 200; ++k) {
    const std::vector<Eigen::VectorXd> v = held_train_values(held, law, top * k / 200.0);
    for (std::size_t q = 0; q < held.quantities.size(); ++q)
      if (held.quantities[q].held()) least = std::min(least, v[q].minCoeff());
  }
  // The scan the sizing takes includes these 201 speeds: the least is 10 N at
  // the binding speed (one of them, or a resonance between them, which only lowers it).
  EXPECT_GE(least, 10.0 - 1e-6 * s.required_preload);
  EXPECT_LE(least, 10.0 + 0.05 * s.required_preload);
}

}  // namespace
}  // namespace camdyn::optim
