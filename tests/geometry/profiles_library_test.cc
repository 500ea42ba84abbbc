// The profiles library (profiles/*.json, documented in profiles/README.md):
// every file loads through the config reader as a motion law, closes over a
// turn, has the documented lift, and is as smooth as documented (s, s', s''
// continuous across every piece boundary and across 360° → 0°; s''' too where
// the table says C3). Laws with closed forms are compared with them.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <numbers>
#include <string>
#include <vector>

#include "common/constants.h"
#include "geometry/motion_law.h"
#include "io/config.h"
#include "law_checks.h"
#include "tolerance.h"

namespace camdyn {
namespace {

namespace fs = std::filesystem;

const fs::path kProfilesDir = fs::path(CAMDYN_SOURCE_DIR) / "profiles";

/// What profiles/README.md promises about a profile.
struct Documented {
  double lift;     ///< [m], or [rad] for an oscillating arm
  int continuity;  ///< 1: C1 (s'' jumps), 2: C2, 3: C3 or better
  bool oscillating = false;
};

const std::map<std::string, Documented>& documented() {
  static const std::map<std::string, Documented> table = {
      {"cycloidal_rise_return", {0.02, 2}},     {"polynomial_345", {0.02, 2}},
      {"polynomial_4567", {0.02, 3}},           {"harmonic_rise_return", {0.02, 1}},
      {"harmonic_eccentric", {0.02, 3}},        {"modified_trapezoid_rise_return", {0.02, 2}},
      {"modified_sine_rise_return", {0.02, 2}}, {"flat_tappet_valve_lift", {0.009, 3}},
      {"dohc_bucket_lift", {0.00936161, 3}},    {"oscillating_roller_packaging", {20.0 * kPi / 180.0, 2, true}},
  };
  return table;
}

Json read_json(const fs::path& file) {
  std::ifstream in(file);
  return Json::parse(in);
}

/// A valid scene whose motion law is the profile file, read by the config
/// reader exactly as `"motion_law": "profiles/NAME.json"` would be.
MotionLaw load_translating(const fs::path& file) {
  Json scene = Json::parse(R"({
    "name": "profile-check",
    "mechanism": {
      "cam": { "base_radius": 0.05, "rpm": 1000, "motion_law": "" },
      "follower": { "shape": { "type": "roller", "radius": 0.01 }, "mass": 0.3,
                    "spring": { "stiffness": 5000, "preload": 40 } },
      "contact": { "stiffness": 1e9 } }
  })");
  scene["mechanism"]["cam"]["motion_law"] = file.string();
  const SceneConfig config = scene_from_json(scene, ConfigSource{"scene.json", kProfilesDir.string()});
  EXPECT_EQ(fs::path(config.mechanism.cam.motion_law.source), file);
  return build_motion_law(config.mechanism.cam.motion_law, file.string());
}

/// Oscillating-arm laws (segments with lift_deg) are read segment by segment:
/// the scene around them needs the oscillating follower, another module's.
MotionLaw load_oscillating(const fs::path& file) {
  const Json doc = read_json(file);
  MotionLawConfig config;
  for (const Json& s : doc.at("segments")) {
    SegmentConfig seg;
    seg.type = parse_enum<SegmentType>(s.at("type").get<std::string>());
    seg.end_deg = s.at("end_deg").get<double>();
    if (s.contains("law")) seg.law = parse_enum<SegmentLaw>(s.at("law").get<std::string>());
    if (s.contains("lift_deg")) seg.lift_deg = s.at("lift_deg").get<double>();
    for (const auto& item : s.items())
      EXPECT_TRUE(item.key() == "type" || item.key() == "end_deg" || item.key() == "law" || item.key() == "lift_deg")
          << file << ": unexpected key " << item.key();
    config.segments.push_back(seg);
  }
  return build_motion_law(config, file.string());
}

/// Largest |s'''| step between neighbours of a dense grid, divided by the
/// spacing: a bound on |s''''| where s''' is continuous (and ~jump/spacing at
/// a jump, which the 1e-7 rad probe below still detects by a factor of ~400).
double d4_bound(const MotionLaw& law) {
  constexpr int n = 36000;
  double worst = 0, prev = law.eval(0).d3s;
  for (int i = 1; i <= n; ++i) {
    const double cur = law.eval(kTwoPi * i / n).d3s;
    worst = std::max(worst, std::abs(cur - prev) * n / kTwoPi);
    prev = cur;
  }
  return worst;
}

/// Angles [rad] where the law's pieces meet, including 0 (= 360°, the wrap).
std::vector<double> boundaries(const MotionLaw& law) {
  std::vector<double> b;
  for (const auto& piece : law.pieces()) b.push_back(piece.start);
  return b;
}

TEST(ProfilesLibrary, EveryProfileIsDocumentedLoadsAndIsAsSmoothAsDocumented) {
  int checked = 0;
  for (const auto& entry : fs::directory_iterator(kProfilesDir)) {
    if (entry.path().extension() != ".json") continue;
    const std::string name = entry.path().stem().string();
    SCOPED_TRACE(name);
    const auto doc = documented().find(name);
    ASSERT_NE(doc, documented().end()) << "add " << name << " to profiles/README.md and to the table above";
    const Documented& d = doc->second;
    EXPECT_TRUE(read_json(entry.path()).at("description").is_string()) << "each profile says what it is";
    const MotionLaw law = d.oscillating ? load_oscillating(entry.path()) : load_translating(entry.path());

    EXPECT_NEAR(law.lift(), d.lift, 1e-6 * d.lift);
    // Continuity of s, s', s'' (law_checks.h) at every piece boundary and the wrap.
    const std::vector<double> b = boundaries(law);
    if (d.continuity >= 2) {
      for (double theta : b) test::expect_c2_at(law, theta, name + " at " + std::to_string(theta * 180 / kPi) + "°");
    }
    if (d.continuity >= 3) {
      constexpr double delta = 1e-7;
      const double bound = 2 * delta * 2 * d4_bound(law);
      for (double theta : b)
        EXPECT_NEAR(law.eval(theta - delta).d3s, law.eval(theta + delta).d3s, bound) << "s''' at " << theta;
    }
    ++checked;
  }
  EXPECT_EQ(checked, static_cast<int>(documented().size())) << "a documented profile file is missing";
}

TEST(ProfilesLibrary, HarmonicRiseReturnIsC1WithTheTextbookAccelerationJumps) {
  const MotionLaw law = load_translating(kProfilesDir / "harmonic_rise_return.json");
  // s = h/2 (1 − cos(π x)), x = θ/β: s'' = ±π² h / (2 β²) at the segment ends, 0 in the dwells.
  const double h = 0.02, beta = 120 * kPi / 180, jump = kPi * kPi * h / (2 * beta * beta);
  constexpr double delta = 1e-9;
  for (double end_deg : {0.0, 120.0, 180.0, 300.0}) {
    const double th = end_deg * kPi / 180;
    const LawSample l = law.eval(th - delta), r = law.eval(th + delta);
    // s' = 0 at the ends: s moves by O(δ²) only; s' moves by δ·|s''| on the moving side.
    EXPECT_NEAR(l.s, r.s, test::kRoundoff * h);
    EXPECT_NEAR(l.ds, r.ds, 2 * delta * jump);
    EXPECT_NEAR(std::abs(r.d2s - l.d2s), jump, 1e-6 * jump) << "at " << end_deg << "°";
  }
}

TEST(ProfilesLibrary, HarmonicEccentricIsOneCosine) {
  const MotionLaw law = load_translating(kProfilesDir / "harmonic_eccentric.json");
  for (int i = 0; i < 100; ++i) {
    const double th = kTwoPi * (i + 0.5) / 100;
    const LawSample s = law.eval(th);
    EXPECT_NEAR(s.s, 0.01 * (1 - std::cos(th)), test::kRoundoff * test::kLengthScale);
    EXPECT_NEAR(s.ds, 0.01 * std::sin(th), test::kRoundoff * test::kLengthScale);
    EXPECT_NEAR(s.d2s, 0.01 * std::cos(th), test::kRoundoff);
    EXPECT_NEAR(s.d3s, -0.01 * std::sin(th), 10 * test::kRoundoff);  // a digit lost per derivative
  }
}

/// The valve-lift design of profiles/generate_valve_lift.py, independently.
double valve_design(double theta_deg) {
  const auto bell = [](double x) {
    if (std::abs(x) >= 1) return 0.0;
    const double x2 = x * x;
    return 1 - 1.75 * x2 + 5.25 * std::pow(x2, 5) - 7 * std::pow(x2, 6) + 2.5 * std::pow(x2, 7);
  };
  return 8.7e-3 * bell((theta_deg - 75) / 65) + 0.3e-3 * bell((theta_deg - 75) / 75);
}

TEST(ProfilesLibrary, ValveLiftFollowsItsPolynomialDesign) {
  const MotionLaw law = load_translating(kProfilesDir / "flat_tappet_valve_lift.json");
  double worst = 0, lowest = 0;
  for (int i = 0; i < 7200; ++i) {
    const double deg = 360.0 * i / 7200;
    const double s = law.eval(deg * kPi / 180).s;
    worst = std::max(worst, std::abs(s - valve_design(deg)));
    if (deg > 150 && deg < 360) lowest = std::min(lowest, s);
  }
  // A quintic spline every 2.5° through a C3 design: well below a micrometre
  // (the design's 4th derivative jumps at the lobe ends, where the error peaks).
  EXPECT_LT(worst, 1e-6);
  EXPECT_GT(lowest, -1e-7) << "the base circle stays a circle to 0.1 µm";
  // At the peak, a knot: the stored lift (12 decimals) and the spline's slope there.
  constexpr double kFit = 1e-9;  // [m], [m/rad]
  EXPECT_NEAR(law.eval(75 * kPi / 180).s, 9.0e-3, kFit);
  EXPECT_NEAR(law.eval(75 * kPi / 180).ds, 0.0, kFit);
  // The flat-tappet condition quoted in profiles/README.md: min(s + s'') = −16.6 mm.
  constexpr double kLastDigit = 1e-5;  // [m], the last digit of −0.01663
  double min_s_s2 = INFINITY;
  for (int i = 0; i < 36000; ++i) {
    const LawSample l = law.eval(kTwoPi * i / 36000);
    min_s_s2 = std::min(min_s_s2, l.s + l.d2s);
  }
  EXPECT_NEAR(min_s_s2, -0.01663, 2 * kLastDigit);
}

}  // namespace
}  // namespace camdyn
