// Time to the steady state (issue 16): the periodic study's shooting against
// a plain run long enough to settle, on the quickstart above its jump speed
// (1300 rpm, the follower leaves the cam and lands once per revolution), with
// its damper and without.
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
#include <cmath>
#include <map>
#include <string>

#include "dynamics/poincare_map.h"
#include "io/config.h"
#include "study/periodic_orbit.h"

namespace {

using namespace camdyn;

const std::string kQuickstart = std::string(CAMDYN_SOURCE_DIR) + "/studies/quickstart.json";

// The quickstart with its damper (argument 1) or without (0): the damper
// (damping ratio 0.26) settles it within a few revolutions; without it only
// the contact's hysteresis takes energy out, and a plain run takes long.
struct Case {
  explicit Case(bool damper)
      : scene(load_scene(kQuickstart, {"integrator.rtol=1e-10",
                                       damper ? "mechanism.follower.damping=20" : "mechanism.follower.damping=0"})),
        model(build_model(scene, kQuickstart)),
        map(scene, model, kQuickstart) {}
  SceneConfig scene;
  Model model;
  PoincareMap map;
};

Case& quickstart(long damping) {
  static std::map<long, Case> cases;
  return cases.try_emplace(damping, damping).first->second;
}

void BM_ShootingToThePeriodicOrbit(benchmark::State& state) {
  Case& c = quickstart(state.range(0));
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
BENCHMARK(BM_ShootingToThePeriodicOrbit)->Arg(20)->Arg(5)->Unit(benchmark::kMillisecond)->UseRealTime();

// Revolutions of a plain run from the scene's start until its section state
// is within `tolerance` (scaled) of the fixed point; 0 if not within `limit`.
long revolutions_to_settle(Case& c, const SectionPoint& fixed, double tolerance, long limit) {
  Workspace ws = make_workspace(c.model);
  SimulationOptions options;
  options.record_series = false;
  options.step_metrics = false;
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

void BM_PlainRunUntilSettled(benchmark::State& state) {
  Case& c = quickstart(state.range(0));
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
BENCHMARK(BM_PlainRunUntilSettled)->Arg(20)->Arg(5)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(1);

}  // namespace

BENCHMARK_MAIN();
