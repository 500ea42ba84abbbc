// Cost of contact identification on studies/identify_cam_rig (two records,
// contact stiffness and follower damping): one residual evaluation (both
// experiments simulated and the residuals assembled) by the old route (the
// scene's JSON with the values read again and the model built, FitScene's
// from_json) and with the values set in place on the model; the
// parameter-setting part alone both ways; one experiment's simulation with
// the metrics followed over every step (what simulate does for a report) and
// with the samples alone (what identification asks for); and the whole study
// on one thread.
// Counters: heap allocations per evaluation (the counting operator new).
//
//   build/release/bench/identify_bench --benchmark_out=bench/results/identify.json --benchmark_out_format=json
#include <benchmark/benchmark.h>

#include <memory>
#include <string>
#include <vector>

#include "allocation_counter.h"
#include "dynamics/model.h"
#include "dynamics/simulation.h"
#include "io/config.h"
#include "optim/identify/fit_residuals.h"
#include "optim/identify/fit_scene.h"
#include "optim/identify/identify.h"

namespace {

using namespace camdyn;
using namespace camdyn::optim;

const std::string kStudy = std::string(CAMDYN_SOURCE_DIR) + "/studies/identify_cam_rig/identify_cam_rig.json";

IdentifyProblem cam_rig() { return load_identify_problem(load_config_json(kStudy), config_source(kStudy)); }

/// Near the optimum the study finds (stiffness [N/m^1.5], damping [N s/m]).
const std::vector<double> kValues{6e9, 20.0};

/// One FitScene per experiment; `from_json`: the old route (JSON → scene → model).
std::vector<std::unique_ptr<FitScene>> fit_scenes(const IdentifyProblem& problem, bool from_json) {
  std::vector<std::unique_ptr<FitScene>> scenes;
  for (const FitExperiment& e : problem.experiments)
    scenes.push_back(std::make_unique<FitScene>(e, problem.parameters, problem.source, from_json));
  return scenes;
}

void report_allocations(benchmark::State& state, long allocations) {
  state.counters["allocations_per_evaluation"] =
      static_cast<double>(allocations) / static_cast<double>(state.iterations());
}

/// One residual evaluation: both experiments simulated, the residuals
/// assembled; range(0) = 1: the old route (JSON → scene → model), 0: in place.
void BM_ResidualEvaluation(benchmark::State& state) {
  const IdentifyProblem problem = cam_rig();
  const bool from_json = state.range(0) == 1;
  const std::vector<std::unique_ptr<FitScene>> scenes = fit_scenes(problem, from_json);
  ResidualAssembler assembler(problem);
  std::vector<double> r(problem.residual_count());
  std::vector<FitRun> runs(problem.experiments.size());
  const long before = test::allocation_count();
  for (auto _ : state) {
    for (std::size_t k = 0; k < runs.size(); ++k) runs[k] = scenes[k]->run(kValues);
    assembler.assemble(runs, 0.0, r.data());
    benchmark::DoNotOptimize(r.data());
  }
  state.SetLabel(from_json ? "rebuilt from JSON" : "set in place");
  report_allocations(state, test::allocation_count() - before);
}
BENCHMARK(BM_ResidualEvaluation)->Arg(1)->Arg(0)->Unit(benchmark::kMillisecond);

/// The parameter-setting part alone, both experiments (range(0) as above).
void BM_SetParameters(benchmark::State& state) {
  const IdentifyProblem problem = cam_rig();
  const bool from_json = state.range(0) == 1;
  const std::vector<std::unique_ptr<FitScene>> scenes = fit_scenes(problem, from_json);
  const long before = test::allocation_count();
  for (auto _ : state) {
    for (const std::unique_ptr<FitScene>& scene : scenes) scene->set(kValues);
    benchmark::DoNotOptimize(scenes[0]->model().contact.stiffness);
  }
  state.SetLabel(from_json ? "rebuilt from JSON" : "set in place");
  report_allocations(state, test::allocation_count() - before);
}
BENCHMARK(BM_SetParameters)->Arg(1)->Arg(0)->Unit(benchmark::kMicrosecond);

/// The 1300 rpm experiment simulated at kValues' starting scene and sampled
/// on its record's times; range(0) = 1: metrics and energy balance followed
/// over every step, 0: the samples alone (SimulationOptions::step_metrics).
void BM_SampledSimulation(benchmark::State& state) {
  const IdentifyProblem problem = cam_rig();
  const FitExperiment& experiment = problem.experiments.back();
  const Model model = build_model(experiment.scene, problem.source.file);
  Workspace ws = make_workspace(model);
  SimulationOptions options;
  options.record_series = false;
  options.sample_times = experiment.record.time;
  options.step_metrics = state.range(0) == 1;
  long steps = 0;
  for (auto _ : state) {
    const SimulationResult result = simulate(experiment.scene, model, ws, options);
    steps = result.solver.counters.steps;
    benchmark::DoNotOptimize(steps);
  }
  state.counters["steps"] = static_cast<double>(steps);
  state.SetLabel(options.step_metrics ? "every step observed" : "samples only");
}
BENCHMARK(BM_SampledSimulation)->Arg(1)->Arg(0)->Unit(benchmark::kMillisecond);

/// The whole study on one thread (what `camdyn run` does with --jobs 1).
void BM_IdentifyCamRigStudy(benchmark::State& state) {
  const IdentifyProblem problem = cam_rig();
  IdentifyResult result;
  for (auto _ : state) {
    result = identify(problem, {1, {}});
    // Not DoNotOptimize(result.final_cost): its "+m,r" form may hand a double
    // back through a general register and garble it (benchmark 1.7).
    benchmark::ClobberMemory();
  }
  state.counters["simulations"] = static_cast<double>(result.simulations);
  state.counters["reused_points"] = static_cast<double>(result.reused_points);
  state.counters["final_cost"] = result.final_cost;
}
BENCHMARK(BM_IdentifyCamRigStudy)->Unit(benchmark::kSecond)->Iterations(1);

}  // namespace

BENCHMARK_MAIN();
