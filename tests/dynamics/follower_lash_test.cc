// `mechanism.follower.lash` and a spring's `lumps` apart from its `coils`
// (docs/config.md, "follower.lash" and "Springs with mass"; docs/model.md §12).
// follower.lash is placed on the elements a lash was written with before it,
// so a scene written with it runs as the seat- or link-based scene it stands
// for; a seat or link lash given with it that disagrees is warned about. A
// spring's clash clearance is its coils', whatever its lumps: the static
// compression at which its coils first touch is the closed form (coils + 1)
// gap for 4, 8 or 16 lumps, and its first surge mode is the lumped chain's
// closed form, converging on the continuous spring's ½ √(k/m_s).
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

#include "dynamics/model.h"
#include "dynamics/plausibility.h"
#include "dynamics/simulation.h"
#include "input_error_of.h"
#include "io/config.h"
#include "scenes.h"
#include "study_paths.h"

namespace camdyn {
namespace {

using test::input_error_of;

/// A committed valve-train study, shortened to two revolutions (one evaluated).
SceneConfig valvetrain_study(const std::string& name) {
  SceneConfig s = load_scene(kStudies + "valvetrain/" + name + ".json");
  s.simulation.cycles = 2;
  s.simulation.discard_cycles = 1;
  return s;
}

/// The runs agree to the integrator's tolerance: every metric within
/// 10 rtol of its size (plus 10 atol for the lengths). Placing the lash on
/// the same elements makes them equal to the bit; this is what the contract asks.
void expect_same_lash_run(const SceneConfig& a, const SceneConfig& b) {
  const Model ma = build_model(a, "a"), mb = build_model(b, "b");
  EXPECT_EQ(ma.elements, mb.elements);
  const SimulationResult ra = simulate_scene(a, "a"), rb = simulate_scene(b, "b");
  ASSERT_EQ(ra.solver.termination, Termination::converged) << ra.solver.message;
  ASSERT_EQ(rb.solver.termination, Termination::converged) << rb.solver.message;
  const double rtol = a.integrator.rtol, atol = a.integrator.atol;
  const auto near = [&](double x, double y, const char* what) {
    EXPECT_NEAR(x, y, 10.0 * rtol * std::max(std::abs(x), std::abs(y)) + 10.0 * atol) << what;
  };
  const Metrics& x = ra.metrics;
  const Metrics& y = rb.metrics;
  near(x.peak_contact_force, y.peak_contact_force, "peak_contact_force");
  near(x.min_contact_force, y.min_contact_force, "min_contact_force");
  near(x.separation_fraction, y.separation_fraction, "separation_fraction");
  near(x.max_separation_gap, y.max_separation_gap, "max_separation_gap");
  near(x.max_impact_velocity, y.max_impact_velocity, "max_impact_velocity");
  EXPECT_EQ(x.impact_count, y.impact_count);
  ASSERT_TRUE(x.train && y.train);
  near(x.train->max_seating_velocity, y.train->max_seating_velocity, "max_seating_velocity");
  near(x.train->peak_spring_force, y.train->peak_spring_force, "peak_spring_force");
  EXPECT_EQ(x.train->seat_impacts, y.train->seat_impacts);
  ASSERT_EQ(x.train->max_lift_error.size(), y.train->max_lift_error.size());
  for (std::size_t i = 0; i < x.train->max_lift_error.size(); ++i)
    near(x.train->max_lift_error[i], y.train->max_lift_error[i], "max_lift_error");
}

int count_warnings(const std::vector<PlausibilityWarning>& warnings, const std::string& cause) {
  return static_cast<int>(
      std::count_if(warnings.begin(), warnings.end(), [&](const PlausibilityWarning& w) { return w.cause == cause; }));
}

std::vector<PlausibilityWarning> lash_test_warnings(const SceneConfig& scene) {
  return input_warnings(scene, build_model(scene, "test"));
}

// ---------------------------------------------------------------- follower.lash

TEST(FollowerLash, WithoutATrainSeatItIsTheFollowersSeatAtTheLash) {
  const SceneConfig seat_based =
      valvetrain_study("bucket_tappet");  // hunt_crossley seat, 1e9 N/m, n 1, e 0.3 at 0.2 mm
  ASSERT_TRUE(seat_based.mechanism.follower.seat);
  EXPECT_EQ(seat_based.mechanism.follower.seat->position, 0.0002);

  SceneConfig lash_only = seat_based;  // the default stiff seat
  lash_only.mechanism.follower.seat.reset();
  lash_only.mechanism.follower.lash = 0.0002;
  expect_same_lash_run(seat_based, lash_only);

  SceneConfig seat_law = seat_based;  // the seat block's law, at the lash
  seat_law.mechanism.follower.seat->position = 0.0;
  seat_law.mechanism.follower.lash = 0.0002;
  const Model model = build_model(seat_law, "test");
  const TrainElement& seat = model.train.elements[static_cast<std::size_t>(model.train.bodies[0].seat)];
  EXPECT_EQ(seat.offset, 0.0002);
  EXPECT_EQ(seat.contact.model, ContactModel::hunt_crossley);
  EXPECT_EQ(count_warnings(lash_test_warnings(lash_only), "lash_mismatch"), 0);
  EXPECT_EQ(count_warnings(lash_test_warnings(seat_law), "lash_mismatch"), 0);
}

TEST(FollowerLash, WithATrainItIsTheLashOfTheLinkIntoTheFirstSeatedBody) {
  // pushrod_rocker: the valve (train[1]) is the first seated body, behind a
  // 1.0 pushrod and a 1.5 rocker; 0.2 mm at the cam is 0.3 mm at the valve.
  // The same double as the assembly's r₁ r₂ λ (0.0003 + 1 ulp): a train that
  // takes its lash up with an impact moves its peaks by 1e-6 for 1 ulp of lash.
  SceneConfig link_based = valvetrain_study("pushrod_rocker");
  link_based.mechanism.train[1].link.lash = 1.0 * 1.5 * 0.0002;
  SceneConfig lash_based = valvetrain_study("pushrod_rocker");
  lash_based.mechanism.follower.lash = 0.0002;
  const Model model = build_model(lash_based, "test");
  EXPECT_DOUBLE_EQ(model.train.bodies[2].lash, 0.0003);
  EXPECT_EQ(model.train.bodies[1].lash, 0.0);
  EXPECT_LT(model.train.bodies[0].seat, 0);  // the follower stays on the cam
  const TrainLash lash = train_lash(model.train);
  EXPECT_EQ(lash.body, 2);
  EXPECT_NEAR(lash.at_cam, 0.0002, 1e-15);
  EXPECT_EQ(lash.held_open, 0.0);
  expect_same_lash_run(link_based, lash_based);
  EXPECT_EQ(count_warnings(lash_test_warnings(lash_based), "lash_mismatch"), 0);
  EXPECT_EQ(count_warnings(lash_test_warnings(link_based), "lash_mismatch"), 0);  // no follower.lash: nothing to check
}

TEST(FollowerLash, ASeatAndLinkLashThatDisagreeAreWarnedNotRefused) {
  // A bucket on a valve: a frame seat for the bucket 0.2 mm up and a link
  // lash of 0.1 mm hold the valve 0.1 mm off its seat.
  SceneConfig s = valvetrain_study("pushrod_rocker");
  s.mechanism.train.erase(s.mechanism.train.begin());
  s.mechanism.train[0].link.ratio = 1.0;
  s.mechanism.train[0].link.lash = 0.0001;
  s.mechanism.follower.seat = test::hunt_crossley_seat(0.0002, 1e9);
  s.mechanism.follower.lash = 0.0002;
  std::vector<PlausibilityWarning> w = lash_test_warnings(s);
  ASSERT_EQ(count_warnings(w, "lash_mismatch"), 1);
  const auto it = std::find_if(w.begin(), w.end(), [](const auto& x) { return x.cause == "lash_mismatch"; });
  EXPECT_EQ(it->field, "mechanism.follower.lash");
  EXPECT_NE(it->message.find("0.0001 m off its seat"), std::string::npos) << it->message;
  const TrainLash lash = train_lash(build_model(s, "test").train);
  EXPECT_NEAR(lash.at_cam, 0.0002, 1e-15);
  EXPECT_NEAR(lash.held_open, 0.0001, 1e-15);

  s.mechanism.follower.lash = 0.0003;  // the "sum" of the two: still a valve held open
  EXPECT_EQ(count_warnings(lash_test_warnings(s), "lash_mismatch"), 1);

  s.mechanism.follower.seat->position = 0.0;  // now the link alone: 0.1 mm, not 0.3 mm
  w = lash_test_warnings(s);
  ASSERT_EQ(count_warnings(w, "lash_mismatch"), 1);
  const auto link_alone = std::find_if(w.begin(), w.end(), [](const auto& x) { return x.cause == "lash_mismatch"; });
  EXPECT_NE(link_alone->message.find("cam travel 0.0001 m"), std::string::npos) << link_alone->message;

  s.mechanism.follower.lash = 0.0001;  // agreeing
  EXPECT_EQ(count_warnings(lash_test_warnings(s), "lash_mismatch"), 0);

  SceneConfig bucket = valvetrain_study("bucket_tappet");  // its seat at 0.2 mm against follower.lash 0.1 mm
  bucket.mechanism.follower.lash = 0.0001;
  EXPECT_EQ(count_warnings(lash_test_warnings(bucket), "lash_mismatch"), 1);
  EXPECT_EQ(build_model(bucket, "test").train.elements[0].offset, 0.0002);  // the seat as given
}

TEST(FollowerLash, PlacementsThatCannotBeMadeNameTheLash) {
  SceneConfig two_sided = valvetrain_study("pushrod_rocker");
  two_sided.mechanism.train[1].link.one_sided = false;
  two_sided.mechanism.follower.lash = 0.0002;
  InputError e = input_error_of([&] { build_model(two_sided, "f.json"); });
  EXPECT_EQ(e.path(), "mechanism.follower.lash");
  EXPECT_NE(e.reason().find("two-sided"), std::string::npos) << e.reason();

  SceneConfig stopped = valvetrain_study("bucket_tappet");
  stopped.mechanism.follower.seat.reset();
  stopped.mechanism.follower.stop = test::hunt_crossley_seat(0.0001, 1e9);
  stopped.mechanism.follower.lash = 0.0002;
  e = input_error_of([&] { build_model(stopped, "f.json"); });
  EXPECT_EQ(e.path(), "mechanism.follower.lash");
  EXPECT_NE(e.reason().find("below its stop"), std::string::npos) << e.reason();

  SceneConfig arm = test::follower_scene("oscillating_roller", 1000.0);
  arm.mechanism.follower.lash = 0.001;  // [rad]: no seat law for the arm angle
  e = input_error_of([&] { build_model(arm, "f.json"); });
  EXPECT_EQ(e.path(), "mechanism.follower.lash");
  EXPECT_NE(e.reason().find("'seat' block"), std::string::npos) << e.reason();
}

// ---------------------------------------------------------------- coils and lumps

constexpr double kCoilRate = 35000.0, kCoilMass = 0.045;  // k [N/m], m_s [kg]
constexpr int kActiveCoils = 6;
constexpr double kCoilGap = 4e-4;  // [m] per coil segment: the coils close (kActiveCoils + 1) kCoilGap = 2.8 mm

/// The cycloidal test cam's follower with a spring with mass of kActiveCoils
/// coils, lumped in `lumps` masses (none: one a coil, as before `lumps`).
SceneConfig coil_scene(std::optional<int> lumps) {
  SceneConfig s = test::cycloidal_cam_scene(1000.0, ContactModel::hunt_crossley);
  SpringConfig& spring = s.mechanism.follower.spring;
  spring.stiffness = kCoilRate;
  spring.preload = 250.0;
  spring.mass = kCoilMass;
  spring.coils = kActiveCoils;
  spring.lumps = lumps;
  spring.clash = CoilClashConfig{kCoilGap, 1e8};
  return s;
}

/// The largest compression beyond its gap of any clash element [m] with the
/// follower held at `x` [m] and the lumps in static equilibrium.
double clash_engagement(const Model& model, double x) {
  TrainWorkspace ws;
  prepare_train_workspace(model.train, ws);
  std::vector<double> y(static_cast<std::size_t>(model.layout.size), 0.0);
  y[0] = x;
  EXPECT_TRUE(train_static_state(model.train, ws, model.theta(0.0), y.data()));
  double largest = -std::numeric_limits<double>::infinity();
  for (const TrainElement& e : model.train.elements) {
    if (e.role != TrainRole::clash) continue;
    double d = e.offset + e.ca * y[static_cast<std::size_t>(e.position_a)];
    if (e.b >= 0) d += e.cb * y[static_cast<std::size_t>(e.position_b)];
    largest = std::max(largest, d);
  }
  return largest;
}

TEST(SpringLumps, TheCoilsCloseAtTheSameCompressionWhateverTheLumps) {
  // Static: N lumps on N + 1 equal segments share a compression X equally,
  // X / (N + 1) each, against a gap (coils + 1) gap / (N + 1) each: the first
  // clash engages at X = (coils + 1) gap, with every segment at once.
  const double closed = (kActiveCoils + 1) * kCoilGap;  // [m]
  for (int lumps : {4, 8, 16}) {
    SCOPED_TRACE(lumps);
    const Model model = build_model(coil_scene(lumps), "test");
    const int segments = lumps + 1;
    for (const double fraction : {0.5, 1.0 - 1e-6}) {
      const double below = clash_engagement(model, fraction * closed);
      EXPECT_LT(below, 0.0);
      EXPECT_NEAR(below, (fraction - 1.0) * closed / segments, 1e-10 * closed);
    }
    EXPECT_GT(clash_engagement(model, (1.0 + 1e-6) * closed), 0.0);
  }
  // Without `lumps` (one a coil) each segment's gap is `gap` itself, to the bit.
  const Model as_before = build_model(coil_scene(std::nullopt), "test");
  int clashes = 0;
  for (const TrainElement& e : as_before.train.elements)
    if (e.role == TrainRole::clash) {
      EXPECT_EQ(e.offset, -kCoilGap);
      ++clashes;
    }
  EXPECT_EQ(clashes, kActiveCoils + 1);
}

/// The first natural frequency [rad/s] of the assembled spring chain with
/// both its ends held (the follower and the frame): the lumps' masses and
/// the segments' stiffnesses as the train assembled them.
double first_surge_mode(const Model& model) {
  const int n = static_cast<int>(model.train.coordinates.size()) - 1;  // the lumps
  Eigen::MatrixXd K = Eigen::MatrixXd::Zero(n, n), M = Eigen::MatrixXd::Zero(n, n);
  for (int c = 0; c < n; ++c) M(c, c) = model.train.coordinates[static_cast<std::size_t>(c) + 1].mass;
  for (const TrainElement& e : model.train.elements) {
    if (e.law != TrainElement::Law::spring) continue;
    const int ends[2] = {e.a, e.b};
    const double coefficients[2] = {e.ca, e.cb};
    for (int p = 0; p < 2; ++p)
      for (int q = 0; q < 2; ++q)
        if (ends[p] >= 1 && ends[q] >= 1)
          K(ends[p] - 1, ends[q] - 1) += coefficients[p] * coefficients[q] * e.stiffness;
  }
  Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> solver(K, M);
  return std::sqrt(solver.eigenvalues().minCoeff());
}

TEST(SpringLumps, TheSurgeModeConvergesOnTheContinuousSpringsAsTheLumpsGrow) {
  const double continuous = std::numbers::pi * std::sqrt(kCoilRate / kCoilMass);  // f₁ = ½ √(k/m_s) [rad/s]
  double previous_error = 1.0;
  for (int lumps : {4, 8, 16, 32}) {
    SCOPED_TRACE(lumps);
    const Model model = build_model(coil_scene(lumps), "test");
    ASSERT_EQ(static_cast<int>(model.train.coordinates.size()), lumps + 1);
    const double k_s = (lumps + 1) * kCoilRate;
    const double closed = 2.0 * std::sqrt(k_s * lumps / kCoilMass) * std::sin(std::numbers::pi / (2.0 * (lumps + 1)));
    const double omega = first_surge_mode(model);
    EXPECT_NEAR(omega, closed, 1e-9 * closed);
    const double error = 1.0 - omega / continuous;  // ≈ 1/(2N), from below
    EXPECT_GT(error, 0.0);
    EXPECT_LT(error, 0.6 / lumps);
    EXPECT_LT(error, previous_error);
    previous_error = error;
  }
}

TEST(SpringLumps, TheElementNamesAndTheCoilWarningCountTheLumps) {
  const Model lumped = build_model(coil_scene(16), "test");
  EXPECT_NE(std::find(lumped.elements.begin(), lumped.elements.end(), "spring:follower:6_coils:16_lumps"),
            lumped.elements.end());
  const Model as_before = build_model(coil_scene(std::nullopt), "test");
  EXPECT_NE(std::find(as_before.elements.begin(), as_before.elements.end(), "spring:follower:6_coils"),
            as_before.elements.end());
  // 6 coils in 2 lumps resolve the surge poorly: the warning names `lumps`.
  const std::vector<PlausibilityWarning> w = lash_test_warnings(coil_scene(2));
  ASSERT_EQ(count_warnings(w, "spring_coils"), 1);
  const auto it = std::find_if(w.begin(), w.end(), [](const auto& x) { return x.cause == "spring_coils"; });
  EXPECT_EQ(it->field, "mechanism.follower.spring.lumps");
  EXPECT_EQ(count_warnings(lash_test_warnings(coil_scene(4)), "spring_coils"), 0);
}

}  // namespace
}  // namespace camdyn
