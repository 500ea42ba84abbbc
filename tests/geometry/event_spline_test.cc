// The event of a motion law as one spline (geometry/event_spline.h,
// `motion_law.event`): outside the event the law is the one it was spliced
// into bit for bit, for every kind of law it can be spliced into; at the
// joins s, s', s'' (and s''' from degree 4 on) are continuous; and a config
// with an event is read, written and read back to the same law.
#include "geometry/event_spline.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <filesystem>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

#include "common/errors.h"
#include "io/config.h"
#include "io/json_archive.h"

namespace camdyn {
namespace {

namespace fs = std::filesystem;
constexpr double kRad = std::numbers::pi / 180.0;
const fs::path kProfiles = fs::path(CAMDYN_SOURCE_DIR) / "profiles";

/// A translating scene on `law_json` (a motion_law object or a profile path).
SceneConfig scene_on(const Json& law_json) {
  Json scene = Json::parse(R"({
    "name": "event-check",
    "mechanism": {
      "cam": { "base_radius": 0.02, "rpm": 1000 },
      "follower": { "shape": { "type": "flat", "face_width": 0.04 }, "mass": 0.09,
                    "spring": { "stiffness": 35000, "preload": 250 } },
      "contact": { "stiffness": 1e9 } }
  })");
  scene["mechanism"]["cam"]["motion_law"] = law_json;
  return scene_from_json(scene, ConfigSource{"scene.json", kProfiles.parent_path().string()});
}

/// Free control points of a wavy event: not a fit of anything, so a test
/// cannot pass because the spline happens to copy the law it replaces.
std::vector<double> wavy(int m, double lift) {
  std::vector<double> c;
  for (int j = 0; j < m; ++j) c.push_back(lift * (0.5 + 0.4 * std::sin(1.3 * j)));
  return c;
}

struct Base {
  std::string name;
  Json law;
};

class EventSplice : public ::testing::TestWithParam<Base> {};

TEST_P(EventSplice, KeepsTheLawOutsideTheEventBitForBit) {
  const SceneConfig base_scene = scene_on(GetParam().law);
  const MotionLaw base = build_motion_law(base_scene.mechanism.cam.motion_law, "scene.json");
  for (const int degree : {3, 5, 7}) {
    const double from = 10.0 * kRad, to = 140.0 * kRad;
    const EventSplineBasis basis = event_spline_basis(base, from, to, degree, 12);
    const MotionLaw spliced = splice_event(base, basis, wavy(12, 0.009));
    int checked = 0;
    for (int i = 0; i < 36000; ++i) {
      const double theta = 2.0 * std::numbers::pi * i / 36000;
      if (theta >= from && theta < to) continue;
      const LawSample a = base.eval(theta), b = spliced.eval(theta);
      ASSERT_EQ(a.s, b.s) << "at " << theta / kRad << " deg";
      ASSERT_EQ(a.ds, b.ds) << "at " << theta / kRad << " deg";
      ASSERT_EQ(a.d2s, b.d2s) << "at " << theta / kRad << " deg";
      ASSERT_EQ(a.d3s, b.d3s) << "at " << theta / kRad << " deg";
      ++checked;
    }
    EXPECT_GT(checked, 20000);
  }
}

// At each join the event's one-sided derivatives equal the kept law's. The
// kept side is read just outside the join and carried to it by its Taylor
// series, so the tolerance is that series' remainder (one step of 1e-7 rad
// times the next derivative) plus rounding.
TEST_P(EventSplice, IsContinuousAtTheJoinsUpToSecondOrThirdDerivative) {
  const SceneConfig base_scene = scene_on(GetParam().law);
  const MotionLaw base = build_motion_law(base_scene.mechanism.cam.motion_law, "scene.json");
  for (const int degree : {3, 5}) {
    const double from = 10.0 * kRad, to = 140.0 * kRad;
    const EventSplineBasis basis = event_spline_basis(base, from, to, degree, 12);
    const MotionLaw spliced = splice_event(base, basis, wavy(12, 0.009));
    const int order = event_join_order(degree);
    EXPECT_EQ(order, degree >= 4 ? 3 : 2);
    for (const auto& [join, outside] : {std::pair{from, -1.0}, std::pair{to, 1.0}}) {
      const LawSample in = spliced.eval(join + (outside < 0 ? 0.0 : -1e-12));  // the event's side
      const LawSample near = spliced.eval(join + outside * 1e-7);              // the kept side
      const double d = -outside * 1e-7;                                        // back to the join
      const std::array<double, 4> kept = {near.s + d * near.ds + 0.5 * d * d * near.d2s,
                                          near.ds + d * near.d2s + 0.5 * d * d * near.d3s, near.d2s + d * near.d3s,
                                          near.d3s};
      const std::array<double, 4> event = {in.s, in.ds, in.d2s, in.d3s};
      const std::array<double, 4> scale = {1e-2, 1e-2, 1e-1, 1.0};  // lift, s', s'', s''' magnitudes [m/radᵏ]
      for (int k = 0; k <= order; ++k)
        EXPECT_NEAR(event[k], kept[k], 1e-6 * scale[k]) << "derivative " << k << " at " << join / kRad << " deg";
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Laws, EventSplice,
                         ::testing::Values(Base{"periodic_spline", Json("profiles/flat_tappet_valve_lift.json")},
                                           Base{"segments", Json("profiles/polynomial_4567.json")},
                                           Base{"harmonic_eccentric", Json("profiles/harmonic_eccentric.json")}),
                         [](const auto& param_info) { return param_info.param.name; });

TEST(EventSplineConfig, RoundTripsThroughJsonToTheSameLaw) {
  Json law = Json::parse(R"({"segments": [
      {"type": "dwell", "end_deg": 20},
      {"type": "rise", "law": "cycloidal", "end_deg": 120, "lift": 0.009},
      {"type": "return", "law": "cycloidal", "end_deg": 220},
      {"type": "dwell", "end_deg": 360}],
    "event": {"from_deg": 20, "to_deg": 220, "degree": 5, "control_points": [0.002, 0.006, 0.009, 0.009, 0.006, 0.002]}})");
  const SceneConfig a = scene_on(law);
  ASSERT_TRUE(a.mechanism.cam.motion_law.event.has_value());
  const SceneConfig b = scene_from_json(to_json(a), ConfigSource{"scene.json", "."});
  EXPECT_EQ(a.mechanism.cam.motion_law, b.mechanism.cam.motion_law);
  const MotionLaw la = build_motion_law(a.mechanism.cam.motion_law, "scene.json");
  const MotionLaw lb = build_motion_law(b.mechanism.cam.motion_law, "scene.json");
  for (int i = 0; i < 3600; ++i) EXPECT_EQ(la.eval(i * 0.1 * kRad).s, lb.eval(i * 0.1 * kRad).s);
  // The nose is free: the event need not stop at the top (s' = s'' = 0 of two segments).
  EXPECT_LT(la.eval(120.0 * kRad).d2s, -1e-4);
}

TEST(EventSplineConfig, RefusesAnEventThatDoesNotFit) {
  Json law = Json::parse(R"({"spline": {"degree": 5, "knots_deg": [0, 60, 120, 180, 240, 300],
    "lift": [0, 0.001, 0.002, 0.002, 0.001, 0]}, "event": {"from_deg": 200, "to_deg": 100, "control_points": [0.001]}})");
  EXPECT_THROW(scene_on(law), InputError);
  law["event"] = Json::parse(R"({"from_deg": 10, "to_deg": 100, "control_points": [0.001], "wrong": 1})");
  EXPECT_THROW(scene_on(law), InputError);
}

}  // namespace
}  // namespace camdyn
