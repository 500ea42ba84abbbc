// The optimize studies of studies/ run as shipped (label `slow`: about half a
// minute each on two cores). Acceptance of the design optimisation: the
// optimised jump study separates at no operating speed, holds every
// constraint, hammers less than the baseline, and `camdyn run optimized.json`
// reproduces its metrics.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "cli_run.h"

namespace {

namespace fs = std::filesystem;
using Json = nlohmann::json;

using camdyn::test::read_text;

fs::path scratch(const std::string& name) { return camdyn::test::scratch_dir("optimize_slowtest", name); }

int run_cli(const std::string& args, const fs::path& log) {
  return camdyn::test::run_camdyn(camdyn::test::split_args(args), log).code;
}

double relative(double a, double b) { return std::abs(a - b) / std::max({std::abs(a), std::abs(b), 1e-300}); }

/// Runs a study from studies/, checks that every constraint holds and that
/// `camdyn run optimized.json` gives the top speed's metrics to 1e-9.
Json run_study(const std::string& name) {
  const fs::path dir = scratch(name);
  const std::string config = std::string(CAMDYN_SOURCE_DIR) + "/studies/" + name + ".json";
  const int code = run_cli("run " + config + " --out " + (dir / "out").string() + " --jobs 2", dir);
  EXPECT_EQ(code, 0) << read_text(dir / "camdyn.err");
  const Json result = Json::parse(read_text(dir / "out" / "result.json"));
  for (const auto& [key, c] : result["optimized"]["constraints"].items()) EXPECT_TRUE(c["holds"].get<bool>()) << key;
  EXPECT_TRUE(result["optimized"]["feasible"].get<bool>());

  EXPECT_EQ(
      run_cli("run " + (dir / "out" / "optimized.json").string() + " --out " + (dir / "rerun").string() + " --quiet",
              dir),
      0)
      << read_text(dir / "camdyn.err");
  const Json summary = Json::parse(read_text(dir / "rerun" / "summary.json"));
  const Json& top = result["optimized"]["metrics"].back();
  EXPECT_EQ(summary["config"]["mechanism"]["cam"]["rpm"], top["rpm"]);
  for (const auto& [key, value] : summary["metrics"].items()) {
    if (value.is_null()) continue;  // an infinite jump speed
    EXPECT_LE(relative(value.get<double>(), top[key].get<double>()), 1e-9) << key;
  }
  return result;
}

TEST(OptimizeStudies, JumpStudyStopsTheJumpAndTheHammering) {
  const Json r = run_study("optimize_jump");
  const Json& base = r["baseline"]["metrics"];
  const Json& opt = r["optimized"]["metrics"];
  ASSERT_EQ(opt.size(), 3u);
  EXPECT_GT(base[2]["separation_fraction"].get<double>(), 0.0);  // the baseline jumps at 1300 rpm
  double base_peak = 0.0, opt_peak = 0.0;
  for (std::size_t i = 0; i < opt.size(); ++i) {
    EXPECT_EQ(opt[i]["separation_fraction"].get<double>(), 0.0) << opt[i]["rpm"];
    EXPECT_EQ(opt[i]["impact_count"].get<long>(), 0) << opt[i]["rpm"];
    base_peak = std::max(base_peak, base[i]["peak_contact_force"].get<double>());
    opt_peak = std::max(opt_peak, opt[i]["peak_contact_force"].get<double>());
  }
  EXPECT_LT(opt_peak, base_peak);  // worst case over the speeds, which the objective minimises
  EXPECT_LT(r["optimized"]["objective"]["value"].get<double>(), r["baseline"]["objective"]["value"].get<double>());
}

TEST(OptimizeStudies, ForceStudyLowersThePeakForceWithoutSeparation) {
  const Json r = run_study("optimize_force");
  double base_peak = 0.0, opt_peak = 0.0;
  for (const Json& m : r["baseline"]["metrics"]) base_peak = std::max(base_peak, m["peak_contact_force"].get<double>());
  for (const Json& m : r["optimized"]["metrics"]) {
    opt_peak = std::max(opt_peak, m["peak_contact_force"].get<double>());
    EXPECT_EQ(m["separation_fraction"].get<double>(), 0.0);
  }
  EXPECT_LT(opt_peak, 0.9 * base_peak);
}

// Issue 56's acceptance on the DOHC lash train: the baseline floats on its
// steady state at the 3700 rpm red line (its held-train jump speed is 3481
// rpm); the optimiser's dynamic stage reaches a green answer that floats at
// no operating speed, holds the seat-bounce and curvature limits, keeps at
// least three quarters of the baseline's lift (the study maximises the
// area: a search without that term gave 90 % of the lift up), and whose one
// jump-free figure is above the baseline's. The lash's take-up bounces are there at every speed and
// are no jump (docs/valvetrain.md).
TEST(OptimizeStudies, DohcLashTrainGoesGreen) {
  const fs::path dir = scratch("optimize_dohc_lash");
  const std::string config = std::string(CAMDYN_SOURCE_DIR) + "/studies/valvetrain/optimize_dohc_lash.json";
  ASSERT_EQ(run_cli("run " + config + " --out " + (dir / "out").string() + " --jobs 2 --quiet", dir), 0)
      << read_text(dir / "camdyn.err");
  const Json r = Json::parse(read_text(dir / "out" / "result.json"));
  EXPECT_EQ(r["verdict"], "good");
  EXPECT_NE(r["chosen"], "baseline");
  EXPECT_FALSE(r["baseline"]["feasible"].get<bool>());  // it floats at the red line
  EXPECT_TRUE(r["lift"]["given_up"].is_null());
  EXPECT_GE(r["lift"]["answer_highest"].get<double>(), 0.75 * r["lift"]["baseline_highest"].get<double>());
  EXPECT_GE(r["lift"]["answer_area"].get<double>(), 0.75 * r["lift"]["baseline_area"].get<double>());
  EXPECT_TRUE(r["optimized"]["feasible"].get<bool>());
  for (const auto& [key, c] : r["optimized"]["constraints"].items()) EXPECT_TRUE(c["holds"].get<bool>()) << key;
  const Json& jump_free = r["rigid_stage"]["jump_free_rpm"];
  EXPECT_GT(jump_free["answer"].get<double>(), jump_free["baseline"].get<double>());
}

}  // namespace
