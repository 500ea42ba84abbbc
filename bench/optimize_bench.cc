// Cost of the design optimisation on studies/optimize_jump.json: one design
// evaluation of the search loop (three simulations, one per operating speed,
// on 1 or 2 threads), the kinematics-and-geometry part alone, and the whole
// study (wall time; target under 60 s on two cores).
//
//   build/release/bench/optimize_bench --benchmark_out=bench/results/optimize.json --benchmark_out_format=json
#include <benchmark/benchmark.h>

#include <algorithm>
#include <string>

#include "io/config.h"
#include "optim/optimize/design.h"
#include "optim/optimize/objectives.h"
#include "optim/optimize/optimize.h"
#include "optim/optimize/rigid_design.h"
#include "optim/simulation_pool.h"

namespace {

using namespace camdyn;
using namespace camdyn::optim;

const std::string kStudy = std::string(CAMDYN_SOURCE_DIR) + "/studies/optimize_jump.json";

OptimizeStudy jump_study() { return read_optimize_study(load_config_json(kStudy), config_source(kStudy)); }

/// One evaluation of the search loop at the baseline's spline fit.
void BM_LoopEvaluation(benchmark::State& state) {
  const OptimizeStudy study = jump_study();
  const DesignSpace space(study.baseline, study.config.design, kStudy);
  SimulationPool pool(static_cast<int>(state.range(0)), kStudy);
  const DesignEvaluator evaluator(study.config, kStudy, pool);
  const SceneConfig scene = space.scene(space.initial());
  const EvaluationSettings settings = loop_settings(study.config.optimizer);
  const double speeds = static_cast<double>(study.config.operating_rpm.size());
  for (auto _ : state) {
    const DesignEvaluation e = evaluator.evaluate(scene, settings, true);
    benchmark::DoNotOptimize(e.objective);
  }
  state.SetLabel(std::to_string(state.range(0)) + " thread(s)");
  state.counters["evaluations_per_s"] = benchmark::Counter(1.0, benchmark::Counter::kIsIterationInvariantRate);
  state.counters["simulations_per_s"] = benchmark::Counter(speeds, benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(BM_LoopEvaluation)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

/// The part of an evaluation that needs no simulation: law, kinematics, cam check.
void BM_KinematicsAndGeometry(benchmark::State& state) {
  const OptimizeStudy study = jump_study();
  const DesignSpace space(study.baseline, study.config.design, kStudy);
  SimulationPool pool(1, kStudy);
  const DesignEvaluator evaluator(study.config, kStudy, pool);
  const SceneConfig scene = space.scene(space.initial());
  for (auto _ : state) {
    const DesignEvaluation e = evaluator.evaluate(scene, {}, false);
    benchmark::DoNotOptimize(e.kinematics.peak_acceleration);
  }
}
BENCHMARK(BM_KinematicsAndGeometry)->Unit(benchmark::kMillisecond);

/// The rigid-model stage alone (target under 0.1 s): the certificate's
/// bisections over CLP solves and the design programme.
void BM_RigidStage(benchmark::State& state) {
  const OptimizeStudy study = jump_study();
  const DesignSpace space(study.baseline, study.config.design, kStudy);
  RigidStageResult r;
  for (auto _ : state) {
    r = run_rigid_stage(study.baseline, study.config, space, kStudy);
    // (an int: Benchmark 1.7.1's "+m,r" constraint can zero a double it is given, as GCC 12 compiles it)
    benchmark::DoNotOptimize(r.lp_solves);
  }
  state.counters["lp_solves"] = r.lp_solves;
  state.counters["any_law_rpm"] = r.certificate.any_law_rpm;
  state.counters["family_rpm"] = r.certificate.family_rpm;
  state.counters["design_rpm"] = r.design.jump_free_rpm;
}
BENCHMARK(BM_RigidStage)->Unit(benchmark::kMillisecond)->UseRealTime();

/// The whole study as shipped, on two threads.
void BM_OptimizeJumpStudy(benchmark::State& state) {
  const OptimizeStudy study = jump_study();
  OptimizeOptions options;
  options.threads = 2;
  OptimizeOutcome o;
  for (auto _ : state) {
    o = run_optimize(study.baseline, study.config, kStudy, options);
    benchmark::DoNotOptimize(o.optimized.objective);
  }
  auto worst_peak = [](const DesignEvaluation& e) {
    double peak = 0.0;
    for (const SpeedResult& s : e.speeds) peak = std::max(peak, s.result.metrics.peak_contact_force);
    return peak;
  };
  state.counters["run_time_s"] = o.run_time_s;
  state.counters["evaluations"] = static_cast<double>(o.search.evaluations);
  state.counters["evaluations_per_s"] = static_cast<double>(o.search.evaluations) / o.loop_time_s;
  state.counters["simulations_per_s"] = static_cast<double>(o.loop_simulations) / o.loop_time_s;
  state.counters["peak_force_baseline_N"] = worst_peak(o.baseline);
  state.counters["peak_force_optimized_N"] = worst_peak(o.optimized);
  state.counters["feasible"] = o.optimized.feasible ? 1.0 : 0.0;
}
BENCHMARK(BM_OptimizeJumpStudy)->Iterations(1)->Unit(benchmark::kSecond)->UseRealTime();

}  // namespace
BENCHMARK_MAIN();
