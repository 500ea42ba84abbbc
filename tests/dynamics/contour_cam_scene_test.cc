// Contour cams in the simulator (issue 4, item 3) and the general profile-pair
// form (item 4): a cam given as points, checked against closed forms (the
// eccentric disc) and against the same cam synthesised from its law; the
// general two-parameter tracker against the one-parameter reductions on the
// same scenes.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <numbers>
#include <ostream>
#include <sstream>
#include <string>
#include <vector>

#include "common/constants.h"
#include "common/errors.h"
#include "contact/profile_pair_tracking.h"
#include "dynamics/rigid_jump_speed.h"
#include "dynamics/simulation.h"
#include "scenes.h"
#include "tolerance.h"

namespace camdyn {
namespace {

constexpr double kDiscRadius = 0.03, kEccentricity = 0.004;  // test::use_eccentric_disc_contour's

/// The cycloidal test scene with its cam replaced by the eccentric disc.
SceneConfig eccentric_scene(const std::string& kind, double rpm) {
  SceneConfig s = test::follower_scene(kind, rpm, ContactModel::lankarani_nikravesh);
  test::use_eccentric_disc_contour(s);
  return s;
}

/// The cam a scene synthesises from its law, as `n` contour points: the flat
/// face's cam is the synthesised curve itself, a circle follower's the pitch
/// curve moved inwards by the circle's radius.
std::vector<std::vector<double>> contour_points_of(const SceneConfig& scene, int n) {
  const Model model = build_model(scene, "test");
  const ClosedCurveProfile synthesised(*model.cam);
  const InwardOffsetProfile offset(synthesised, model.follower.radius);
  const PairProfile& contour = model.follower.circle() ? static_cast<const PairProfile&>(offset) : synthesised;
  std::vector<std::vector<double>> points;
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector2d r = contour.at(kTwoPi * i / n).r;
    points.push_back({r.x(), r.y()});
  }
  return points;
}

TEST(ContourCamScene, EccentricDiscLiftIsTheClosedForm) {
  // Flat face: s = ε(1 − cos θ); centred roller ρ: the centre height is
  // −ε cos θ + sqrt((R + ρ)² − ε² sin² θ).
  for (const char* kind : {"translating_flat", "translating_roller"}) {
    SCOPED_TRACE(kind);
    const Model model = build_model(eccentric_scene(kind, 100.0), "test");
    const bool flat = std::string(kind) == "translating_flat";
    // The lift through the fitted contour against the closed form (below).
    constexpr double kLiftFit = 1e-9;  // [m]
    const double rho = model.follower.radius, reach = kDiscRadius + rho;
    EXPECT_NEAR(model.follower.base_radius, kDiscRadius - kEccentricity, kLiftFit);
    double worst = 0.0, worst_d2 = 0.0;
    for (int i = 0; i < 360; ++i) {
      const double th = kTwoPi * (i + 0.3) / 360, c = std::cos(th), s = std::sin(th);
      const double e = kEccentricity;
      double y, d2y;
      if (flat) {
        y = e * (1 - c);
        d2y = e * c;
      } else {
        const double w = std::sqrt(reach * reach - e * e * s * s);
        y = -e * c + w - (reach - e);
        // y'' = e cos θ − e² cos 2θ / w − e⁴ sin² θ cos² θ / w³
        d2y = e * c - e * e * std::cos(2 * th) / w - std::pow(e, 4) * s * s * c * c / (w * w * w);
      }
      const LawSample l = model.law->eval(th);
      worst = std::max(worst, std::abs(l.s - y));
      worst_d2 = std::max(worst_d2, std::abs(l.d2s - d2y));
    }
    EXPECT_LT(worst, kLiftFit);
    EXPECT_LT(worst_d2, 1e-5 * kEccentricity);  // the quintic interpolation through 0.5° knots
    EXPECT_LT(model.law_interpolation_error, 1e-12);
    EXPECT_LT(model.contour->report().max_residual, 1e-10);
  }
}

TEST(ContourCamScene, EccentricDiscFlatFaceJumpSpeedIsTheClosedForm) {
  // s'' = ε cos θ; the spring holds hardest at θ = π: ω² = k (2ε + x₀) / (m ε).
  const SceneConfig scene = eccentric_scene("translating_flat", 100.0);
  const FollowerConfig& f = scene.mechanism.follower;
  const double x0 = f.spring.preload / f.spring.stiffness;
  const double omega = std::sqrt(f.spring.stiffness * (2 * kEccentricity + x0) / (f.mass * kEccentricity));
  // The fitted lift's s'' at θ = π, where the spring holds hardest, is good to ≲ 1e-6 relative.
  constexpr double kJumpFit = 1e-6;
  EXPECT_NEAR(jump_speed_rpm(build_model(scene, "test")) / (omega * 60 / kTwoPi), 1.0, kJumpFit);
  // And the simulation separates just above it, not just below.
  const double jump_rpm = omega * 60 / kTwoPi;
  EXPECT_EQ(simulate_scene(eccentric_scene("translating_flat", 0.98 * jump_rpm), "test").metrics.separation_fraction,
            0.0);
  EXPECT_GT(simulate_scene(eccentric_scene("translating_flat", 1.02 * jump_rpm), "test").metrics.separation_fraction,
            0.0);
}

class ContourOfSynthesisedCam : public ::testing::TestWithParam<std::string> {};

TEST_P(ContourOfSynthesisedCam, SimulatesLikeTheCamItWasTakenFrom) {
  // The cycloidal cam exported as 720 contour points and read back: its law,
  // jump speed and simulated contact force agree with the cam synthesised from
  // the law (to the fit's accuracy), and the contour-cam run follows its own
  // rigid model within the acceptance bounds.
  const SceneConfig original = test::follower_scene(GetParam(), 100.0, ContactModel::lankarani_nikravesh);
  SceneConfig contour = original;
  contour.mechanism.cam.base_radius = 0.0;
  contour.mechanism.cam.motion_law = {};
  contour.mechanism.cam.motion_law.contour = ContourConfig{};
  contour.mechanism.cam.motion_law.contour->points = contour_points_of(original, 720);

  const Model a = build_model(original, "test"), b = build_model(contour, "test");
  // 720 points fit the lift to 0.1 µm; the jump speed hangs on s'' at its
  // worst point, two derivatives of the fit: 2 %.
  constexpr double kContourFit = 1e-7, kContourJump = 0.02;  // [m], relative
  EXPECT_NEAR(b.follower.base_radius, a.follower.base_radius, kContourFit);
  double worst_s = 0.0;
  for (int i = 0; i < 720; ++i)
    worst_s = std::max(worst_s, std::abs(a.law->eval(kTwoPi * i / 720).s - b.law->eval(kTwoPi * i / 720).s));
  EXPECT_LT(worst_s, kContourFit);
  EXPECT_NEAR(jump_speed_rpm(b) / jump_speed_rpm(a), 1.0, kContourJump);

  const SimulationResult ra = simulate_scene(original, "test"), rb = simulate_scene(contour, "test");
  EXPECT_EQ(rb.metrics.separation_fraction, 0.0);
  EXPECT_NEAR(rb.metrics.peak_contact_force / ra.metrics.peak_contact_force, 1.0, test::kRigidForceAcceptance);
  EXPECT_NEAR(rb.metrics.min_contact_force / ra.metrics.min_contact_force, 1.0, test::kRigidForceAcceptance);
  double worst_force = 0.0;
  for (size_t i = 0; i < rb.series.time.size(); ++i) {
    if (rb.series.time[i] < rb.evaluated_from) continue;
    const double theta = rb.series.cam_angle_deg[i] * kTwoPi / 360.0;
    worst_force = std::max(worst_force, std::abs(rb.series.contact_force[i] / rigid_normal_force(b, theta) - 1.0));
  }
  EXPECT_LT(worst_force, test::kRigidForceAcceptance);
}

INSTANTIATE_TEST_SUITE_P(TranslatingFollowers, ContourOfSynthesisedCam,
                         ::testing::Values("translating_roller", "translating_flat", "translating_mushroom"),
                         [](const ::testing::TestParamInfo<std::string>& p) { return p.param; });

TEST(ContourCamScene, FlatFaceOnAConcaveContourIsRejectedBeforeSimulating) {
  // A disc with a dent: the flat face would bridge it.
  SceneConfig s = eccentric_scene("translating_flat", 100.0);
  auto& points = s.mechanism.cam.motion_law.contour->points;
  for (int i = 28; i <= 32; ++i) {
    const double a = kTwoPi * i / 120, depth = 0.002 * std::cos((i - 30) * std::numbers::pi / 10);
    points[i] = {(kDiscRadius - depth) * std::cos(a), -kEccentricity + (kDiscRadius - depth) * std::sin(a)};
  }
  try {
    build_model(s, "scene.json");
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("mechanism.cam.motion_law.contour"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("concave"), std::string::npos) << e.what();
  }
}

// ---------------------------------------------------------------- general pair form

struct PairFormCase {
  std::string kind, tracking;
};
void PrintTo(const PairFormCase& c, std::ostream* os) { *os << c.kind << " / " << c.tracking; }

class GeneralPairForm : public ::testing::TestWithParam<PairFormCase> {};

TEST_P(GeneralPairForm, SameMetricsAsTheReductionWithinIntegrationTolerance) {
  // Just below the jump speed (large forces, near-separation): the general
  // tracker and the reduction solve the same contact, so the metrics agree to
  // the integration tolerance (rtol 1e-9, errors accumulated over 3 turns).
  const PairFormCase& c = GetParam();
  SceneConfig reduced = test::follower_scene(c.kind, 1000.0, ContactModel::lankarani_nikravesh);
  reduced.mechanism.cam.rpm = 0.95 * jump_speed_rpm(build_model(reduced, "test"));
  reduced.mechanism.contact.tracking = parse_enum<Tracking>(c.tracking);
  reduced.integrator.flight = FlightMethod::integrated;  // as the general form's flights are: like for like
  SceneConfig general = reduced;
  general.mechanism.contact.pair_form = PairFormChoice::general;
  const Model model = build_model(general, "test");
  ASSERT_EQ(model.pair_form, PairForm::general);
  EXPECT_FALSE(model.exact_jacobian());
  const SimulationResult a = simulate_scene(reduced, "test"), b = simulate_scene(general, "test");
  EXPECT_EQ(b.solver.tracking_resets, 0);
  // Forces compared on the scale of the peak force. The extreme-value metrics
  // are sampled at each run's own integrator steps (the general form's steps
  // differ: its Jacobian is a difference quotient), so a sharp minimum is
  // resolved slightly differently; the time series at common output angles
  // is the tighter comparison.
  const double scale = a.metrics.peak_contact_force;
  const double rtol = reduced.integrator.rtol;
  // The peak, as the minimum, is sampled at each run's own steps: the same
  // factor as the penetration (the peak force is K times its 1.5th power).
  EXPECT_NEAR(b.metrics.peak_contact_force, scale, test::integrator_tolerance(rtol, 1e4) * scale);
  EXPECT_NEAR(b.metrics.min_contact_force, a.metrics.min_contact_force, test::integrator_tolerance(rtol, 2e4) * scale);
  EXPECT_NEAR(b.metrics.max_penetration, a.metrics.max_penetration,
              test::integrator_tolerance(rtol, 1e4) * a.metrics.max_penetration);
  EXPECT_EQ(b.metrics.separation_fraction, a.metrics.separation_fraction);
  ASSERT_EQ(a.series.time.size(), b.series.time.size());
  double worst = 0.0;
  for (size_t i = 0; i < a.series.time.size(); ++i)
    worst = std::max(worst, std::abs(a.series.contact_force[i] - b.series.contact_force[i]));
  std::ostringstream measured;
  measured << std::setprecision(3) << worst / scale;
  ::testing::Test::RecordProperty("worst_force_difference_over_peak", measured.str());
  EXPECT_LT(worst / scale, 1e-5);
}

INSTANTIATE_TEST_SUITE_P(
    Followers, GeneralPairForm,
    ::testing::Values(PairFormCase{"translating_roller", "differential"}, PairFormCase{"translating_roller", "newton"},
                      PairFormCase{"translating_flat", "differential"}, PairFormCase{"translating_mushroom", "newton"},
                      PairFormCase{"oscillating_roller", "differential"}, PairFormCase{"oscillating_flat", "newton"}),
    [](const ::testing::TestParamInfo<PairFormCase>& p) { return p.param.kind + "_" + p.param.tracking; });

TEST(GeneralPairForm, OnAContourCamToo) {
  SceneConfig reduced = eccentric_scene("translating_roller", 1500.0);
  SceneConfig general = reduced;
  general.mechanism.contact.pair_form = PairFormChoice::general;
  const SimulationResult a = simulate_scene(reduced, "test"), b = simulate_scene(general, "test");
  const double rtol = reduced.integrator.rtol;
  EXPECT_NEAR(b.metrics.peak_contact_force / a.metrics.peak_contact_force, 1.0, test::integrator_tolerance(rtol, 1e3));
  EXPECT_NEAR(b.metrics.min_contact_force / a.metrics.min_contact_force, 1.0, test::integrator_tolerance(rtol, 1e4));
}

TEST(GeneralPairForm, FollowsAConcaveFlankLikeTheReduction) {
  // A dent (concave radius about 20 mm) in the eccentric disc under a 10 mm
  // roller: accepted, reported as concave, and tracked through by both forms.
  SceneConfig reduced = eccentric_scene("translating_roller", 300.0);
  auto& points = reduced.mechanism.cam.motion_law.contour->points;
  for (int i = 24; i <= 36; ++i) {
    const double a = kTwoPi * i / 120, r = kDiscRadius - 0.0015 * (1 + std::cos((i - 30) * std::numbers::pi / 6)) / 2;
    points[i] = {r * std::cos(a), -kEccentricity + r * std::sin(a)};
  }
  const Model model = build_model(reduced, "test");
  ASSERT_EQ(model.contour->report().concave.size(), 1u);
  EXPECT_GT(model.contour->report().concave[0].min_abs_radius, model.follower.radius);
  SceneConfig general = reduced;
  general.mechanism.contact.pair_form = PairFormChoice::general;
  const SimulationResult a = simulate_scene(reduced, "test"), b = simulate_scene(general, "test");
  EXPECT_EQ(a.metrics.separation_fraction, 0.0);
  EXPECT_EQ(b.solver.tracking_resets, 0);
  const double rtol = reduced.integrator.rtol;
  EXPECT_NEAR(b.metrics.peak_contact_force / a.metrics.peak_contact_force, 1.0, test::integrator_tolerance(rtol, 1e3));
  EXPECT_NEAR(b.metrics.min_contact_force, a.metrics.min_contact_force,
              test::integrator_tolerance(rtol, 2e4) * a.metrics.peak_contact_force);
}

TEST(GeneralPairForm, AddsTheFollowerParameterStateOnlyWithDifferentialTracking) {
  SceneConfig s = test::follower_scene("translating_roller", 500.0);
  s.mechanism.contact.pair_form = PairFormChoice::general;
  const Model differential = build_model(s, "test");
  EXPECT_EQ(differential.layout.names, (std::vector<std::string>{"follower_position", "follower_velocity",
                                                                 "contact_parameter_u", "contact_parameter_v"}));
  s.mechanism.contact.tracking = Tracking::newton;
  EXPECT_EQ(build_model(s, "test").layout.size, 2);
}

}  // namespace
}  // namespace camdyn
