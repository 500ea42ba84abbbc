// Valve-train verdicts (docs/valvetrain.md "What each verdict means"): every
// separation is a take-up bounce, float or a seat bounce. Against closed
// forms: a follower resting on its seat at the lash, met by a cam on a
// constant-velocity ramp, leaves at (1 + e) times the ramp speed and rebounds
// in flights whose relative speeds fall by e and heights by e² — each a
// parabola of height v²/(2a) under the spring's deceleration a = F/m — all
// inside the take-up window; over the nose of a law above its jump speed the
// separation is float. The take-up window's heights are the seat's lash
// carried through the train; a valve the law cannot seat is held open, a lash
// beyond the lift is bad input.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "dynamics/model.h"
#include "dynamics/simulation.h"
#include "input_error_of.h"
#include "io/config.h"
#include "scenes.h"
#include "study_paths.h"

namespace camdyn {
namespace {

using test::input_error_of;

const ConfigSource kRampSource{"ramp.json", CAMDYN_SOURCE_DIR};

// The smootherstep: 0 below 0, 1 above 1, C2 in between.
double ramp_smoother(double x) {
  x = std::clamp(x, 0.0, 1.0);
  return x * x * x * (10.0 - 15.0 * x + 6.0 * x * x);
}

// The ramp law's velocity [m/deg]: 0 before 18°, a constant `v` from 22° to
// 78° (reached smoothly), turning over a cosine nose to −v at 102°, −v to 158°,
// back to 0 at 162°; symmetric about 90°, so it closes.
double seat_ramp_velocity(double deg, double v) {
  if (deg < 18.0 || deg > 162.0) return 0.0;
  if (deg < 22.0) return v * ramp_smoother((deg - 18.0) / 4.0);
  if (deg <= 78.0) return v;
  if (deg < 102.0) return v * std::cos(std::numbers::pi * (deg - 78.0) / 24.0);
  if (deg <= 158.0) return -v;
  return -v * (1.0 - ramp_smoother((deg - 158.0) / 4.0));
}

// A translating flat follower of mass m = 0.01 kg resting under gravity on
// its seat at the lash λ = 0.1 mm (no spring: off the cam it falls at g,
// exactly), met at 25.7° by the cam's ramp at 0.01745 mm/deg (0.01 m/s at
// 100 rpm); Flores' contact with restitution 0.8, stiff (K = 1e11 N/m^1.5)
// so that its impacts are short and their force far above the weight (75×
// at the take-up), its damping scaled by each impact's own speed
// (reference_velocity far below them). The law is a quintic spline through the ramp every 0.5°,
// its ramps marked as ending at 78° and 102° (outputs.valvetrain).
Json ramp_scene_json(double rpm) {
  constexpr double kVelocity = 1e-3 * std::numbers::pi / 180.0;  // [m/deg]: 1 mm/rad
  Json knots = Json::array(), lift = Json::array();
  double s = 0.0;
  for (int i = 0; i < 720; ++i) {
    const double deg = 0.5 * i;
    knots.push_back(deg);
    lift.push_back(s);
    constexpr int kSub = 200;  // midpoint rule over the next half degree
    for (int j = 0; j < kSub; ++j) s += seat_ramp_velocity(deg + 0.5 * (j + 0.5) / kSub, kVelocity) * 0.5 / kSub;
  }
  Json doc = Json::parse(R"({
    "gravity": 9.81,
    "mechanism": {
      "cam": { "base_radius": 0.03, "direction": "ccw" },
      "follower": { "shape": { "type": "flat", "face_width": 0.03 }, "mass": 0.01,
                    "seat": { "position": 0.0001, "model": "hunt_crossley", "stiffness": 1e9, "exponent": 1.0,
                              "restitution": 0.3 } },
      "contact": { "model": "flores", "stiffness": 1e11, "exponent": 1.5, "restitution": 0.8,
                   "reference_velocity": 1e-6 } },
    "simulation": { "duration": 0.1, "discard_cycles": 0, "output_step": 5e-6 },
    "integrator": { "method": "cvode_bdf", "rtol": 1e-10, "atol": 1e-14 },
    "outputs": { "valvetrain": { "ramp_end_deg": [78, 102] } } })");
  doc["mechanism"]["cam"]["rpm"] = rpm;
  doc["mechanism"]["cam"]["motion_law"] = Json{{"spline", Json{{"degree", 5}, {"knots_deg", knots}, {"lift", lift}}}};
  return doc;
}

// One separation of the cam contact: its opening and closing, and the largest gap between them.
struct RampFlight {
  double opened = 0.0, landed = 0.0;  // [s]
  double separation_speed = 0.0;      // [m/s]
  SeparationCause cause = SeparationCause::none;
  double peak_gap = 0.0;  // [m], from the time series
  double position = 0.0;  // the follower's position at the peak [m]
};

std::vector<RampFlight> ramp_flights(const SimulationResult& r) {
  std::vector<RampFlight> out;
  for (std::size_t i = 0; i + 1 < r.events.size(); ++i) {
    const ContactEvent& e = r.events[i];
    if (e.onset || e.lash) continue;
    out.push_back({e.time, r.events[i + 1].time, e.speed, e.cause, 0.0, 0.0});
  }
  const TimeSeries& ts = r.series;
  for (RampFlight& f : out)
    for (std::size_t k = 0; k < ts.time.size(); ++k)
      if (ts.time[k] > f.opened && ts.time[k] < f.landed && ts.gap[k] > f.peak_gap) {
        f.peak_gap = ts.gap[k];
        f.position = ts.follower_position[k];
      }
  return out;
}

// A stiff valve seat at `position` [m]: Hunt and Crossley, 1e9 N/m, restitution 0.3.
SeatConfig stiff_seat(double position) {
  SeatConfig seat;
  seat.position = position;
  seat.model = ContactModel::hunt_crossley;
  seat.stiffness = 1e9;
  seat.exponent = 1.0;
  seat.restitution = 0.3;
  return seat;
}

// Whether the scene's take-up window ends at its marked ramps.
bool model_ramps_marked(const SceneConfig& scene) { return build_model(scene, "ramp.json").take_up.ramps_from_law; }

TEST(TakeUpBounce, RampMeetsTheSeatedFollowerAndTheBouncesDecayByRestitutionSquared) {
  const double rpm = 100.0, omega = rpm * 2.0 * std::numbers::pi / 60.0;  // [rad/s]
  const SceneConfig scene = scene_from_json(ramp_scene_json(rpm), kRampSource);
  const SimulationResult r = simulate_scene(scene, "ramp.json");
  ASSERT_TRUE(r.solver.converged()) << r.solver.message;
  const double ramp_speed = 1e-3 * omega;  // [m/s]
  constexpr double kGravity = 9.81;        // [m/s²]

  // The take-up: the cam meets the seated follower at the ramp speed.
  const auto take_up = std::find_if(r.events.begin(), r.events.end(), [](const ContactEvent& e) { return e.onset; });
  ASSERT_NE(take_up, r.events.end());
  EXPECT_TRUE(take_up->lash);
  constexpr double kSpeedLevel = 1e-6;  // the root's speed against the law's, at rtol 1e-10 (spline: 1e-6)
  EXPECT_NEAR(take_up->speed / ramp_speed, 1.0, kSpeedLevel);

  const std::vector<RampFlight> bounces = ramp_flights(r);
  ASSERT_GE(bounces.size(), 3u);
  // Each rebound's flight is a parabola under g (the seat and the cam do not
  // touch it): h = v² / (2g). Level: the output step samples the peak to
  // 3e-5 relative; nothing but gravity acts in flight.
  constexpr double kParabolaLevel = 1e-3;
  const double e = bounces[1].separation_speed / bounces[0].separation_speed;
  std::size_t checked = 0;
  for (std::size_t k = 0; k < bounces.size(); ++k) {
    const RampFlight& f = bounces[k];
    EXPECT_EQ(f.cause, SeparationCause::take_up) << "bounce " << k;
    // The weight's share of an impact's impulse grows as the bounces slow: those within 0.45 of the first.
    if (f.separation_speed < 0.45 * bounces[0].separation_speed) continue;
    ++checked;
    EXPECT_NEAR(f.peak_gap / (f.separation_speed * f.separation_speed / (2.0 * kGravity)), 1.0, kParabolaLevel)
        << "bounce " << k;
    if (k == 0) continue;
    // Geometric decay: speeds by e, heights by e² (each impact's weight impulse is a few per cent of it).
    constexpr double kRestitutionLevel = 0.05;
    EXPECT_NEAR(f.separation_speed / bounces[k - 1].separation_speed / e, 1.0, kRestitutionLevel) << "bounce " << k;
    EXPECT_NEAR(f.peak_gap / bounces[k - 1].peak_gap / (e * e), 1.0, 2.0 * kRestitutionLevel) << "bounce " << k;
  }
  EXPECT_GE(checked, 3u);
  EXPECT_NEAR(e, 0.8, 0.05);
  // All in the take-up window (the ramp, to 78°) and none a jump.
  const Metrics& m = r.metrics;
  ASSERT_TRUE(m.train && m.float_fraction);
  EXPECT_TRUE(model_ramps_marked(scene));
  EXPECT_EQ(*m.float_fraction, 0.0);
  EXPECT_GT(m.separation_fraction, 0.0);
  EXPECT_EQ(m.train->take_up_bounces, static_cast<long>(bounces.size()));
  EXPECT_FALSE(separates(m));
}

TEST(TakeUpBounce, AboveItsJumpSpeedTheNoseFloats) {
  SceneConfig scene = test::cycloidal_cam_scene(1000.0);
  scene.mechanism.follower.seat = stiff_seat(1e-4);
  const double jump_rpm = build_model(scene, "cycloid.json").rigid_jump_speed_rpm;
  ASSERT_TRUE(std::isfinite(jump_rpm));
  scene.mechanism.cam.rpm = 0.7 * jump_rpm;
  const SimulationResult below = simulate_scene(scene, "cycloid.json");
  ASSERT_TRUE(below.solver.converged());
  EXPECT_FALSE(separates(below.metrics));
  scene.mechanism.cam.rpm = 1.3 * jump_rpm;
  const SimulationResult above = simulate_scene(scene, "cycloid.json");
  ASSERT_TRUE(above.solver.converged());
  EXPECT_TRUE(separates(above.metrics));
  EXPECT_GT(above.metrics.float_fraction.value_or(0.0), 0.0);
  // The cycloidal rise decelerates from 60° to 120°, where the spring cannot
  // hold the follower: the float's flight spans it (it may open as a rebound
  // of the take-up before 60°, and flies on).
  const auto floated = std::find_if(above.events.begin(), above.events.end(), [&](const ContactEvent& e) {
    return !e.onset && e.cause == SeparationCause::float_gap && e.time >= above.evaluated_from;
  });
  ASSERT_NE(floated, above.events.end());
  const auto landed = std::find_if(floated, above.events.end(), [](const ContactEvent& e) { return e.onset; });
  ASSERT_NE(landed, above.events.end());
  EXPECT_EQ(landed->cause, SeparationCause::float_gap);
  EXPECT_LT(std::fmod(floated->cam_angle_deg, 360.0), 120.0);
  EXPECT_GT(std::fmod(landed->cam_angle_deg, 360.0), 60.0);
}

SceneConfig bucket_scene_with(const std::vector<std::string>& overrides = {}) {
  return load_scene(kStudies + "valvetrain/bucket_tappet.json", overrides);
}

TEST(TakeUpWindow, TheBucketsLashIsItsSeatHeight) {
  const Model model = build_model(bucket_scene_with(), "bucket.json");
  const TakeUpWindow& w = model.take_up;
  ASSERT_TRUE(w.applies);
  EXPECT_NEAR(w.base, 0.0, 1e-7);  // the spline's least value, sampled
  EXPECT_NEAR(w.take_up, 2e-4 - w.base, 1e-12);
  EXPECT_FALSE(w.ramps_from_law);  // a spline marks no ramp: twice the lash
  EXPECT_NEAR(w.opening_end, 2.0 * w.take_up, 1e-15);
  EXPECT_EQ(w.held_open_body, -1);
  EXPECT_EQ(w.never_lifted_body, -1);
}

TEST(TakeUpWindow, AValveHeldOffItsSeatIsHeldOpen) {
  // Link lash 0.1 mm under the bucket's 0.2 mm seat: the valve is held 0.1 mm off its seat.
  SceneConfig scene = bucket_scene_with();
  TrainBodyConfig valve;
  valve.name = "valve";
  valve.mass = 0.02;
  valve.link = LinkConfig{1.0, 1e8, 20.0, 1e-4, true};
  valve.seat = stiff_seat(0.0);
  scene.mechanism.train.push_back(valve);
  const Model model = build_model(scene, "held.json");
  EXPECT_EQ(model.take_up.held_open_body, 1);
  EXPECT_NEAR(model.take_up.held_open_by, 1e-4, 1e-12);
  EXPECT_NE(take_up_window_problem(model.train, model.take_up).find("valve held open"), std::string::npos);
}

TEST(TakeUpWindow, ALashBeyondTheLiftIsBadInput) {
  for (const char* lash : {"1", "0.05"}) {
    const InputError e = input_error_of([&] {
      build_model(load_scene(kStudies + "valvetrain/pushrod_rocker.json",
                             {std::string("mechanism.train[1].link.lash=") + lash}),
                  "pushrod.json");
    });
    EXPECT_EQ(e.path(), "mechanism.train[1].link.lash") << lash;
    EXPECT_NE(std::string(e.what()).find("never lifts"), std::string::npos) << e.what();
  }
  const InputError above = input_error_of([&] {
    build_model(bucket_scene_with({"mechanism.follower.seat.position=0.02"}), "bucket.json");  // above the 9 mm lift
  });
  EXPECT_EQ(above.path(), "mechanism.follower.seat.position");
}

}  // namespace
}  // namespace camdyn
