// The closed-form flight (dynamics/free_flight.h, issue 15): the solution of
// M q̈ + c q̇ + k q = −(F₀ + M g) against independent closed forms in every
// damping regime, and the hybrid simulation against the integrated flight on
// a follower thrown metres off a large cam.
#include "dynamics/free_flight.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "dynamics/simulation.h"
#include "io/config.h"
#include "scenes.h"

namespace camdyn {
namespace {

const std::string kLongFlight = std::string(CAMDYN_SOURCE_DIR) + "/studies/peers/long_flight.json";

// A model whose flight has the given mass, damper, spring, preload and gravity.
Model flight_model(double m, double c, double k, double preload, double g) {
  SceneConfig s = test::cycloidal_cam_scene(600.0);
  s.mechanism.follower.mass = m;
  s.mechanism.follower.damping = c;
  s.mechanism.follower.spring.stiffness = k;
  s.mechanism.follower.spring.preload = preload;
  s.gravity = g;
  return build_model(s, "flight");
}

// Closed forms written out case by case, independently of FreeFlight's uniform one.
struct Case {
  const char* name;
  double m, c, k, preload, g;
};

void expected(const Case& cs, double q0, double v0, double t, double& q, double& v) {
  const double load = (cs.preload + cs.m * cs.g) / cs.m;
  if (cs.k == 0.0 && cs.c == 0.0) {
    q = q0 + v0 * t - 0.5 * load * t * t;
    v = v0 - load * t;
    return;
  }
  if (cs.k == 0.0) {  // v' = −λ v − load: v → −load/λ
    const double lambda = cs.c / cs.m, v_inf = -load / lambda;
    v = v_inf + (v0 - v_inf) * std::exp(-lambda * t);
    q = q0 + v_inf * t + (v0 - v_inf) * (1.0 - std::exp(-lambda * t)) / lambda;
    return;
  }
  const double q_eq = -(cs.preload + cs.m * cs.g) / cs.k, x0 = q0 - q_eq;
  const double a = cs.c / (2.0 * cs.m), w2 = cs.k / cs.m;
  if (a * a < w2) {
    const double wd = std::sqrt(w2 - a * a), e = std::exp(-a * t);
    const double A = x0, B = (v0 + a * x0) / wd;
    q = q_eq + e * (A * std::cos(wd * t) + B * std::sin(wd * t));
    v = e * (-a * (A * std::cos(wd * t) + B * std::sin(wd * t)) + wd * (-A * std::sin(wd * t) + B * std::cos(wd * t)));
  } else if (a * a == w2) {
    const double e = std::exp(-a * t), B = v0 + a * x0;
    q = q_eq + (x0 + B * t) * e;
    v = (B - a * (x0 + B * t)) * e;
  } else {
    const double r1 = -a + std::sqrt(a * a - w2), r2 = -a - std::sqrt(a * a - w2);
    const double C1 = (v0 - r2 * x0) / (r1 - r2), C2 = x0 - C1;
    q = q_eq + C1 * std::exp(r1 * t) + C2 * std::exp(r2 * t);
    v = C1 * r1 * std::exp(r1 * t) + C2 * r2 * std::exp(r2 * t);
  }
}

TEST(FreeFlightTest, MatchesTheClosedFormsOfEveryDampingRegime) {
  const std::vector<Case> cases = {
      {"undamped spring", 1.221, 0.0, 1430.8, 143.08, 0.0},
      {"underdamped", 0.3, 20.0, 5000.0, 40.0, 9.81},
      {"critically damped", 0.5, 2.0 * std::sqrt(0.5 * 2000.0), 2000.0, 10.0, 0.0},
      {"overdamped", 0.2, 400.0, 1000.0, 5.0, 0.0},
      {"free fall", 0.1, 0.0, 0.0, 0.0, 9.81},
      {"free fall with a damper", 0.1, 0.05, 0.0, 1.0, 9.81},
  };
  const double q0 = 0.013, v0 = 2.7, t0 = 0.35;
  for (const Case& cs : cases) {
    SCOPED_TRACE(cs.name);
    FreeFlight flight(flight_model(cs.m, cs.c, cs.k, cs.preload, cs.g));
    flight.start(t0, q0, v0);
    for (double tau : {1e-9, 1e-6, 1e-3, 0.02, 0.1, 0.5}) {
      double q = 0.0, v = 0.0, q_ref = 0.0, v_ref = 0.0;
      flight.at(t0 + tau, q, v);
      expected(cs, q0, v0, tau, q_ref, v_ref);
      // Both are exact: they differ by rounding, amplified at most by the
      // cancellations of the reference's exponentials.
      const double scale_q = std::abs(q0) + std::abs(v0) * tau + std::abs(q_ref),
                   scale_v = std::abs(v0) + std::abs(v_ref);
      EXPECT_NEAR(q, q_ref, 1e-12 * scale_q) << "tau " << tau;
      EXPECT_NEAR(v, v_ref, 1e-12 * scale_v) << "tau " << tau;
      // The speed bound holds over the interval.
      double q_half = 0.0, v_half = 0.0;
      flight.at(t0 + 0.5 * tau, q_half, v_half);
      EXPECT_LE(std::abs(v), flight.speed_bound(q_half, v_half, 0.5 * tau) * (1.0 + 1e-12));
    }
  }
}

struct Landing {
  double time, angle_deg, speed;
};

struct FlightRun {
  std::vector<Landing> impacts;
  SimulationResult result;
};

FlightRun run_long_flight(const std::string& tracking, const std::string& flight, int cycles) {
  const SceneConfig scene = load_scene(
      kLongFlight, {"mechanism.contact.tracking=\"" + tracking + "\"", "integrator.flight=\"" + flight + "\"",
                    "simulation.cycles=" + std::to_string(cycles), "simulation.discard_cycles=0"});
  FlightRun run;
  run.result = simulate_scene(scene, kLongFlight);
  EXPECT_TRUE(run.result.solver.converged()) << run.result.solver.message;
  for (const ContactEvent& e : run.result.events)
    if (e.onset && e.impact) run.impacts.push_back({e.time, e.cam_angle_deg, e.speed});
  return run;
}

// A follower thrown up to 3 m off a 0.4 m cam lands once per revolution: the
// same impacts whether the pair is tracked by its ODE or by Newton, and
// whether the flight is integrated or in closed form.
TEST(FreeFlightTest, LongFlightsLandTheSameInEveryTrackingAndFlightMode) {
  constexpr int kCycles = 8;
  const FlightRun reference = run_long_flight("differential", "integrated", kCycles);
  ASSERT_GE(reference.impacts.size(), 8u);
  for (const auto& [tracking, flight] : std::vector<std::pair<std::string, std::string>>{
           {"differential", "closed_form"}, {"newton", "closed_form"}, {"newton", "integrated"}}) {
    SCOPED_TRACE(tracking + " / " + flight);
    const FlightRun run = run_long_flight(tracking, flight, kCycles);
    ASSERT_EQ(run.impacts.size(), reference.impacts.size());
    // rtol 1e-8, amplified about 100x by the slow third impact (bench/peers/README.md):
    // 1e-4 deg and 1e-5 in speed leave a margin of ten over that.
    for (std::size_t i = 0; i < run.impacts.size(); ++i) {
      EXPECT_NEAR(run.impacts[i].angle_deg, reference.impacts[i].angle_deg, 1e-4 * 10) << "impact " << i;
      EXPECT_NEAR(run.impacts[i].speed / reference.impacts[i].speed, 1.0, 1e-5 * 10) << "impact " << i;
    }
    EXPECT_NEAR(run.result.metrics.max_separation_gap / reference.result.metrics.max_separation_gap, 1.0, 1e-4);
    if (flight == "closed_form") {
      // Every flight lands, but the one the run ends in.
      EXPECT_EQ(run.result.solver.flights, static_cast<long>(run.impacts.size()) + 1);
      // At most two restarts and projections per impact: the landing, and at most one in contact.
      EXPECT_LE(run.result.solver.counters.reinitialisations + run.result.solver.projections,
                2 * static_cast<long>(run.impacts.size()));
    }
  }
}

// The energy balance closes across closed-form flights (damper work in
// flight by quadrature on the closed form): the quickstart, whose follower
// separates and lands on every revolution with a 20 N s/m damper.
TEST(FreeFlightTest, EnergyBalanceClosesAcrossClosedFormFlights) {
  const std::string quickstart = std::string(CAMDYN_SOURCE_DIR) + "/studies/quickstart.json";
  const SceneConfig closed = load_scene(quickstart, {"integrator.flight=\"closed_form\""});
  const SceneConfig integrated = load_scene(quickstart, {"integrator.flight=\"integrated\""});
  const SimulationResult a = simulate_scene(closed, quickstart), b = simulate_scene(integrated, quickstart);
  ASSERT_GT(a.solver.flights, 0);
  EXPECT_EQ(b.solver.flights, 0);
  EXPECT_EQ(a.metrics.impact_count, b.metrics.impact_count);
  // The residual is the integrator's business: both within 100 rtol.
  EXPECT_LT(a.metrics.energy_residual, 100 * closed.integrator.rtol);
  EXPECT_NEAR(a.metrics.separation_integral / b.metrics.separation_integral, 1.0, 1e-5);
  EXPECT_NEAR(a.metrics.max_impact_velocity / b.metrics.max_impact_velocity, 1.0, 1e-5);
  EXPECT_NEAR(a.metrics.separation_fraction, b.metrics.separation_fraction, 1e-5);
}

}  // namespace
}  // namespace camdyn
