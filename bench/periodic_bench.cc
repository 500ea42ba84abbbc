// Time to the steady state (issue 16): the periodic study's shooting against
// a plain run long enough to settle,
//
// * on the quickstart above its jump speed (1300 rpm, the follower leaves
//   the cam and lands once per revolution) with its damper: it settles
//   within two revolutions (the follower is back at rest on the dwell
//   before the section comes round, so the map contracts almost to a
//   point), and no search can beat that. (With a damper of 5 N s/m the
//   same speed is chaotic, λ ≈ +3 per revolution: there is nothing to
//   settle on, and the periodic study says so.)
// * on a slowly settling impact oscillator: the bouncing ball
//   (studies/periodic/bouncing_ball.json) at restitution 0.95 and 540 rpm,
//   whose stable period-1 orbit has Floquet multipliers of modulus 0.95
//   (det = e*²), so a plain run closes the distance to the orbit by only 5 %
//   a revolution.
//
// The Jacobian of the map (issue 38): forward sensitivities (one CVODES run
// with the saltation matrices, dynamics/map_sensitivity.h) against central
// differences (2n map runs) on the bouncing ball (2 states), the quickstart
// cam (3: its roller leaves the cam and hammers back) and the bucket tappet
// with its 8-coil valve spring (18), each at a section point two revolutions
// from its start, one thread. Counters: the map's states, and in the
// sensitivity benchmark the time ratio finite differences / sensitivities.
//
// "Settled" is measured, not guessed: the plain run goes on one revolution
// at a time from the scene's start until its state at the section is within
// the shooting's tolerance of the orbit's fixed point (each coordinate
// relative to its scale). The counters are the revolutions each needs and
// their ratio (goal: the plain run integrates ≥ 5× more), beside the times.
//
//   build/release/bench/periodic_bench --benchmark_out=bench/results/periodic.json --benchmark_out_format=json
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <string>
#include <vector>

#include "dynamics/map_sensitivity.h"
#include "dynamics/poincare_map.h"
#include "io/config.h"
#include "study/periodic_orbit.h"
#include "study/periodic_study.h"

namespace {

using namespace camdyn;

const std::string kQuickstart = std::string(CAMDYN_SOURCE_DIR) + "/studies/quickstart.json";
const std::string kBouncingBall = std::string(CAMDYN_SOURCE_DIR) + "/studies/periodic/bouncing_ball.json";

// The scene of a simulate config, or of a periodic study's config.
SceneConfig scene_of(const std::string& config, const std::vector<std::string>& sets, bool periodic) {
  if (!periodic) return load_scene(config, sets);
  StudyContext ctx;
  ctx.config_file = config;
  ctx.source = config_source(config);
  return read_periodic_study(load_config_json(config, sets), ctx).scene;
}

struct Case {
  Case(const std::string& config, const std::vector<std::string>& sets, bool periodic = false)
      : scene(scene_of(config, sets, periodic)), model(build_model(scene, config)), map(scene, model, config) {}
  SceneConfig scene;
  Model model;
  PoincareMap map;
};

// The quickstart with a damper of `damping` [N s/m] (its own: 20).
Case& quickstart(long damping) {
  static std::map<long, Case> cases;
  return cases
      .try_emplace(
          damping, kQuickstart,
          std::vector<std::string>{"integrator.rtol=1e-10", "mechanism.follower.damping=" + std::to_string(damping)})
      .first->second;
}

// The bouncing ball at restitution 0.95 and 540 rpm, started in flight near
// its period-1 orbit (the closed form's section point is 0.0211 m, -0.014 m/s).
Case& bouncing_ball() {
  static Case c(kBouncingBall,
                {"mechanism.contact.restitution=0.95", "mechanism.cam.rpm=540",
                 "mechanism.follower.initial.position=0.0225", "mechanism.follower.initial.velocity=0"},
                /*periodic=*/true);
  return c;
}

void shooting(benchmark::State& state, Case& c) {
  PeriodicOptions options;
  options.threads = 1;
  long revolutions = 0;
  for (auto _ : state) {
    const PeriodicAnalysis a = analyse_steady_state(c.map, options);
    if (!a.orbit) state.SkipWithError("no orbit");
    revolutions = a.revolutions;
  }
  state.counters["revolutions"] = static_cast<double>(revolutions);
}

void BM_ShootingToThePeriodicOrbit(benchmark::State& state) { shooting(state, quickstart(state.range(0))); }
BENCHMARK(BM_ShootingToThePeriodicOrbit)->Arg(20)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_ShootingBouncingBall(benchmark::State& state) { shooting(state, bouncing_ball()); }
BENCHMARK(BM_ShootingBouncingBall)->Unit(benchmark::kMillisecond)->UseRealTime();

// Revolutions of a plain run from the scene's start until its section state
// is within `tolerance` (scaled) of the fixed point; 0 if not within `limit`.
long revolutions_to_settle(Case& c, const SectionPoint& fixed, double tolerance, long limit) {
  Workspace ws = make_workspace(c.model);
  SimulationOptions options;
  options.record_series = false;
  options.step_metrics = false;
  options.quadratures = false;  // as the map's own runs
  const SimulationResult first = simulate(c.map.scene_for(1), c.model, ws, options);
  SectionPoint p = c.map.point(first);
  for (long n = 1; n <= limit; ++n) {
    double distance = 0.0;
    for (std::size_t j = 0; j < p.x.size(); ++j)
      distance = std::max(distance, std::abs(p.x[j] - fixed.x[j]) / c.map.scales()[j]);
    if (distance <= tolerance) return n;
    p = c.map.apply(p, 1, ws).end;
  }
  return 0;
}

void plain_run(benchmark::State& state, Case& c) {
  PeriodicOptions options;
  const PeriodicAnalysis a = analyse_steady_state(c.map, options);
  if (!a.orbit) {
    state.SkipWithError("no orbit");
    return;
  }
  long revolutions = 0;
  for (auto _ : state) revolutions = revolutions_to_settle(c, a.orbit->fixed_point, options.tolerance, 2000);
  state.counters["revolutions"] = static_cast<double>(revolutions);
  state.counters["shooting_revolutions"] = static_cast<double>(a.revolutions);
  state.counters["revolutions_ratio"] =
      a.revolutions > 0 ? static_cast<double>(revolutions) / static_cast<double>(a.revolutions) : 0.0;
}

void BM_PlainRunUntilSettled(benchmark::State& state) { plain_run(state, quickstart(state.range(0))); }
BENCHMARK(BM_PlainRunUntilSettled)->Arg(20)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(1);

void BM_PlainRunUntilSettledBouncingBall(benchmark::State& state) { plain_run(state, bouncing_ball()); }
BENCHMARK(BM_PlainRunUntilSettledBouncingBall)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(1);

const std::string kBucketTappet = std::string(CAMDYN_SOURCE_DIR) + "/studies/valvetrain/bucket_tappet.json";

// The Jacobian cases: 0 the bouncing ball, 1 the quickstart, 2 the 8-coil bucket tappet.
Case& jacobian_case(long which) {
  static Case quick(kQuickstart, {"integrator.rtol=1e-10"});
  static Case tappet(kBucketTappet, {});
  return which == 0 ? bouncing_ball() : which == 1 ? quick : tappet;
}

SectionPoint two_revolutions_in(Case& c) {
  Workspace ws = make_workspace(c.model);
  SimulationOptions options;
  options.record_series = false;
  return c.map.point(simulate(c.map.scene_for(2), c.model, ws, options));
}

// The shooting's central differences, on one thread: 2n map runs.
bool finite_difference_jacobian(Case& c, const SectionPoint& p, Workspace& ws) {
  const double h = 10.0 * std::sqrt(c.scene.integrator.rtol);
  bool ok = true;
  for (int j = 0; j < c.map.dimension(); ++j)
    for (const double side : {h, -h}) {
      SectionPoint q = p;
      q.x[static_cast<std::size_t>(j)] += side * c.map.scales()[static_cast<std::size_t>(j)];
      ok = c.map.apply(q, 1, ws).ok && ok;
    }
  return ok;
}

void BM_MapJacobianSensitivity(benchmark::State& state) {
  Case& c = jacobian_case(state.range(0));
  const SectionPoint p = two_revolutions_in(c);
  Workspace ws = make_workspace(c.model);
  using Clock = std::chrono::steady_clock;
  const Clock::time_point start = Clock::now();
  long runs = 0;
  for (auto _ : state) {
    const MapJacobian r = sensitivity_jacobian(c.map, p, 1, ws);
    if (!r.ok) state.SkipWithError(r.reason.c_str());
    ++runs;
  }
  const double sensitivity_s = std::chrono::duration<double>(Clock::now() - start).count() / static_cast<double>(runs);
  const Clock::time_point fd_start = Clock::now();
  if (!finite_difference_jacobian(c, p, ws)) state.SkipWithError("a map run failed");
  const double fd_s = std::chrono::duration<double>(Clock::now() - fd_start).count();
  state.counters["states"] = c.map.dimension();
  state.counters["fd_over_sensitivity"] = fd_s / sensitivity_s;
}
BENCHMARK(BM_MapJacobianSensitivity)->DenseRange(0, 2)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_MapJacobianFiniteDifference(benchmark::State& state) {
  Case& c = jacobian_case(state.range(0));
  const SectionPoint p = two_revolutions_in(c);
  Workspace ws = make_workspace(c.model);
  for (auto _ : state)
    if (!finite_difference_jacobian(c, p, ws)) state.SkipWithError("a map run failed");
  state.counters["states"] = c.map.dimension();
}
BENCHMARK(BM_MapJacobianFiniteDifference)->DenseRange(0, 2)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
