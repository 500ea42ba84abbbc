// The jump map's warm start (jump_map.warm_start): a speed shot from the
// orbit its neighbours predict, without the transient, must classify every
// speed as the transient path does (motion kind and period), find the same
// orbit within the shooting tolerance, and record the same samples and
// impacts; and the shortcut must be taken (its speeds are marked
// "predicted"), else it saves nothing. On the quickstart cam across its jump
// speed (period 1, leaving the cam) and on the bouncing ball across its
// first period doubling (period 2: the phase the secant runs along).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>
#include <ostream>
#include <string>

#include "cli_run.h"
#include "io/config.h"

namespace camdyn {
namespace {

namespace fs = std::filesystem;

struct WarmCase {
  const char* name;
  const char* config;     ///< under the source tree
  const char* jump_map;   ///< the `jump_map` fields but warm_start
  const char* periodic;   ///< the `periodic` fields
  double position_scale;  ///< the Poincaré map's scale of the section coordinate (its lift range) [m]
  int least_period;       ///< of some speed of the grid, so the grid crosses what it should
};

/// The shooting tolerance both runs use (periodic.tolerance's default) [-].
constexpr double kWarmShootingTolerance = 1e-7;

Json run_warm_or_cold_map(const WarmCase& c, bool warm, const fs::path& dir) {
  const std::string out = (dir / (warm ? "warm" : "cold")).string();
  const std::string fields = std::string(c.jump_map) + R"(, "warm_start": )" + (warm ? "true}" : "false}");
  const test::Outcome r = test::run_camdyn(
      {"run", std::string(CAMDYN_SOURCE_DIR) + "/" + c.config, "--out", out, "--quiet", "--jobs", "1", "--set",
       "study=jump_map", "--set", "jump_map=" + fields, "--set", std::string("periodic=") + c.periodic},
      dir, warm ? "warm" : "cold");
  EXPECT_EQ(r.code, 0) << r.err;
  return Json::parse(test::read_text(fs::path(out) / "jump_map.json"));
}

void PrintTo(const WarmCase& c, std::ostream* os) { *os << c.name; }

class JumpMapWarmStart : public ::testing::TestWithParam<WarmCase> {};

TEST_P(JumpMapWarmStart, ClassifiesEverySpeedAsTheTransientPathDoes) {
  const WarmCase& c = GetParam();
  const fs::path dir = test::scratch_dir("jump_map_warm_start_test", c.name);
  const Json warm = run_warm_or_cold_map(c, true, dir), cold = run_warm_or_cold_map(c, false, dir);
  ASSERT_EQ(warm["speeds"].size(), cold["speeds"].size());
  int predicted = 0, most_period = 0;
  for (std::size_t i = 0; i < warm["speeds"].size(); ++i) {
    const Json& w = warm["speeds"][i];
    const Json& k = cold["speeds"][i];
    const double rpm = w["rpm"].get<double>();
    ASSERT_TRUE(w["ok"].get<bool>() && k["ok"].get<bool>()) << rpm << ": " << w["error"] << k["error"];
    EXPECT_EQ(k["start"], "transient") << rpm << ": warm_start false takes no shortcut";
    EXPECT_EQ(w["motion"], k["motion"]) << rpm;
    EXPECT_EQ(w["period"], k["period"]) << rpm;
    most_period = std::max(most_period, w["period"].get<int>());
    if (w["start"] != "predicted") continue;
    ++predicted;
    // Both fixed points lie within the tolerance of the orbit's: a
    // contraction of spectral radius ρ leaves |x − x*| ≤ tol·scale / (1 − ρ).
    const double rho = std::max(w["spectral_radius"].get<double>(), k["spectral_radius"].get<double>());
    ASSERT_LT(rho, 1.0) << rpm;
    const double bound = 2.0 * kWarmShootingTolerance * c.position_scale / (1.0 - rho);  // [m]
    const auto& ws = w["section_position"];
    const auto& ks = k["section_position"];
    ASSERT_EQ(ws.size(), ks.size()) << rpm;
    const int period = w["period"].get<int>();
    // The cold run's samples start one revolution after its fixed point, as the warm one's do;
    // a period-k orbit's samples may start at another of its k phases.
    double best = INFINITY;
    for (int shift = 0; shift < period; ++shift) {
      double worst = 0.0;
      for (std::size_t j = 0; j + static_cast<std::size_t>(shift) < ws.size(); ++j)
        worst = std::max(worst, std::abs(ws[j + static_cast<std::size_t>(shift)].get<double>() - ks[j].get<double>()));
      best = std::min(best, worst);
    }
    EXPECT_LE(best, bound) << rpm << " rpm: the section samples of the two paths";
    EXPECT_EQ(w["impact_speed"].size(), k["impact_speed"].size()) << rpm;
    // Just past the jump speed the gap grows like the square root of the
    // distance from grazing, so a tolerance-sized shift of the orbit moves it
    // by much more than the orbit itself: within 1 %.
    EXPECT_NEAR(w["max_gap"].get<double>(), k["max_gap"].get<double>(), bound + 1e-2 * k["max_gap"].get<double>())
        << rpm;
  }
  EXPECT_GE(predicted, static_cast<int>(warm["speeds"].size()) / 2) << "the shortcut was hardly taken";
  EXPECT_EQ(warm["predicted_speeds"], predicted);
  EXPECT_GE(most_period, c.least_period);
  EXPECT_EQ(warm["transitions"], cold["transitions"]);
}

INSTANTIATE_TEST_SUITE_P(
    Scenes, JumpMapWarmStart,
    ::testing::Values(
        WarmCase{
            "quickstart_across_the_jump_speed", "studies/quickstart.json",
            R"({"low_rpm": 1000, "high_rpm": 1250, "speeds": 5, "ranges": 1, "refine": 0, "transient_revolutions": 10,
                     "samples": 10)",
            R"({"max_period": 2, "lyapunov_revolutions": 20})", 0.02, 1},
        WarmCase{
            "bouncing_ball_across_its_period_doubling", "studies/periodic/bouncing_ball_jump_map.json",
            R"({"low_rpm": 585, "high_rpm": 625, "speeds": 6, "ranges": 1, "refine": 0, "transient_revolutions": 20,
                     "samples": 8)",
            R"({"max_period": 2, "lyapunov_revolutions": 20})", 0.006, 2}),
    [](const ::testing::TestParamInfo<WarmCase>& p) { return std::string(p.param.name); });

}  // namespace
}  // namespace camdyn
