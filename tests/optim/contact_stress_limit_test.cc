// The contact-stress limit of an optimize study (constraints.max_contact_stress)
// on studies/optimize_jump.json with steel-on-steel line contact: the rigid
// stage's check-and-tighten loop must bring the design's rigid-model Hertz
// pressure under the limit at every operating speed, checked by the dynamics
// code's own sampling over the whole revolution (what `validate` checks);
// and the limit needs line-contact materials.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <numbers>
#include <string>
#include <vector>

#include "cli_run.h"
#include "common/errors.h"
#include "dynamics/contact_stress.h"
#include "io/config.h"
#include "io/json_archive.h"
#include "optim/optimize/design.h"
#include "optim/optimize/optimize.h"
#include "optim/optimize/rigid_design.h"
#include "study_paths.h"

namespace camdyn::optim {
namespace {

const std::string kSteel =
    "mechanism.contact.stiffness={\"from_materials\": {\"E1\": 2.1e11, \"nu1\": 0.3, \"E2\": 2.1e11, \"nu2\": 0.3, "
    "\"width\": 0.012}}";

OptimizeStudy study(std::vector<std::string> overrides) {
  overrides.insert(overrides.begin(), {kSteel, "mechanism.contact.exponent=1", "objective={\"separation\": 1}"});
  return read_optimize_study(load_config_json(kOptimizeJump, overrides),
                             ConfigSource{kOptimizeJump, CAMDYN_SOURCE_DIR "/studies"});
}

/// The highest rigid-model pressure of design x over the study's operating speeds [Pa].
double peak_pressure(const OptimizeStudy& s, const DesignSpace& space, const std::vector<double>& x) {
  const SceneConfig scene = space.scene(x);
  const Model model = build_model(scene, "test.json");
  const LineContact contact = *line_contact(scene.mechanism.contact);
  double peak = 0.0;
  for (const double rpm : s.config.operating_rpm)
    peak = std::max(peak, peak_rigid_contact_pressure(model, contact, rpm * std::numbers::pi / 30.0).pressure);
  return peak;
}

TEST(ContactStressLimit, HoldsInTheRigidDesignAfterTightening) {
  const OptimizeStudy free = study({});
  const DesignSpace space(free.baseline, free.config.design, "optimize_jump.json");
  const RigidStageResult a = run_rigid_stage(free.baseline, free.config, space, "optimize_jump.json");
  ASSERT_TRUE(a.design.have);
  const double unlimited = peak_pressure(free, space, a.design.x);
  const double limit = 0.97 * unlimited;
  const OptimizeStudy limited = study({"constraints.max_contact_stress=" + std::to_string(limit)});
  const RigidStageResult b = run_rigid_stage(limited.baseline, limited.config, space, "optimize_jump.json");
  ASSERT_TRUE(b.design.have);
  EXPECT_LE(peak_pressure(limited, space, b.design.x), limit);
  EXPECT_GT(b.design.jump_free_rpm, 1300.0);  // still jump-free at every operating speed
  std::printf("peak Hertz pressure %.5g -> %.5g Pa (limit %.5g), jump-free %.5g -> %.5g rpm, %d LPs\n", unlimited,
              peak_pressure(limited, space, b.design.x), limit, a.design.jump_free_rpm, b.design.jump_free_rpm,
              b.lp_solves);
}

// End to end: the optimised design meets the limit, and optimized.json
// carries it as `mechanism.cam.limits.max_contact_stress`, which `validate`
// re-checks (and refuses when it is set below the design's pressure).
TEST(ContactStressLimit, OptimizedConfigCarriesTheLimitAndValidateChecksIt) {
  const OptimizeStudy free = study({});
  const DesignSpace space(free.baseline, free.config.design, "optimize_jump.json");
  const RigidStageResult a = run_rigid_stage(free.baseline, free.config, space, "optimize_jump.json");
  ASSERT_TRUE(a.design.have);
  const std::string limit_text = std::to_string(0.97 * peak_pressure(free, space, a.design.x));
  const double limit = std::stod(limit_text);  // as the config reads it
  const test::fs::path dir = test::scratch_dir("contact_stress", "optimize");
  const std::vector<std::string> sets = {"--set", kSteel,
                                         "--set", "mechanism.contact.exponent=1",
                                         "--set", "objective={\"separation\":1}",
                                         "--set", "constraints.max_contact_stress=" + limit_text,
                                         "--set", "optimizer.max_evaluations=12"};
  std::vector<std::string> args = {"run", kOptimizeJump, "--out", (dir / "out").string(), "--jobs", "2", "--quiet"};
  args.insert(args.end(), sets.begin(), sets.end());
  const test::Outcome run = test::run_camdyn(args, dir);
  ASSERT_EQ(run.code, 0) << run.err;
  const Json result = Json::parse(test::read_text(dir / "out" / "result.json"));
  const Json& c = result["optimized"]["constraints"]["max_contact_stress"];
  ASSERT_TRUE(c.is_object()) << result["optimized"]["constraints"].dump();
  EXPECT_EQ(c["unit"], "Pa");
  EXPECT_TRUE(c["holds"].get<bool>()) << c.dump();
  EXPECT_LE(c["value"].get<double>(), limit);
  const std::string optimized = (dir / "out" / "optimized.json").string();
  const test::Outcome valid = test::run_camdyn({"validate", optimized}, dir);
  ASSERT_EQ(valid.code, 0) << valid.err;
  EXPECT_EQ(Json::parse(valid.out)["mechanism"]["cam"]["limits"]["max_contact_stress"].get<double>(), limit);
  const test::Outcome broken =
      test::run_camdyn({"validate", optimized, "--set", "mechanism.cam.limits.max_contact_stress=1e6"}, dir);
  EXPECT_EQ(broken.code, 2);
  EXPECT_NE(broken.err.find("mechanism.cam.limits.max_contact_stress"), std::string::npos) << broken.err;
}

TEST(ContactStressLimit, NeedsLineContactMaterials) {
  const std::string file = kOptimizeJump;
  const OptimizeStudy s = read_optimize_study(load_config_json(file, {"constraints.max_contact_stress=1e9"}),
                                              ConfigSource{file, CAMDYN_SOURCE_DIR "/studies"});
  try {
    check_optimize(s.baseline, s.config, file);
    FAIL() << "no InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.path(), "constraints.max_contact_stress");
    EXPECT_NE(e.reason().find("width"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace camdyn::optim
