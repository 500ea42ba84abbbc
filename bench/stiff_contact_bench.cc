// A stiff undamped contact held at a tight tolerance (issue 38, item 5): the
// quickstart mechanism (studies/quickstart.json) at 100 rpm on a Hertz
// contact (K = 1e10 N/m^1.5, no damping law) with its follower damper taken
// out, rtol 1e-10, atol 1e-12, two revolutions in steady contact. The
// contact's own vibration (about 1.6 kHz, undamped: nothing dissipates it)
// is what the integrator resolves. Reports the steps, error-test failures,
// Jacobian evaluations, right-hand sides and Newton iterations per step, the
// CPU time per step and the contact force's extremes, with the compiled
// SUNDIALS kernels (arg 1, the default) and with SUNDIALS' own (arg 0): the
// same run to the bit, so the counters and forces agree and only the time
// differs (docs/performance.md). BM_StiffUndampedContactAdams: the same with
// integrator.method "cvode_adams"; BM_StiffUndampedContactErk/q: "arkode_erk"
// with integrator.order q; BM_StiffUndampedContactDop853: "dop853".
//
//   build/ci/bench/stiff_contact_bench --benchmark_out=bench/results/stiff_contact.json --benchmark_out_format=json
#include <benchmark/benchmark.h>
#include <time.h>

#include <algorithm>
#include <string>

#include "dynamics/model.h"
#include "dynamics/simulation.h"
#include "integrate/sundials_compiled_ops.h"
#include "io/config.h"
#include "scene/scene.h"

namespace {

camdyn::SceneConfig stiff_undamped_contact() {
  camdyn::SceneConfig s = camdyn::load_scene(std::string(CAMDYN_SOURCE_DIR) + "/studies/quickstart.json");
  s.mechanism.cam.rpm = 100.0;
  s.mechanism.contact.model = camdyn::ContactModel::hertz;
  s.mechanism.follower.damping = 0.0;
  s.integrator.rtol = 1e-10;
  s.integrator.atol = 1e-12;
  s.simulation.cycles = 2.0;
  s.simulation.discard_cycles = 0;
  return s;
}

/// Process CPU time [s] (the 2 shared cores make wall time a measure of the load).
double cpu_seconds() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

/// Runs `scene` for the benchmark and reports the solver's counters, the CPU
/// time per step and the contact force's extremes.
void run_and_report(benchmark::State& state, const camdyn::SceneConfig& scene, const char* label) {
  const camdyn::Model model = camdyn::build_model(scene, "stiff undamped contact");
  camdyn::Workspace ws = camdyn::make_workspace(model);
  camdyn::SimulationOptions options;
  options.record_series = false;
  // (Not benchmark::DoNotOptimize on a result read afterwards: Google
  // Benchmark 1.7's "+m,r" constraint lets GCC 12 clobber a double.)
  camdyn::SimulationResult r;
  double seconds = 0.0;  // CPU time of the runs [s]
  for (auto _ : state) {
    const double start = cpu_seconds();
    r = camdyn::simulate(scene, model, ws, options);
    seconds += cpu_seconds() - start;
    camdyn::throw_if_failed(r);
  }
  const camdyn::SolverCounters& c = r.solver.counters;
  const auto steps = static_cast<double>(std::max(1L, c.steps));
  state.SetLabel(label);
  state.counters["steps"] = steps;
  state.counters["error_test_failures"] = static_cast<double>(c.error_test_failures);
  state.counters["jacobian_evaluations"] = static_cast<double>(c.jacobian_evaluations);
  state.counters["rhs_per_step"] = static_cast<double>(c.rhs_evaluations) / steps;
  state.counters["newton_per_step"] = static_cast<double>(c.nonlinear_iterations) / steps;
  state.counters["s_per_step"] = seconds / static_cast<double>(state.iterations()) / steps;
  state.counters["peak_contact_force_N"] = r.metrics.peak_contact_force;
  state.counters["min_contact_force_N"] = r.metrics.min_contact_force;
}

void BM_StiffUndampedContact(benchmark::State& state) {
  const bool compiled = state.range(0) == 1;
  camdyn::set_compiled_kernels_enabled(compiled);
  run_and_report(state, stiff_undamped_contact(), compiled ? "compiled kernels" : "SUNDIALS' own kernels");
  camdyn::set_compiled_kernels_enabled(true);
}
BENCHMARK(BM_StiffUndampedContact)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->MinTime(2.0);

/// The same scene with CVODE's Adams method (integrator.method "cvode_adams",
/// compiled kernels): an undamped contact vibration that the step must
/// resolve anyway is not stiff, and Adams follows it with fewer steps and
/// less numerical dissipation than BDF (docs/performance.md).
void BM_StiffUndampedContactAdams(benchmark::State& state) {
  camdyn::SceneConfig scene = stiff_undamped_contact();
  scene.integrator.method = camdyn::IntegrationMethod::cvode_adams;
  run_and_report(state, scene, "cvode_adams, compiled kernels");
}
BENCHMARK(BM_StiffUndampedContactAdams)->Unit(benchmark::kMillisecond)->MinTime(2.0);

/// The same scene with ARKODE's explicit Runge–Kutta pair of order
/// state.range(0) (integrator.method "arkode_erk", integrator.order; compiled
/// kernels): the step is set by accuracy alone, where a high order takes
/// long steps (docs/performance.md).
void BM_StiffUndampedContactErk(benchmark::State& state) {
  camdyn::SceneConfig scene = stiff_undamped_contact();
  scene.integrator.method = camdyn::IntegrationMethod::arkode_erk;
  scene.integrator.order = static_cast<int>(state.range(0));
  const std::string label = "arkode_erk order " + std::to_string(state.range(0)) + ", compiled kernels";
  run_and_report(state, scene, label.c_str());
}
BENCHMARK(BM_StiffUndampedContactErk)->Arg(4)->Arg(5)->Arg(6)->Arg(8)->Unit(benchmark::kMillisecond)->MinTime(2.0);

/// The same scene with camdyn's own Dormand–Prince pair of order 8
/// (integrator.method "dop853"): the order-8 step with no vector library
/// between the stages (docs/performance.md).
void BM_StiffUndampedContactDop853(benchmark::State& state) {
  camdyn::SceneConfig scene = stiff_undamped_contact();
  scene.integrator.method = camdyn::IntegrationMethod::dop853;
  run_and_report(state, scene, "dop853");
}
BENCHMARK(BM_StiffUndampedContactDop853)->Unit(benchmark::kMillisecond)->MinTime(2.0);

}  // namespace

BENCHMARK_MAIN();
