// Cost of the rigid stage of an optimize study on a follower train
// (docs/optimize.md "Trains"): studies/valvetrain/optimize_train.json, a
// two-body train with an 8-coil spring, every design checked at 10 sampled
// speeds. Target: the whole stage (certificate, family bound, design,
// checks) under 2 s; the held train's response at one speed alone.
//
//   build/ci/bench/train_rigid_stage_bench --benchmark_out=bench/results/train_rigid_stage.json
//   --benchmark_out_format=json
#include <benchmark/benchmark.h>

#include <numbers>
#include <string>

#include "dynamics/held_train.h"
#include "dynamics/model.h"
#include "io/config.h"
#include "optim/optimize/design.h"
#include "optim/optimize/optimize.h"
#include "optim/optimize/rigid_design.h"

namespace {

using namespace camdyn;
using namespace camdyn::optim;

const std::string kStudy = std::string(CAMDYN_SOURCE_DIR) + "/studies/valvetrain/optimize_train.json";

OptimizeStudy train_study() { return read_optimize_study(load_config_json(kStudy), config_source(kStudy)); }

void BM_TrainRigidStage(benchmark::State& state) {
  const OptimizeStudy study = train_study();
  const DesignSpace space(study.baseline, study.config.design, kStudy);
  RigidStageResult r;
  for (auto _ : state) {
    r = run_rigid_stage(study.baseline, study.config, space, kStudy);
    benchmark::DoNotOptimize(r.lp_solves);
  }
  const Certificate& c = r.certificate;
  state.counters["lp_solves"] = r.lp_solves;
  state.counters["any_law_rpm"] = c.any_law_rpm;
  state.counters["any_law_coarse_rpm"] = c.any_law_coarse_rpm;
  state.counters["family_rpm"] = c.family_rpm;
  state.counters["baseline_rpm"] = c.baseline_rpm;
  state.counters["design_jump_free_rpm"] = r.design.jump_free_rpm;
  state.counters["harmonics"] = c.train_harmonics;
}
BENCHMARK(BM_TrainRigidStage)->Unit(benchmark::kMillisecond)->UseRealTime();

/// The held train's response of the baseline law at one speed (512 angles).
void BM_HeldTrainResponse(benchmark::State& state) {
  const OptimizeStudy study = train_study();
  const Model model = build_model(study.baseline, kStudy);
  const HeldTrain held = held_train(model);
  const GridSignal law = grid_signal([&](double theta) { return model.law->eval(theta); }, 512);
  int harmonics = 0;
  for (auto _ : state) {
    const auto v = held_train_values(held, law, 6000.0 * std::numbers::pi / 30.0, &harmonics);
    benchmark::DoNotOptimize(v.data());
  }
  state.counters["harmonics"] = harmonics;
}
BENCHMARK(BM_HeldTrainResponse)->Unit(benchmark::kMicrosecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
