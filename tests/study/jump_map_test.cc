// The jump_map study: on the quickstart mechanism the follower first leaves
// the cam at the first grid speed above the rigid-model jump speed (with its
// damper), and below it every speed is a period-1 motion without impacts; a
// rerun into the same folder resumes from the journal; the transitions found
// along a grid.
#include "study/jump_map.h"

#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>

#include "cli_run.h"
#include "io/config.h"
#include "study_paths.h"
#include "tests/dynamics/scenes.h"

namespace camdyn {
namespace {

namespace fs = std::filesystem;

std::vector<std::string> jump_map_args(const fs::path& out) {
  return {"run",
          kQuickstart,
          "--out",
          out.string(),
          "--quiet",
          "--jobs",
          "2",
          "--set",
          "study=jump_map",
          "--set",
          R"(jump_map={"low_rpm": 900, "high_rpm": 1400, "speeds": 6, "ranges": 2, "transient_revolutions": 10,
             "samples": 10})",
          "--set",
          R"(periodic={"max_period": 2, "lyapunov_revolutions": 20})"};
}

TEST(JumpMap, QuickstartLeavesTheCamAtTheFirstSpeedAboveTheRigidJumpSpeed) {
  const fs::path dir = test::scratch_dir("jump_map_test", "quickstart");
  const test::Outcome r = test::run_camdyn(jump_map_args(dir / "out"), dir);
  ASSERT_EQ(r.code, 0) << r.err;
  const Json j = Json::parse(test::read_text(dir / "out" / "jump_map.json"));
  const double jump = j["damped_rigid_jump_speed_rpm"].get<double>();
  bool seen_separation = false;
  for (const Json& p : j["speeds"]) {
    const double rpm = p["rpm"].get<double>();
    ASSERT_TRUE(p["ok"].get<bool>()) << rpm << ": " << p["error"];
    const bool separates = !p["impact_speed"].empty() || p["separation_fraction"].get<double>() > 0;
    if (rpm < jump) {
      EXPECT_FALSE(separates) << rpm << " rpm is below the jump speed " << jump;
      EXPECT_EQ(p["motion"], "periodic") << rpm;
      EXPECT_EQ(p["period"], 1) << rpm;
    } else if (!seen_separation) {
      EXPECT_TRUE(separates) << rpm << " rpm is the first grid speed above the jump speed " << jump;
      seen_separation = true;
    }
  }
  EXPECT_TRUE(seen_separation);
  EXPECT_EQ(j["transitions"][0]["kind"], "separation");
  for (const char* file : {"jump_map.csv", "impacts.csv", "report.html", "journal.jsonl"})
    EXPECT_TRUE(fs::exists(dir / "out" / file)) << file;

  // Run again into the same folder: every range comes from the journal, and the outputs are the same.
  const test::Outcome again = test::run_camdyn(jump_map_args(dir / "out"), dir, "again");
  ASSERT_EQ(again.code, 0) << again.err;
  EXPECT_NE(again.err.find("resuming: 2 of 2 runs already done"), std::string::npos) << again.err;
  const Json k = Json::parse(test::read_text(dir / "out" / "jump_map.json"));
  EXPECT_EQ(k["speeds"], j["speeds"]);
}

// The bouncing ball's chaotic bands graze the cam now and then (the gap
// touches zero without closing): those onsets are not impacts, so no impact
// of the diagram has a non-positive approach speed (issue: they were drawn
// and counted as impacts).
TEST(JumpMap, ChaoticBandsHoldOnlyImpactsThatApproach) {
  const fs::path dir = test::scratch_dir("jump_map_test", "grazing");
  const std::string ball = std::string(CAMDYN_SOURCE_DIR) + "/studies/periodic/bouncing_ball_jump_map.json";
  const test::Outcome r = test::run_camdyn(
      {"run", ball, "--out", (dir / "out").string(), "--quiet", "--jobs", "2", "--set",
       R"(jump_map={"low_rpm": 660, "high_rpm": 690, "speeds": 4, "ranges": 1, "transient_revolutions": 20,
          "samples": 40})"},
      dir);
  ASSERT_EQ(r.code, 0) << r.err;
  const Json j = Json::parse(test::read_text(dir / "out" / "jump_map.json"));
  std::size_t impacts = 0;
  for (const Json& p : j["speeds"]) {
    for (const Json& v : p["impact_speed"]) EXPECT_GT(v.get<double>(), 0.0) << p["rpm"];
    impacts += p["impact_speed"].size();
  }
  EXPECT_GT(impacts, 100u);
}

// Each speed's Jacobian columns and Lyapunov pair run on the --jobs threads
// (a range left running alone uses every core), so the map must not depend on
// --jobs: the ball from period 2 into its chaotic band (Lyapunov runs, failed
// shooting, a warm-started speed), one range, with 1 and with 2 threads, to the bit.
TEST(JumpMap, SpeedsAreTheSameWhateverTheThreads) {
  const fs::path dir = test::scratch_dir("jump_map_test", "threads");
  const std::string ball = std::string(CAMDYN_SOURCE_DIR) + "/studies/periodic/bouncing_ball_jump_map.json";
  std::string speeds[2];
  for (int jobs = 1; jobs <= 2; ++jobs) {
    const fs::path out = dir / ("jobs" + std::to_string(jobs));
    const test::Outcome r = test::run_camdyn(
        {"run", ball, "--out", out.string(), "--quiet", "--jobs", std::to_string(jobs), "--set",
         R"(jump_map={"low_rpm": 640, "high_rpm": 690, "speeds": 4, "ranges": 1, "transient_revolutions": 10,
            "samples": 10})",
         "--set", R"(periodic={"max_period": 2, "lyapunov_revolutions": 20})"},
        dir);
    ASSERT_EQ(r.code, 0) << r.err;
    const Json j = Json::parse(test::read_text(out / "jump_map.json"));
    speeds[jobs - 1] = j["speeds"].dump();
    if (jobs == 1) {
      bool chaotic = false;
      for (const Json& p : j["speeds"]) chaotic = chaotic || p["motion"] == "chaotic";
      EXPECT_TRUE(chaotic) << "the case must reach the chaotic band: " << speeds[0];
    }
  }
  EXPECT_EQ(speeds[0], speeds[1]);
}

JumpMapPoint point(double rpm, MotionKind motion, int period, int impacts) {
  JumpMapPoint p;
  p.rpm = rpm;
  p.ok = true;
  p.motion = motion;
  p.period = period;
  p.impact_speed.assign(static_cast<std::size_t>(impacts), 0.1);
  p.floats = impacts > 0;  // no seat: every impact ends a float
  return p;
}

TEST(JumpMap, TransitionsAlongTheGrid) {
  const std::vector<JumpMapPoint> points = {
      point(100, MotionKind::periodic, 1, 0), point(200, MotionKind::periodic, 1, 1),
      point(300, MotionKind::periodic, 2, 2), point(400, MotionKind::periodic, 3, 3),
      point(500, MotionKind::chaotic, 0, 5),  point(600, MotionKind::periodic, 1, 1)};
  const std::vector<JumpMapTransition> t = jump_map_transitions(points);
  ASSERT_EQ(t.size(), 5u);
  EXPECT_EQ(t[0].kind, "separation");
  EXPECT_EQ(t[0].from_rpm, 100);
  EXPECT_EQ(t[1].kind, "period_doubling");
  EXPECT_EQ(t[2].kind, "period_adding");
  EXPECT_EQ(t[3].kind, "chaos_onset");
  EXPECT_EQ(t[4].kind, "chaos_end");
}

// The map's limit is speed_limit's (docs/valvetrain.md): the lowest speed
// that floats and where (the cam contact or a link), never a seat bounce or
// a failed speed; the lowest seat bounce has its own speed.
TEST(JumpMap, TheLimitIsTheFirstFloatAndSeatBouncesHaveTheirOwnSpeed) {
  auto at = [](double rpm, bool ok, bool floats, const char* cause, long seat_bounces) {
    JumpMapPoint p;
    p.rpm = rpm;
    p.ok = ok;
    p.floats = floats;
    p.float_cause = cause;
    p.seat_bounces = seat_bounces;
    return p;
  };
  const JumpMapLimit none = jump_map_limit({at(3000, true, false, "", 0), at(3200, true, false, "", 0)});
  EXPECT_FALSE(none.rpm);
  EXPECT_FALSE(none.seat_bounce_rpm);
  const JumpMapLimit l =
      jump_map_limit({at(3000, true, false, "", 0), at(3200, false, true, "float", 4), at(3400, true, false, "", 7),
                      at(3600, true, true, "link", 2), at(3800, true, true, "float", 0)});
  ASSERT_TRUE(l.rpm);
  EXPECT_EQ(*l.rpm, 3600);  // 3200 failed: no evidence
  EXPECT_EQ(l.cause, "link");
  ASSERT_TRUE(l.seat_bounce_rpm);
  EXPECT_EQ(*l.seat_bounce_rpm, 3400);
  // A record from before float_cause: the journal reads a float as "float".
  JumpMapPoint old = at(3600, true, true, "", 0);
  Json j = jump_map_point_json(old);
  j.erase("float_cause");
  EXPECT_EQ(jump_map_point_from_json(j).float_cause, "float");
}

TEST(JumpMap, BadRangeIsNamed) {
  const fs::path dir = test::scratch_dir("jump_map_test", "bad");
  const test::Outcome r = test::run_camdyn(
      {"validate", kQuickstart, "--set", "study=jump_map", "--set", R"(jump_map={"low_rpm": 900, "high_rpm": 800})"},
      dir);
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("jump_map.high_rpm"), std::string::npos) << r.err;
}

// 2e9 speeds filled 8 GB before validate ended; 2e9 samples per speed
// validated and would not finish. Both are refused up front, naming the field.
TEST(JumpMap, WorkBeyondTheBudgetsIsRefusedByValidate) {
  const fs::path dir = test::scratch_dir("jump_map_test", "work");
  const std::string base = R"(jump_map={"low_rpm": 800, "high_rpm": 900, )";
  for (const auto& [fields, expected] :
       {std::pair<std::string, std::string>{R"("speeds": 2000000000})",
                                            "jump_map.speeds: 2000000000 speeds of 30 samples need about"},
        {R"("samples": 2000000000})", "jump_map.samples: transient_revolutions + samples asks for"},
        {R"("transient_revolutions": 100000})", "at each speed (at most 1e+05)"}}) {
    const test::Outcome r =
        test::run_camdyn({"validate", kQuickstart, "--set", "study=jump_map", "--set", base + fields}, dir);
    EXPECT_EQ(r.code, 2) << fields;
    EXPECT_NE(r.err.find(expected), std::string::npos) << r.err;
  }
}

/// The report's Poincaré section plot for a one-speed map of `kind`'s follower
/// (scenes.h), its section at `position` [m | rad].
Plot section_plot(const std::string& kind, double position = 0.1) {
  JumpMapStudy study;
  study.scene = test::follower_scene(kind, 1000.0);
  study.config.low_rpm = 900.0;
  study.config.high_rpm = 1100.0;
  JumpMapPoint p;
  p.rpm = 1000.0;
  p.ok = true;
  p.motion = MotionKind::periodic;
  p.period = 1;
  p.section_position = {position, position};
  const Report report = jump_map_report(study, {p}, {}, 1.0, "test");
  for (const Plot& plot : report.plots)
    if (plot.title.rfind("Poincaré section", 0) == 0) return plot;
  ADD_FAILURE() << "no Poincaré section plot";
  return {};
}

// The section samples are the follower coordinate: an arm's angle in rad.
TEST(JumpMap, ArmsSectionIsLabelledInRad) {
  const Plot plot = section_plot("oscillating_roller");
  EXPECT_EQ(plot.ylabel, "arm angle at the section [rad]");
  EXPECT_EQ(plot.title, "Poincaré section: arm angle once per revolution");
}

// A translating follower's section is a length, in the unit its size needs
// (output/plot_style.h): 0.1 m in mm, 2 m in m, 50 µm in µm.
TEST(JumpMap, TranslatingFollowersSectionIsLabelledInALengthUnitItsSizeNeeds) {
  const Plot mm = section_plot("translating_roller", 0.1);
  EXPECT_EQ(mm.ylabel, "follower position at the section [mm]");
  ASSERT_FALSE(mm.series.empty());
  EXPECT_DOUBLE_EQ(mm.series.front().y.front(), 100.0);
  EXPECT_EQ(section_plot("translating_roller", 2.0).ylabel, "follower position at the section [m]");
  const Plot um = section_plot("translating_roller", 50e-6);
  EXPECT_EQ(um.ylabel, "follower position at the section [µm]");
  EXPECT_DOUBLE_EQ(um.series.front().y.front(), 50.0);
}

// Between grid speeds of different classes the map bisects `refine` times:
// the bouncing ball's period doubling (near 603 rpm, the closed form) lies
// between the grid speeds 595 and 605 rpm; with refine 2 the change is
// bracketed to a quarter of that step by two refined speeds inside it, and
// the grid speeds are not marked refined.
TEST(JumpMap, AChangeOfClassIsBracketedByBisection) {
  const fs::path dir = test::scratch_dir("jump_map_test", "refine");
  const std::string ball = std::string(CAMDYN_SOURCE_DIR) + "/studies/periodic/bouncing_ball_jump_map.json";
  const test::Outcome r = test::run_camdyn(
      {"run", ball, "--out", (dir / "out").string(), "--quiet", "--jobs", "1", "--set",
       R"(jump_map={"low_rpm": 585, "high_rpm": 625, "speeds": 5, "ranges": 1, "samples": 8, "refine": 2})", "--set",
       R"(periodic={"max_period": 2, "lyapunov_revolutions": 20})"},
      dir);
  ASSERT_EQ(r.code, 0) << r.err;
  const Json j = Json::parse(test::read_text(dir / "out" / "jump_map.json"));
  const double step = 10.0;  // [rpm]
  std::vector<double> refined;
  double previous = 0.0;
  for (const Json& p : j["speeds"]) {
    const double rpm = p["rpm"].get<double>();
    EXPECT_GT(rpm, previous) << "in rpm order";
    previous = rpm;
    const bool on_grid = std::abs(std::remainder(rpm - 585.0, step)) < 1e-9;
    EXPECT_EQ(p["refined"].get<bool>(), !on_grid) << rpm;
    if (!on_grid) refined.push_back(rpm);
  }
  ASSERT_EQ(refined.size(), 2u) << j["speeds"].dump();
  for (const double rpm : refined) {
    EXPECT_GT(rpm, 595.0);
    EXPECT_LT(rpm, 605.0);
  }
  ASSERT_FALSE(j["transitions"].empty());
  for (const Json& t : j["transitions"])
    EXPECT_LE(t["to_rpm"].get<double>() - t["from_rpm"].get<double>(), step / 4 + 1e-9) << t.dump();
  EXPECT_EQ(j["speeds"].back()["period"], 2);
}

TEST(JumpMap, RefineBeyondItsBoundIsNamed) {
  const fs::path dir = test::scratch_dir("jump_map_test", "refine_bad");
  for (const char* refine : {"-1", "21"}) {
    const test::Outcome r =
        test::run_camdyn({"validate", kQuickstart, "--set", "study=jump_map", "--set",
                          std::string(R"(jump_map={"low_rpm": 900, "high_rpm": 1000, "refine": )") + refine + "}"},
                         dir);
    EXPECT_EQ(r.code, 2) << refine;
    EXPECT_NE(r.err.find("jump_map.refine"), std::string::npos) << r.err;
  }
}

// The progress line's unit is a speed's expected cost in revolutions, so its
// time left weighs the speeds left (issue 38: a 25-speed map's estimate was
// 87 s short of its 119 s, the cheap speeds below the jump speed setting the
// pace for the dear ones above it). 6 speeds in 2 ranges (0–2, 3–5), the
// damped jump speed at 3.5; a 2-coordinate section: a Jacobian is 5
// revolutions; transient 20, samples 30, Lyapunov 100.
TEST(JumpMap, EachSpeedWeighsWhatItIsExpectedToCost) {
  JumpMapStudy study;
  study.rpm = {1, 2, 3, 4, 5, 6};
  study.config.ranges = 2;
  study.damped_rigid_jump_speed_rpm = 3.5;
  study.section_dimension = 2;
  study.periodic.options.lyapunov_revolutions = 100;
  const double predicted = 5.0 + 3.0, transient = 20.0 + 30.0 + 2.0 * 5.0, past_jump = transient + 200.0;
  EXPECT_DOUBLE_EQ(jump_map_speed_work(study, 0), transient);  // the first of range 0
  EXPECT_DOUBLE_EQ(jump_map_speed_work(study, 1), predicted);
  EXPECT_DOUBLE_EQ(jump_map_speed_work(study, 2), predicted);
  EXPECT_DOUBLE_EQ(jump_map_speed_work(study, 3), past_jump);  // the first of range 1, past the jump
  EXPECT_DOUBLE_EQ(jump_map_speed_work(study, 5), past_jump);
  study.damped_rigid_jump_speed_rpm = 10.0;
  EXPECT_DOUBLE_EQ(jump_map_speed_work(study, 3), transient);  // the first of range 1
  EXPECT_DOUBLE_EQ(jump_map_speed_work(study, 4), predicted);
  study.config.warm_start = false;
  EXPECT_DOUBLE_EQ(jump_map_speed_work(study, 4), transient);
}

}  // namespace
}  // namespace camdyn
