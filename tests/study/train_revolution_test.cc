// The report's last revolution of a follower train (docs/valvetrain.md, "The
// train's last revolution"): on a linear train at low speed the kinematic
// lift, velocity and acceleration are the harmonic law carried through the
// valve's ratio, written here in closed form, and the dynamic ones differ
// from them by the static compression of the contact and the link; on the
// DOHC scene with lash the kinematic lift is the law less the lash, held at
// the seat; the axis spans one revolution in crank degrees (720 for a
// four-stroke) or cam degrees; the markers stand at the angles the verdict
// names and carry its text; nothing is drawn without a train.
#include "study/train_revolution.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "common/constants.h"
#include "dynamics/model.h"
#include "dynamics/separation_cause.h"
#include "dynamics/simulation.h"
#include "io/config.h"
#include "study/simulation_output.h"
#include "study_paths.h"
#include "tests/dynamics/linear_train_case.h"
#include "tests/dynamics/scenes.h"

namespace camdyn {
namespace {

const std::string kRevolutionDohc = kStudies + "valvetrain/dohc_bucket_lash.json";

/// A scene with its model and run, and the run's report.
struct RevolutionRun {
  SceneConfig scene;
  Model model;
  SimulationResult result;
  Report report;
  explicit RevolutionRun(SceneConfig s)
      : scene(std::move(s)),
        model(build_model(scene, "test")),
        result(simulate_scene(scene, "test")),
        report(simulation_report(scene, model, result)) {}
};

bool revolution_title(const std::string& title, const std::string& head) { return title.rfind(head, 0) == 0; }

/// The report's plot whose title starts with `head`; fails the test without one.
const Plot& revolution_plot(const Report& report, const std::string& head) {
  for (const Plot& p : report.plots)
    if (revolution_title(p.title, head)) return p;
  ADD_FAILURE() << "no plot \"" << head << "…\"";
  static const Plot none;
  return none;
}

/// The series labelled `label` in `plot`; fails the test without one.
const Series& labelled(const Plot& plot, const std::string& label) {
  for (const Series& s : plot.series)
    if (s.label == label) return s;
  ADD_FAILURE() << plot.title << ": no series " << label;
  static const Series none;
  return none;
}

/// The train's last-revolution plots of a report.
std::vector<const Plot*> train_revolution_plots(const Report& report) {
  std::vector<const Plot*> out;
  for (const Plot& p : report.plots)
    if (revolution_title(p.title, "Last revolution at the ") ||
        (revolution_title(p.title, "Last revolution: ") && p.title.find("of the train") != std::string::npos))
      out.push_back(&p);
  return out;
}

// The linear train of tests/dynamics/linear_train_case.h with one body: the
// valve behind a 1.5 lever on a harmonic lift s = h/2 (1 − cos θ), its spring
// massless, at a speed far below every mode, with a four-stroke crank whose
// TDC is at cam angle 30°.
constexpr double kRatio = 1.5;              // [m/m]
constexpr double kRevolutionRpm = 200.0;    // [rpm]
constexpr double kRevolutionTdcDeg = 30.0;  // [deg of cam]
constexpr double kRevolutionStepDeg = 1.0;  // output step [deg of cam]
constexpr double kContactStiffness = 1e8;   // [N/m], the case's Kelvin–Voigt contact
constexpr double kLinkStiffness = 2e7;      // [N/m], the valve's link
constexpr double kValvePreload = 300.0;     // [N]
constexpr double kValveRate = 30000.0;      // [N/m]
constexpr double kFollowerPreload = 50.0;   // [N]
constexpr double kFollowerRate = 5000.0;    // [N/m]

SceneConfig linear_valve_scene(bool crank) {
  SceneConfig s = test::linear_train_case(1, false, 0).scene;
  s.mechanism.cam.rpm = kRevolutionRpm;
  s.simulation.cycles = 2;
  s.simulation.discard_cycles = 1;
  s.simulation.steady_state = false;
  s.simulation.output_step_deg = kRevolutionStepDeg;
  if (crank) {
    ValvetrainOutputConfig v;
    v.crank_ratio = 2.0;
    v.tdc_deg = kRevolutionTdcDeg;
    s.outputs.valvetrain = v;
  }
  return s;
}

/// The static compression between the law carried to the valve and the valve
/// [m] at cam angle θ: the contact's r F_c / k_c and the link's F_l / k_l,
/// with F_l the valve spring's force and F_c the follower spring's plus r F_l
/// (inertia and damping are below 1 N at this speed).
double static_compression(double theta) {
  const double s = 0.5 * test::kLift * (1.0 - std::cos(theta));  // [m]
  const double link = kValvePreload + kValveRate * kRatio * s;   // [N]
  const double contact = kFollowerPreload + kFollowerRate * s + kRatio * link;
  return kRatio * contact / kContactStiffness + link / kLinkStiffness;
}

TEST(TrainRevolution, KinematicMotionIsTheLawThroughTheRatioOverOneRevolutionInCrankDegrees) {
  const RevolutionRun run(linear_valve_scene(true));
  ASSERT_TRUE(run.result.solver.converged()) << run.result.solver.message;
  const double omega = kRevolutionRpm * kTwoPi / 60.0;  // [rad/s]
  const double amplitude = 0.5 * test::kLift * kRatio;  // of the valve's harmonic lift [m]
  const Plot& lift = revolution_plot(run.report, "Last revolution at the valve: lift");
  ASSERT_EQ(lift.ylabel, "lift [mm]");
  ASSERT_TRUE(lift.xrange.has_value());
  EXPECT_EQ(*lift.xrange, std::make_pair(0.0, 720.0));  // one cam turn = two crank turns
  EXPECT_EQ(lift.xlabel, "crank angle from TDC, 2 × (cam angle − 30°) [deg]");
  const Series& dynamic = labelled(lift, "valve");
  const Series& kinematic = labelled(lift, "valve kinematic");
  // Every output step of exactly one revolution, once, in order from TDC.
  ASSERT_EQ(kinematic.x.size(), static_cast<std::size_t>(360.0 / kRevolutionStepDeg));
  EXPECT_TRUE(std::is_sorted(kinematic.x.begin(), kinematic.x.end()));
  EXPECT_GE(kinematic.x.front(), 0.0);
  EXPECT_LE(kinematic.x.front(), 2.0 * kRevolutionStepDeg + 1e-9);
  EXPECT_LT(kinematic.x.back(), 720.0);
  EXPECT_GE(kinematic.x.back(), 720.0 - 2.0 * kRevolutionStepDeg - 1e-9);
  double compression_max = 0.0, compression_min = 1.0;  // [m]
  for (double x : kinematic.x) {
    const double c = static_compression((x / 2.0 + kRevolutionTdcDeg) * kDegToRad);
    compression_max = std::max(compression_max, c);
    compression_min = std::min(compression_min, c);
  }
  ASSERT_GT(compression_max, 2e-5);  // the test can tell a compression from a phase error
  const Plot& velocity = revolution_plot(run.report, "Last revolution at the valve: velocity");
  const Plot& acceleration = revolution_plot(run.report, "Last revolution at the valve: acceleration");
  for (const Plot* p : {&velocity, &acceleration}) {
    ASSERT_TRUE(p->xrange.has_value());
    EXPECT_EQ(*p->xrange, std::make_pair(0.0, 720.0));
  }
  const Series& v_dyn = labelled(velocity, "valve");
  const Series& v_kin = labelled(velocity, "valve kinematic");
  const Series& a_dyn = labelled(acceleration, "valve");
  const Series& a_kin = labelled(acceleration, "valve kinematic");
  ASSERT_EQ(dynamic.y.size(), kinematic.y.size());
  ASSERT_EQ(v_kin.y.size(), kinematic.y.size());
  ASSERT_EQ(a_kin.y.size(), kinematic.y.size());
  ASSERT_EQ(v_dyn.y.size(), kinematic.y.size());
  ASSERT_EQ(a_dyn.y.size(), kinematic.y.size());
  // The compression is harmonic in θ, δ(θ) = δ(0) + Δ/2 (1 − cos θ) with Δ
  // its swing, so the valve's velocity and acceleration fall short of the
  // kinematic ones by its rate ω Δ/2 sin θ and ω² Δ/2 cos θ; the valve's
  // acceleration, a central difference of its velocity over the output step
  // Δθ = ω Δt, is short by (Δθ)² / 6 of the acceleration besides.
  const double half_swing = 0.5 * (compression_max - compression_min);      // [m]
  const double step = kRevolutionStepDeg * kDegToRad;                       // [rad]
  const double difference = amplitude * omega * omega * step * step / 6.0;  // [m/s²]
  for (std::size_t j = 0; j < kinematic.x.size(); ++j) {
    const double theta = (kinematic.x[j] / 2.0 + kRevolutionTdcDeg) * kDegToRad;  // [rad]
    SCOPED_TRACE(testing::Message() << "crank " << kinematic.x[j] << "°");
    EXPECT_NEAR(kinematic.y[j], 1e3 * amplitude * (1.0 - std::cos(theta)), 1e-9);  // [mm]
    EXPECT_NEAR(v_kin.y[j], amplitude * omega * std::sin(theta), 1e-9);
    EXPECT_NEAR(a_kin.y[j], amplitude * omega * omega * std::cos(theta), 1e-9);
    // The dynamic valve sits below the kinematic one by the static
    // compression; 2 % of it covers the inertia and damping forces (below
    // 1 N, against the 660 N on the link at full lift).
    EXPECT_NEAR(kinematic.y[j] - dynamic.y[j], 1e3 * static_compression(theta), 1e3 * 0.02 * compression_max);
    EXPECT_NEAR(v_kin.y[j] - v_dyn.y[j], omega * half_swing * std::sin(theta), 0.02 * omega * half_swing);
    EXPECT_NEAR(a_kin.y[j] - a_dyn.y[j], omega * omega * half_swing * std::cos(theta),
                0.02 * omega * omega * half_swing + difference);
  }
}

TEST(TrainRevolution, WithoutACrankScaleTheAxisIsOneCamTurn) {
  const RevolutionRun run(linear_valve_scene(false));
  const Plot& lift = revolution_plot(run.report, "Last revolution at the valve: lift");
  ASSERT_TRUE(lift.xrange.has_value());
  EXPECT_EQ(*lift.xrange, std::make_pair(0.0, 360.0));
  EXPECT_EQ(lift.xlabel, "cam angle [deg]");
  const Series& kinematic = labelled(lift, "valve kinematic");
  ASSERT_EQ(kinematic.x.size(), static_cast<std::size_t>(360.0 / kRevolutionStepDeg));
  for (std::size_t j = 0; j < kinematic.x.size(); ++j)
    EXPECT_NEAR(kinematic.y[j], 1e3 * 0.5 * test::kLift * kRatio * (1.0 - std::cos(kinematic.x[j] * kDegToRad)), 1e-9);
}

// The DOHC bucket: the bucket rests 0.2 mm up on its seat, the link into the
// seated valve has 0.2 mm of lash, so the valve's kinematic lift from its
// seat is max(s − 0.2 mm, 0).
TEST(TrainRevolution, TheValvesKinematicLiftIsTheLawLessTheLashHeldAtItsSeat) {
  SceneConfig scene = load_scene(kRevolutionDohc);
  scene.simulation.cycles = 2;
  const RevolutionRun run(scene);
  const Plot& lift = revolution_plot(run.report, "Last revolution at the valve: lift from its seat");
  ASSERT_EQ(lift.ylabel, "lift [mm]");
  ASSERT_TRUE(lift.xrange.has_value());
  EXPECT_EQ(*lift.xrange, std::make_pair(0.0, 720.0));
  const Series& kinematic = labelled(lift, "valve kinematic");
  const Series& dynamic = labelled(lift, "valve");
  constexpr double kLash = 0.0002;  // [m]
  double peak = 0.0, dynamic_peak = 0.0;
  for (std::size_t j = 0; j < kinematic.x.size(); ++j) {
    const double theta = kinematic.x[j] / 2.0 * kDegToRad;  // TDC at cam angle 0
    EXPECT_NEAR(kinematic.y[j], 1e3 * std::max(run.model.law->eval(theta).s - kLash, 0.0), 1e-9);
    peak = std::max(peak, kinematic.y[j]);
    dynamic_peak = std::max(dynamic_peak, dynamic.y[j]);
  }
  // The law's 9.36 mm less the lash; the valve's peak within the
  // compression of the link and the contact (a few µm under 1 kN).
  EXPECT_NEAR(peak, 1e3 * (run.model.law->max_s() - kLash), 1e-6);
  EXPECT_NEAR(dynamic_peak, peak, 0.02);
  // The seat, link and spring forces of every body are drawn.
  EXPECT_EQ(labelled(revolution_plot(run.report, "Last revolution: seat forces"), "follower").x.size(),
            kinematic.x.size());
  EXPECT_EQ(labelled(revolution_plot(run.report, "Last revolution: seat forces"), "valve").x.size(),
            kinematic.x.size());
  EXPECT_EQ(labelled(revolution_plot(run.report, "Last revolution: link forces"), "valve").x.size(),
            kinematic.x.size());
  EXPECT_EQ(labelled(revolution_plot(run.report, "Last revolution: spring forces"), "valve").x.size(),
            kinematic.x.size());
}

/// The crank angle of cam angle `cam_deg` on the DOHC scene (crank_ratio 2, TDC at 0) [deg].
double dohc_crank(double cam_deg) { return 2.0 * std::fmod(cam_deg, 360.0); }

/// Checks that each of the train's last-revolution plots marks exactly
/// `expected` (label → crank angle), and that the verdict prints each with the
/// same crank angle.
void expect_markers(const RevolutionRun& run, const std::vector<std::pair<std::string, double>>& expected) {
  const Verdict v = simulation_verdict(run.scene, run.model, run.result);
  std::string text = v.headline;
  for (const std::string& line : v.details) text += "\n" + line;
  const std::vector<const Plot*> plots = train_revolution_plots(run.report);
  ASSERT_EQ(plots.size(), 6u);
  for (const Plot* plot : plots) {
    std::vector<const Series*> markers;
    for (const Series& s : plot->series)
      if (revolution_title(s.label, "verdict: ")) markers.push_back(&s);
    ASSERT_EQ(markers.size(), expected.size()) << plot->title;
    for (std::size_t k = 0; k < expected.size(); ++k) {
      SCOPED_TRACE(plot->title + ": " + markers[k]->label);
      EXPECT_EQ(markers[k]->style, "points");
      EXPECT_EQ(markers[k]->label.rfind("verdict: " + expected[k].first + " at ", 0), 0u);
      ASSERT_EQ(markers[k]->x.size(), 1u);
      EXPECT_NEAR(markers[k]->x.front(), expected[k].second, 1e-9);
      // The verdict names the marker's angle, crank degrees beside cam degrees.
      const std::string angle = markers[k]->label.substr(markers[k]->label.rfind(" at ") + 4);
      EXPECT_NE(text.find(angle), std::string::npos) << text;
      const std::size_t open = angle.find(" (");
      ASSERT_NE(open, std::string::npos) << angle;
      const double cam = std::stod(angle), crank = std::stod(angle.substr(open + 2));
      EXPECT_NEAR(crank, expected[k].second, 1e-3 * expected[k].second + 1e-9);
      EXPECT_NEAR(crank, 2.0 * cam, 2e-3 * crank + 1e-9);
      EXPECT_NE(angle.find("° crank)"), std::string::npos) << angle;
    }
  }
}

TEST(TrainRevolution, InContactTheMinimumForceIsMarkedWhereTheVerdictSaysItIs) {
  SceneConfig scene = load_scene(kRevolutionDohc);
  scene.simulation.cycles = 2;
  const RevolutionRun run(scene);
  const VerdictAngles at = verdict_angles(run.model, run.result);
  ASSERT_TRUE(at.min_force_deg.has_value());
  EXPECT_FALSE(at.lift_off_deg || at.landing_deg || at.lets_go_deg);
  // The least contact force among the samples of the evaluated window in
  // contact above the take-up windows (docs/valvetrain.md) is at that angle.
  const TimeSeries& ts = run.result.series;
  std::size_t least = ts.time.size();
  for (std::size_t i = 0; i < ts.time.size(); ++i)
    if (ts.time[i] >= run.result.evaluated_from && !(ts.gap[i] > 0.0) &&
        !in_take_up_windows(run.model.take_up, run.model.law->eval(ts.cam_angle_deg[i] * kDegToRad)) &&
        (least == ts.time.size() || ts.contact_force[i] < ts.contact_force[least]))
      least = i;
  ASSERT_LT(least, ts.time.size());
  EXPECT_NEAR(std::fmod(ts.cam_angle_deg[least], 360.0), *at.min_force_deg, 1e-9);
  expect_markers(run, {{"minimum contact force", dohc_crank(*at.min_force_deg)}});
}

TEST(TrainRevolution, AboveTheJumpSpeedLiftOffLandingAndTheLinkAreMarkedWhereTheVerdictSaysTheyAre) {
  const SceneConfig scene = load_scene(kRevolutionDohc, {"mechanism.cam.rpm=4200", "simulation.cycles=3"});
  const RevolutionRun run(scene);
  // The first float separation of the evaluated window (not of the discarded
  // cycle) and the landing after it, from the events.
  const std::vector<ContactEvent>& events = run.result.events;
  const auto lift_off = std::find_if(events.begin(), events.end(), [&](const ContactEvent& e) {
    return e.time >= run.result.evaluated_from && !e.onset && e.cause == SeparationCause::float_gap;
  });
  ASSERT_NE(lift_off, events.end());
  const auto landing = std::find_if(lift_off, events.end(), [](const ContactEvent& e) { return e.onset; });
  ASSERT_NE(landing, events.end());
  ASSERT_TRUE(run.result.metrics.train);
  const TrainMetrics& t = *run.result.metrics.train;
  ASSERT_FALSE(t.separates_first.empty());
  // The cam contact's lift-off is where it lets go first (its own marker); a
  // link that lets go first has a marker of its own.
  if (t.separates_first == "cam contact") {
    // separates_first is judged at the midpoint of the step that opens the gap (dynamics/train_observer.h).
    EXPECT_NEAR(std::fmod(lift_off->cam_angle_deg, 360.0), std::fmod(t.separates_first_deg, 360.0), 1e-2);
    expect_markers(run,
                   {{"separates", dohc_crank(lift_off->cam_angle_deg)}, {"lands", dohc_crank(landing->cam_angle_deg)}});
  } else {
    expect_markers(run, {{"separates", dohc_crank(lift_off->cam_angle_deg)},
                         {"lands", dohc_crank(landing->cam_angle_deg)},
                         {"lets go first (" + t.separates_first + ")", dohc_crank(t.separates_first_deg)}});
  }
}

// A one-body train (the bucket and the valve as one, on its seat): the valve
// is the follower, its acceleration the follower's own column; no crank
// scale: cam degrees.
TEST(TrainRevolution, OnAOneBodyTrainTheValveIsTheFollower) {
  const SceneConfig scene =
      load_scene(kStudies + "valvetrain/bucket_tappet.json", {"simulation.cycles=2", "simulation.discard_cycles=1"});
  const RevolutionRun run(scene);
  const Plot& acceleration = revolution_plot(run.report, "Last revolution at the follower: acceleration");
  EXPECT_NE(acceleration.title.find("(follower_acceleration)"), std::string::npos) << acceleration.title;
  ASSERT_TRUE(acceleration.xrange.has_value());
  EXPECT_EQ(*acceleration.xrange, std::make_pair(0.0, 360.0));
  const Series& dynamic = labelled(acceleration, "follower");
  const TimeSeries& ts = run.result.series;
  // The last sample of the run is the revolution's, at its place on the axis.
  const double x_last = std::fmod(ts.cam_angle_deg.back(), 360.0);
  const auto it = std::find(dynamic.x.begin(), dynamic.x.end(), x_last);
  ASSERT_NE(it, dynamic.x.end());
  EXPECT_EQ(dynamic.y[static_cast<std::size_t>(it - dynamic.x.begin())], ts.follower_acceleration.back());
}

TEST(TrainRevolution, NothingWithoutATrainOrARevolution) {
  SceneConfig no_train = test::cycloidal_cam_scene(700.0);
  no_train.outputs.valvetrain = ValvetrainOutputConfig{};
  const RevolutionRun plain(no_train);
  EXPECT_TRUE(train_revolution_plots(plain.report).empty());
  SceneConfig short_run = linear_valve_scene(true);
  short_run.simulation.cycles = 0.5;
  short_run.simulation.discard_cycles = 0;
  const RevolutionRun half(short_run);
  EXPECT_TRUE(train_revolution_plots(half.report).empty());
  EXPECT_FALSE(half.report.plots.empty());
}

}  // namespace
}  // namespace camdyn
