// The design loop of issue 38 (docs/performance.md "The design loop"): the
// optimise studies a designer iterates with, each run whole on two threads,
// with the wall time, the process's CPU time over it (on a shared machine the
// wall time counts the other jobs too; the CPU time is this run's own work)
// and the search's evaluations. Targets: each under 10 s of wall time on two
// free cores.
//
// Each again with optimizer.warm_start (…Warm): the loop's runs start where
// the start's previous evaluation ended (docs/optimize.md "Warm starts");
// `warm_kept` counts the runs whose warm window was kept, `objective` the
// answer's on the steady state (its verification), to compare with the cold run's.
//
//   * ValveLobe200: studies/optimize_valve_lobe.json with 200 search
//     evaluations (the shipped study stops after 1);
//   * DwellCamForce: studies/optimize_force.json as shipped (a dwell cam's
//     rise and return as splines, 250 evaluations over 900–1200 rpm);
//   * DwellCamJump: studies/optimize_jump.json as shipped (100 evaluations).
//
//   build/ci/bench/design_loop_bench --benchmark_out=bench/results/design_loop.json --benchmark_out_format=json
#include <benchmark/benchmark.h>
#include <sys/resource.h>

#include <string>

#include "io/config.h"
#include "optim/optimize/optimize.h"

namespace {

using namespace camdyn;
using namespace camdyn::optim;

/// User plus system CPU time of this process so far [s].
double process_cpu_s() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  auto seconds = [](const timeval& t) { return static_cast<double>(t.tv_sec) + 1e-6 * static_cast<double>(t.tv_usec); };
  return seconds(u.ru_utime) + seconds(u.ru_stime);
}

OptimizeStudy study_at(const std::string& name, int max_evaluations, bool warm) {
  const std::string file = std::string(CAMDYN_SOURCE_DIR) + "/studies/" + name;
  OptimizeStudy study = read_optimize_study(load_config_json(file), config_source(file));
  if (max_evaluations > 0) study.config.optimizer.max_evaluations = max_evaluations;
  study.config.optimizer.warm_start = warm;
  return study;
}

void run_study(benchmark::State& state, const std::string& name, int max_evaluations, bool warm = false) {
  const OptimizeStudy study = study_at(name, max_evaluations, warm);
  const std::string file = std::string(CAMDYN_SOURCE_DIR) + "/studies/" + name;
  OptimizeOptions options;
  options.threads = 2;
  OptimizeOutcome o;
  double cpu_s = 0.0;
  for (auto _ : state) {
    const double cpu0 = process_cpu_s();
    o = run_optimize(study.baseline, study.config, file, options);
    cpu_s = process_cpu_s() - cpu0;
    benchmark::DoNotOptimize(o.optimized.objective);
  }
  state.counters["run_time_s"] = o.run_time_s;
  state.counters["cpu_s"] = cpu_s;
  state.counters["evaluations"] = static_cast<double>(o.search.evaluations);
  state.counters["loop_simulations"] = static_cast<double>(o.loop_simulations);
  state.counters["evaluations_per_s"] =
      o.loop_time_s > 0.0 ? static_cast<double>(o.search.evaluations) / o.loop_time_s : 0.0;
  state.counters["feasible"] = o.optimized.feasible ? 1.0 : 0.0;
  state.counters["objective"] = o.selection.chosen().verified.objective;
  state.counters["warm_kept"] = static_cast<double>(o.warm_kept);
  state.counters["warm_rejected"] = static_cast<double>(o.warm_rejected);
  state.counters["under_10_s"] = o.run_time_s < 10.0 ? 1.0 : 0.0;
}

void BM_ValveLobe200(benchmark::State& state) { run_study(state, "optimize_valve_lobe.json", 200); }
BENCHMARK(BM_ValveLobe200)->Iterations(1)->Unit(benchmark::kSecond)->UseRealTime();

void BM_DwellCamForce(benchmark::State& state) { run_study(state, "optimize_force.json", 0); }
BENCHMARK(BM_DwellCamForce)->Iterations(1)->Unit(benchmark::kSecond)->UseRealTime();

void BM_DwellCamJump(benchmark::State& state) { run_study(state, "optimize_jump.json", 0); }
BENCHMARK(BM_DwellCamJump)->Iterations(1)->Unit(benchmark::kSecond)->UseRealTime();

void BM_ValveLobe200Warm(benchmark::State& state) { run_study(state, "optimize_valve_lobe.json", 200, true); }
BENCHMARK(BM_ValveLobe200Warm)->Iterations(1)->Unit(benchmark::kSecond)->UseRealTime();

void BM_DwellCamForceWarm(benchmark::State& state) { run_study(state, "optimize_force.json", 0, true); }
BENCHMARK(BM_DwellCamForceWarm)->Iterations(1)->Unit(benchmark::kSecond)->UseRealTime();

void BM_DwellCamJumpWarm(benchmark::State& state) { run_study(state, "optimize_jump.json", 0, true); }
BENCHMARK(BM_DwellCamJumpWarm)->Iterations(1)->Unit(benchmark::kSecond)->UseRealTime();

}  // namespace
BENCHMARK_MAIN();
