// Coexisting attractors on the jump map (docs/periodic.md "Coexisting
// attractors"): where the class changes between neighbouring speeds, each
// side's stable orbit is shot one step across, and a speed where two
// different stable orbits converge is `coexisting`, with every attractor.
//
// * Holmes' bouncing ball (studies/periodic/bouncing_ball.json) with
//   restitution 0.7 from 590 to 610 rpm: past its period doubling the
//   doubled orbit (period 2) coexists with a period-3 orbit, one impact a
//   revolution; at 610 rpm the period 2 has doubled again, and its period 4,
//   which the motion carried on from 600 rpm goes to, coexists with the
//   period 3, which the shooting from that motion finds but the motion does
//   not reach
//   (coexisting periodic orbits of the bouncing ball: Holmes 1982, J. Sound
//   Vib. 84; Luck & Mehta 1993, Phys. Rev. E 48). Checked independently of
//   the shooting: each attractor's fixed point is integrated on in one run
//   and its impacts (count and cam angles) repeat with its own period and
//   not a shorter one, the section state returns to the fixed point every
//   period, and a start perturbed off it comes back (stable); and the motion
//   at 610 rpm from 600 rpm's orbit, integrated in one run, ends with the
//   impacts of the period 4.
// * The quickstart near 1214.6 rpm (bench/jump_map_bench.cc): the transient
//   reports a period-2 orbit whose points lie 1e-6 (scaled) from the
//   period-1 orbit, and integrated on, the two have the same impacts every
//   revolution: one motion seen through the map's integration noise, which
//   must not be called coexisting.
// * The bouncing ball of restitution 0.5 across its first period doubling
//   (supercritical: the period-1 orbit loses stability as the period-2 one
//   appears): the check runs at the change and finds no second attractor.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "cli_run.h"
#include "dynamics/model.h"
#include "dynamics/poincare_map.h"
#include "io/config.h"
#include "study/jump_map.h"

namespace camdyn {
namespace {

namespace fs = std::filesystem;

/// The grid of bench/jump_map_bench.cc's quickstart map, 900 + 350 i / 99 rpm: i = 88 and 89.
constexpr double kBelowRpm = 900.0 + 350.0 * 88.0 / 99.0, kQuickstartRpm = 900.0 + 350.0 * 89.0 / 99.0;
/// Revolutions each attractor is followed on, independently of the shooting.
constexpr int kRevolutions = 48;
/// The shooting tolerance (periodic.tolerance's default) [-, of each coordinate's scale].
constexpr double kShootingTolerance = 1e-7;
const char* const kBouncingBall = "studies/periodic/bouncing_ball_jump_map.json";
const char* const kRestitution = "mechanism.contact.restitution=0.7";
/// Two impacts are the same impact of the pattern within this cam angle [deg]: the
/// integration tolerance (rtol 1e-8) moves them by far less, another pattern by more.
constexpr double kSameImpactDeg = 0.05;

Json run_map(const std::string& config, const std::string& jump_map, const std::string& periodic, const fs::path& dir,
             const std::vector<std::string>& more = {}) {
  const std::string out = (dir / "out").string();
  std::vector<std::string> args{"run",
                                std::string(CAMDYN_SOURCE_DIR) + "/" + config,
                                "--out",
                                out,
                                "--quiet",
                                "--jobs",
                                "1",
                                "--set",
                                "study=jump_map",
                                "--set",
                                "jump_map=" + jump_map,
                                "--set",
                                "periodic=" + periodic};
  for (const std::string& o : more) {
    args.push_back("--set");
    args.push_back(o);
  }
  const test::Outcome r = test::run_camdyn(args, dir, "map");
  EXPECT_EQ(r.code, 0) << r.err;
  return Json::parse(test::read_text(fs::path(out) / "jump_map.json"));
}

/// What some revolutions from one section point give: the section state each
/// revolution and the cam angles of the impacts of each revolution.
struct Followed {
  std::vector<std::vector<double>> section;      ///< after revolution 1, 2, …
  std::vector<std::vector<double>> impacts_deg;  ///< by revolution
};

/// Follows `revolutions` from `attractor`'s fixed point at `rpm`, its section
/// velocity moved by `nudge` scales; `scales` gets the map's.
Followed follow(const std::string& config, const std::vector<std::string>& more, double rpm, const Json& attractor,
                std::vector<double>& scales, double nudge = 0.0, int revolutions = kRevolutions) {
  const std::string path = std::string(CAMDYN_SOURCE_DIR) + "/" + config;
  StudyContext ctx;
  ctx.config_file = path;
  ctx.source = config_source(path);
  std::vector<std::string> overrides{"study=jump_map", R"(jump_map={"low_rpm": 100, "high_rpm": 2000})"};
  overrides.insert(overrides.end(), more.begin(), more.end());
  const JumpMapStudy study = read_jump_map_study(load_config_json(path, overrides), ctx);
  SceneConfig scene = study.scene;
  scene.mechanism.cam.rpm = rpm;
  const Model model = build_model(study.geometry, scene, path);
  const PoincareMap map(scene, model, path);
  scales = map.scales();
  SectionPoint p;
  p.x = attractor.at("fixed_point").get<std::vector<double>>();
  p.approach_speed = attractor.at("approach_speed").get<double>();
  p.x.at(1) += nudge * scales.at(1);
  SimulationOptions options;
  options.record_series = false;
  options.start = std::make_shared<const StartState>(map.start(p));
  for (int j = 1; j <= revolutions; ++j) options.sample_times.push_back(j * map.period());
  Workspace ws = make_workspace(model);
  const SimulationResult r = simulate(map.scene_for(revolutions), model, ws, options);
  throw_if_failed(r);
  Followed f;
  f.impacts_deg.resize(static_cast<std::size_t>(revolutions));
  for (const ContactEvent& e : r.events) {
    if (!e.onset || !e.impact) continue;
    const int revolution = std::clamp(static_cast<int>(std::floor(e.time / map.period())), 0, revolutions - 1);
    f.impacts_deg[static_cast<std::size_t>(revolution)].push_back(std::fmod(e.cam_angle_deg, 360.0));
  }
  // The quickstart's section coordinates are the follower's position and velocity (dynamics/poincare_map.h).
  EXPECT_EQ(p.x.size(), 2u);
  for (std::size_t j = 0; j < r.samples.follower_position.size(); ++j)
    f.section.push_back({r.samples.follower_position[j], r.samples.follower_velocity[j]});
  EXPECT_EQ(f.section.size(), static_cast<std::size_t>(revolutions));
  return f;
}

/// Revolutions a and b have the same impacts (count, and cam angles within kSameImpactDeg).
bool same_impacts(const Followed& f, std::size_t a, std::size_t b) {
  const std::vector<double>&ia = f.impacts_deg[a], &ib = f.impacts_deg[b];
  if (ia.size() != ib.size()) return false;
  for (std::size_t i = 0; i < ia.size(); ++i)
    if (std::abs(ia[i] - ib[i]) > kSameImpactDeg) return false;
  return true;
}

/// The least d ≥ 1 with which the impacts repeat over the followed revolutions
/// from revolution `from` (by default the first period skipped: its start is
/// the shooting's point); 0: none up to 4.
int impact_period(const Followed& f, std::size_t from = 4) {
  for (std::size_t d = 1; d <= 4; ++d) {
    bool repeats = true;
    for (std::size_t r = from; r + d < f.impacts_deg.size() && repeats; ++r) repeats = same_impacts(f, r, r + d);
    if (repeats) return static_cast<int>(d);
  }
  return 0;
}

/// Max over coordinates of |a_i − b_i| / scale_i [-].
double scaled_distance(const std::vector<double>& a, const std::vector<double>& b, const std::vector<double>& scales) {
  double d = 0.0;
  for (std::size_t i = 0; i < std::min(a.size(), b.size()); ++i) d = std::max(d, std::abs(a[i] - b[i]) / scales[i]);
  return d;
}

TEST(JumpMapCoexistence, BouncingBallsDoubledOrbitsCoexistWithAPeriodThreeOrbit) {
  const fs::path dir = test::scratch_dir("jump_map_coexistence_test", "bouncing_ball_coexisting");
  const Json map = run_map(kBouncingBall,
                           R"({"low_rpm": 590, "high_rpm": 610, "speeds": 3, "ranges": 1, "refine": 0,
                               "transient_revolutions": 20, "samples": 8})",
                           R"({"max_period": 4, "lyapunov_revolutions": 20})", dir, {kRestitution});
  ASSERT_EQ(map["speeds"].size(), 3u);
  EXPECT_FALSE(map["speeds"][0]["coexisting"].get<bool>());
  EXPECT_EQ(map["coexisting_speeds"], 2);
  // 600 rpm: the period 2 continued from 590 rpm, and the period 3 of 610 rpm shot there;
  // 610 rpm: the period 4 the motion from 600 rpm goes to, and the period 3
  // the shooting from that motion found, which the motion does not reach.
  const int expected[2][2] = {{2, 3}, {4, 3}};
  const char* reached[2] = {"from_above", "shooting"};
  for (std::size_t s = 1; s <= 2; ++s) {
    const Json& p = map["speeds"][s];
    const double rpm = p["rpm"].get<double>();
    ASSERT_TRUE(p["coexisting"].get<bool>()) << rpm;
    const Json& attractors = p["attractors"];
    ASSERT_EQ(attractors.size(), 2u) << rpm;
    EXPECT_EQ(attractors[0]["reached"], "continuation") << rpm;
    EXPECT_EQ(attractors[0]["period"], p["period"]) << rpm << ": the point's own fields are the continuation's";
    EXPECT_EQ(attractors[1]["reached"], reached[s - 1]) << rpm;
    for (std::size_t a = 0; a < 2; ++a) {
      const Json& attractor = attractors[a];
      const int period = attractor["period"].get<int>();
      EXPECT_EQ(period, expected[s - 1][a]) << rpm;
      const double rho = attractor["spectral_radius"].get<double>();
      ASSERT_LT(rho, 1.0) << rpm;
      std::vector<double> scales;
      const Followed f = follow(kBouncingBall, {kRestitution}, rpm, attractor, scales);
      // It persists: its impacts repeat with its own period, not a shorter one …
      EXPECT_EQ(impact_period(f), period) << rpm << " rpm, the attractor of period " << period;
      // … and the section state returns to the fixed point every period: a
      // contraction of spectral radius ρ keeps a point tol from the orbit
      // within tol / (1 − ρ); as much again for the shooting's fixed point,
      // and twice that for the long run's integration error (rtol 1e-10 on
      // each revolution, under the same contraction).
      const std::vector<double> x0 = attractor["fixed_point"].get<std::vector<double>>();
      const double bound = 4.0 * kShootingTolerance / (1.0 - rho);
      for (std::size_t r = static_cast<std::size_t>(period) - 1; r < f.section.size();
           r += static_cast<std::size_t>(period))
        EXPECT_LE(scaled_distance(f.section[r], x0, scales), bound)
            << rpm << " rpm, period " << period << ", rev " << r + 1;
      // Stable: a start 1e-4 (scaled) off it comes back, by ρ per period or faster
      // (the multipliers' modulus; a margin of 2 for their non-normal transient).
      const double nudge = 1e-4;
      const Followed g = follow(kBouncingBall, {kRestitution}, rpm, attractor, scales, nudge);
      const std::size_t last =
          (g.section.size() / static_cast<std::size_t>(period)) * static_cast<std::size_t>(period) - 1;
      const double periods = static_cast<double>((last + 1) / static_cast<std::size_t>(period));
      EXPECT_LE(scaled_distance(g.section[last], x0, scales), 2.0 * nudge * std::pow(rho, periods) + bound)
          << rpm << " rpm, period " << period;
    }
  }
  // No change of class is stated to or from them.
  for (const Json& t : map["transitions"]) EXPECT_EQ(t["kind"], "coexistence") << t.dump();
  // The motion at 610 rpm is the one carried on from 600 rpm's period-2
  // orbit (20 transient revolutions, then the search): integrated on in one
  // run, it ends with the impacts of the period 4, not those of the period 3.
  std::vector<double> scales;
  const int revolutions = 400;
  const Followed carried =
      follow(kBouncingBall, {kRestitution}, 610.0, map["speeds"][1]["attractors"][0], scales, 0.0, revolutions);
  EXPECT_EQ(impact_period(carried, revolutions - 40), 4);
}

/// The cam angles [deg] of the impacts impacts.csv records at `rpm` (over the speed's samples).
std::vector<double> recorded_impact_angles(const fs::path& out, double rpm) {
  std::istringstream lines(test::read_text(out / "impacts.csv"));
  std::vector<double> angles;
  std::string line;
  std::getline(lines, line);  // the header: rpm,motion,period,cam_angle_deg,approach_speed
  while (std::getline(lines, line)) {
    std::vector<std::string> cells;
    std::istringstream row(line);
    for (std::string cell; std::getline(row, cell, ',');) cells.push_back(cell);
    if (cells.size() == 5 && std::abs(std::stod(cells[0]) - rpm) < 1e-9 * rpm) angles.push_back(std::stod(cells[3]));
  }
  return angles;
}

// The transient path near 1214.6 rpm used to report a period-2 (or 3) orbit
// whose points lie within the chattering map's noise of the period-1 orbit,
// and a period doubling with it. The orbit is reported at period 1 when every
// phase repeats after one revolution within 1e3 shooting tolerances
// (study/periodic_orbit.cc, repeating_every). Independent evidence: the
// motion the speed recorded (its samples, impacts.csv) has the same impacts
// at the same cam angles in every revolution.
TEST(JumpMapCoexistence, QuickstartsTransientNear1214rpmIsPeriodOneAsItsImpactsRepeatEveryRevolution) {
  const fs::path dir = test::scratch_dir("jump_map_coexistence_test", "quickstart");
  constexpr int kSamples = 6;
  char grid[256];
  std::snprintf(grid, sizeof grid,
                R"({"low_rpm": %.17g, "high_rpm": %.17g, "speeds": 2, "ranges": 1, "refine": 0, "warm_start": false,
                    "transient_revolutions": 10, "samples": %d})",
                kBelowRpm, kQuickstartRpm, kSamples);
  const Json map = run_map("studies/quickstart.json", grid, R"({"max_period": 3, "lyapunov_revolutions": 20})", dir);
  ASSERT_EQ(map["speeds"].size(), 2u);
  for (const Json& p : map["speeds"]) {
    const double rpm = p["rpm"].get<double>();
    EXPECT_EQ(p["motion"], "periodic") << rpm;
    EXPECT_EQ(p["period"], 1) << rpm;
    EXPECT_FALSE(p["coexisting"].get<bool>()) << p["attractors"].dump();
    // Every impact angle recurs once per recorded revolution.
    std::vector<double> angles = recorded_impact_angles(dir / "out", rpm);
    ASSERT_FALSE(angles.empty()) << rpm;
    ASSERT_EQ(angles.size() % kSamples, 0u) << rpm;
    std::sort(angles.begin(), angles.end());
    for (std::size_t i = 0; i < angles.size(); i += kSamples)
      EXPECT_LT(angles[i + kSamples - 1] - angles[i], kSameImpactDeg) << rpm << " rpm, impact near " << angles[i];
  }
  EXPECT_TRUE(map["transitions"].empty()) << map["transitions"].dump();
  EXPECT_EQ(map["coexisting_speeds"], 0);
}

TEST(JumpMapCoexistence, BouncingBallsPeriodDoublingIsNotCoexistence) {
  const fs::path dir = test::scratch_dir("jump_map_coexistence_test", "bouncing_ball");
  const Json map = run_map("studies/periodic/bouncing_ball_jump_map.json",
                           R"({"low_rpm": 585, "high_rpm": 625, "speeds": 6, "ranges": 1, "refine": 0,
                               "transient_revolutions": 20, "samples": 8})",
                           R"({"max_period": 2, "lyapunov_revolutions": 20})", dir);
  int most_period = 0;
  for (const Json& p : map["speeds"]) {
    EXPECT_FALSE(p["coexisting"].get<bool>()) << p["rpm"];
    EXPECT_TRUE(p["attractors"].empty()) << p["rpm"];
    most_period = std::max(most_period, p["period"].get<int>());
  }
  EXPECT_EQ(most_period, 2) << "the grid must cross the doubling, else nothing was checked";
  EXPECT_EQ(map["coexisting_speeds"], 0);
  ASSERT_EQ(map["transitions"].size(), 1u);
  EXPECT_EQ(map["transitions"][0]["kind"], "period_doubling");
}

TEST(JumpMapCoexistence, APointsAttractorsSurviveItsJournalRecord) {
  JumpMapPoint p;
  p.rpm = 1214.6;
  p.ok = true;
  p.motion = MotionKind::periodic;
  p.period = 2;
  p.coexisting = true;
  p.attractors = {{JumpMapReach::continuation, MotionKind::periodic, 2, 0.5, {1.0, 2.0}, 0.25, {0.5, -0.1}, {0.0, 0.0}},
                  {JumpMapReach::from_below, MotionKind::periodic, 1, 0.01, {1.5, 2.5}, 0.0, {0.01, 0.0}, {0.0, 0.0}}};
  const JumpMapPoint q = jump_map_point_from_json(jump_map_point_json(p));
  ASSERT_TRUE(q.coexisting);
  ASSERT_EQ(q.attractors.size(), 2u);
  EXPECT_EQ(q.attractors[1].reached, JumpMapReach::from_below);
  EXPECT_EQ(q.attractors[1].fixed_point, std::vector<double>({1.5, 2.5}));
  EXPECT_EQ(q.attractors[0].approach_speed, 0.25);
  EXPECT_EQ(q.attractors[0].multipliers_re, std::vector<double>({0.5, -0.1}));
  // A coexisting speed with one attractor is no record camdyn writes.
  Json one = jump_map_point_json(p);
  one["attractors"].erase(1);
  EXPECT_THROW(jump_map_point_from_json(one), Json::exception);
}

}  // namespace
}  // namespace camdyn
