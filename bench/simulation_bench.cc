// Simulation cost on the quickstart scene: wall time per cam cycle, steps and
// RHS evaluations per cycle, and the time of one right-hand-side evaluation
// (which must not allocate: checked by counting operator new calls).
//
//   build/release/bench/simulation_bench --benchmark_out=bench/results.json --benchmark_out_format=json
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "allocation_counter.h"
#include "dynamics/model.h"
#include "dynamics/simulation.h"
#include "io/config.h"

namespace {

camdyn::SceneConfig quickstart() {
  return camdyn::load_scene(std::string(CAMDYN_SOURCE_DIR) + "/studies/quickstart.json");
}

// Max |y − y_ref| over the evaluated cycles against a run at rtol 1e-12 [m].
double position_error(const camdyn::SceneConfig& scene, const camdyn::SimulationResult& run) {
  camdyn::SceneConfig tight = scene;
  tight.integrator.rtol = 1e-12;
  tight.integrator.atol = 1e-16;
  camdyn::throw_if_failed(run);
  const camdyn::SimulationResult ref = camdyn::simulate_scene(tight, "quickstart");
  camdyn::throw_if_failed(ref);
  double worst = 0.0;
  for (size_t i = 0; i < run.series.time.size() && i < ref.series.time.size(); ++i)
    if (run.series.time[i] >= run.evaluated_from)
      worst = std::max(worst, std::abs(run.series.follower_position[i] - ref.series.follower_position[i]));
  return worst;
}

// The two tracking modes of docs/model.md §2 on the quickstart scene: run time
// per cycle and error against a tight reference, at the default tolerance.
void BM_QuickstartCycle(benchmark::State& state) {
  camdyn::SceneConfig scene = quickstart();
  scene.mechanism.contact.tracking = state.range(0) == 0 ? camdyn::Tracking::differential : camdyn::Tracking::newton;
  const camdyn::Model model = camdyn::build_model(scene, "quickstart");
  camdyn::Workspace ws;
  const double error = position_error(scene, camdyn::simulate(scene, model, ws));
  camdyn::SimulationOptions options;
  options.record_series = false;
  const double cycles = scene.simulation.cycles.value_or(4.0);
  long steps = 0, rhs = 0;
  for (auto _ : state) {
    const camdyn::SimulationResult r = camdyn::simulate(scene, model, ws, options);
    camdyn::throw_if_failed(r);
    steps = r.solver.counters.steps;
    rhs = r.solver.counters.rhs_evaluations;
    benchmark::DoNotOptimize(r.metrics.peak_contact_force);
  }
  state.SetLabel(camdyn::to_string(scene.mechanism.contact.tracking));
  state.counters["cycles"] = cycles;
  state.counters["s_per_cycle"] =
      benchmark::Counter(cycles, benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
  state.counters["steps_per_cycle"] = static_cast<double>(steps) / cycles;
  state.counters["rhs_per_cycle"] = static_cast<double>(rhs) / cycles;
  state.counters["error_position_m"] = error;
}
BENCHMARK(BM_QuickstartCycle)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

// The step-cost scene of issue 15: the quickstart mechanism at 100 rpm, in
// steady contact on a Hertz contact, rtol 1e-10; one revolution. Arg 0 folds
// the metrics and the energy balance in at every step (as every run does),
// arg 1 only integrates (SimulationOptions::step_metrics off), arg 2 also
// leaves out the quadratures and with them the midpoint evaluation (the same
// steps).
// The goal is ≤ 2 µs a step with the metrics.
void BM_SteadyContactStep(benchmark::State& state) {
  camdyn::SceneConfig scene = quickstart();
  scene.mechanism.cam.rpm = 100.0;
  scene.mechanism.contact.model = camdyn::ContactModel::hertz;
  scene.integrator.rtol = 1e-10;
  scene.simulation.cycles = 1.0;
  scene.simulation.discard_cycles = 0;
  const camdyn::Model model = camdyn::build_model(scene, "steady contact");
  camdyn::Workspace ws;
  camdyn::SimulationOptions options;
  options.record_series = false;
  options.step_metrics = state.range(0) == 0;
  options.quadratures = state.range(0) != 2;
  long steps = 0, rhs = 0, impacts = 0;
  for (auto _ : state) {
    const camdyn::SimulationResult r = camdyn::simulate(scene, model, ws, options);
    camdyn::throw_if_failed(r);
    steps = r.solver.counters.steps;
    rhs = r.solver.counters.rhs_evaluations;
    impacts = r.metrics.impact_count;
    benchmark::DoNotOptimize(r.metrics.peak_contact_force);
  }
  static constexpr const char* kLabels[] = {"with step metrics", "integration only", "integration without quadratures"};
  state.SetLabel(kLabels[state.range(0)]);
  state.counters["steps"] = static_cast<double>(steps);
  state.counters["rhs_per_step"] = static_cast<double>(rhs) / static_cast<double>(std::max(1L, steps));
  state.counters["impacts"] = static_cast<double>(impacts);
  state.counters["s_per_step"] = benchmark::Counter(
      static_cast<double>(steps), benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}
BENCHMARK(BM_SteadyContactStep)->Arg(0)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond);

void BM_RightHandSide(benchmark::State& state) {
  camdyn::SceneConfig scene = quickstart();
  scene.mechanism.contact.tracking = state.range(0) == 0 ? camdyn::Tracking::differential : camdyn::Tracking::newton;
  const camdyn::Model model = camdyn::build_model(scene, "quickstart");
  camdyn::Workspace ws;
  camdyn::Evaluation ev;
  double y[4] = {0.01, 0.5, 1.0, 0.0}, y_dot[4];
  ws.u_warm = 1.0;
  double t = 1.0 / (scene.mechanism.cam.rpm / 60.0) * (1.0 / (2.0 * 3.141592653589793));
  // Allocation check outside the timed loop (the benchmark loop itself may allocate).
  const long before = camdyn::test::allocation_count();
  for (int i = 0; i < 1000; ++i) {
    camdyn::evaluate(model, ws, t, y, ev);
    camdyn::state_derivative(model, ev, y_dot);
  }
  const long allocations = camdyn::test::allocation_count() - before;
  for (auto _ : state) {
    camdyn::evaluate(model, ws, t, y, ev);
    camdyn::state_derivative(model, ev, y_dot);
    benchmark::DoNotOptimize(y_dot[1]);
  }
  state.SetLabel(camdyn::to_string(scene.mechanism.contact.tracking));
  state.counters["allocations_per_1000_rhs"] = static_cast<double>(allocations);
  if (allocations != 0) state.SkipWithError("the right-hand side allocated memory");
}
BENCHMARK(BM_RightHandSide)->Arg(0)->Arg(1);

// The long-flight benchmark of issue 15 (studies/peers/long_flight.json: a
// follower thrown up to 3 m off a 0.4 m cam from a 3,600-row lift table,
// landing once per revolution on a stiff Hunt–Crossley contact; 200
// revolutions at 700 rpm, rtol 1e-8), with the time series recorded as the
// CLI does, its flights in closed form (0) or integrated (1). The goal: 200
// revolutions in ≤ 0.6 s, at least ten times faster than Siconos' Moreau–Jean
// at dt 1e-5 (bench/peers/), with at most two restarts and projections per
// impact. The steady orbit's landing angle and speed are reported.
void BM_LongFlight(benchmark::State& state) {
  const std::string file = std::string(CAMDYN_SOURCE_DIR) + "/studies/peers/long_flight.json";
  camdyn::SceneConfig scene = camdyn::load_scene(file);
  scene.integrator.flight = state.range(0) == 0 ? camdyn::FlightMethod::closed_form : camdyn::FlightMethod::integrated;
  const camdyn::Model model = camdyn::build_model(scene, file);
  camdyn::Workspace ws;
  camdyn::SimulationResult r;
  for (auto _ : state) {
    r = camdyn::simulate(scene, model, ws);
    camdyn::throw_if_failed(r);
    benchmark::DoNotOptimize(r.metrics.peak_contact_force);
  }
  const camdyn::ContactEvent* last = nullptr;
  for (const camdyn::ContactEvent& e : r.events)
    if (e.onset && e.impact) last = &e;
  state.SetLabel(camdyn::to_string(scene.integrator.flight));
  state.counters["revolutions"] = scene.simulation.cycles.value_or(0.0);
  state.counters["impacts"] = static_cast<double>(r.metrics.impact_count);
  state.counters["steps"] = static_cast<double>(r.solver.counters.steps);
  state.counters["restarts_and_projections_per_impact"] =
      static_cast<double>(r.solver.counters.reinitialisations + r.solver.projections) /
      std::max(1.0, static_cast<double>(r.events.size()) / 2.0);
  state.counters["landing_angle_deg"] = last ? std::fmod(last->cam_angle_deg, 360.0) : 0.0;
  state.counters["landing_speed_m_s"] = last ? last->speed : 0.0;
  state.counters["max_gap_m"] = r.metrics.max_separation_gap;
}
BENCHMARK(BM_LongFlight)->Arg(0)->Unit(benchmark::kMillisecond)->MinTime(2.0);
BENCHMARK(BM_LongFlight)->Arg(1)->Unit(benchmark::kMillisecond)->Iterations(1);

}  // namespace

// Counting allocator: the RHS benchmark fails if the right-hand side allocates.

BENCHMARK_MAIN();
