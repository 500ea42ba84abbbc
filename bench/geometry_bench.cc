// A design's geometry built once per study against once per speed, in the
// same run (issue: "cam speed is a parameter"): the quickstart's jump map over
// 200 speeds and a speed_limit scan of 24 speeds, each with the geometry
// shared (`shared`, what the studies do) and with every speed building its
// own (`rebuilt`, what they did before), and the model assembly alone for
// 200 speeds, where building the geometry is all the difference.
//
//   build/release/bench/geometry_bench --benchmark_out=bench/results/geometry.json --benchmark_out_format=json
#include <benchmark/benchmark.h>

#include <string>

#include "dynamics/cam_geometry.h"
#include "dynamics/model.h"
#include "io/config.h"
#include "study/jump_map.h"
#include "study/speed_limit.h"
#include "study/study.h"

namespace {

const std::string kQuickstart = std::string(CAMDYN_SOURCE_DIR) + "/studies/quickstart.json";
constexpr int kSpeeds = 200;

camdyn::StudyContext context() {
  camdyn::StudyContext ctx;
  ctx.config_file = kQuickstart;
  ctx.source = camdyn::config_source(kQuickstart);
  ctx.jobs = 1;
  return ctx;
}

void label(benchmark::State& state, long builds) {
  state.counters["geometry_builds"] = static_cast<double>(builds);
  state.SetLabel(state.range(0) ? "shared" : "rebuilt");
}

/// The model of every speed of a 200-speed sweep, nothing simulated.
void BM_SpeedSweepModels(benchmark::State& state) {
  camdyn::SceneConfig scene = camdyn::load_scene(kQuickstart);
  const bool shared = state.range(0) != 0;
  long builds = 0;
  for (auto _ : state) {
    const long before = camdyn::cam_geometry_builds();
    const auto geometry = shared ? camdyn::build_cam_geometry(scene, kQuickstart) : nullptr;
    for (int i = 0; i < kSpeeds; ++i) {
      scene.mechanism.cam.rpm = 600.0 + 4.0 * i;
      benchmark::DoNotOptimize(camdyn::build_model(geometry, scene, kQuickstart));
    }
    builds = camdyn::cam_geometry_builds() - before;
  }
  label(state, builds);
}
BENCHMARK(BM_SpeedSweepModels)->Arg(0)->Arg(1)->ArgName("shared")->Unit(benchmark::kMillisecond);

/// The quickstart's jump map over 200 speeds (2 transient revolutions, 2 samples, period 1).
void BM_JumpMap200(benchmark::State& state) {
  const camdyn::StudyContext ctx = context();
  camdyn::Json doc = camdyn::load_config_json(kQuickstart);
  doc["study"] = "jump_map";
  doc["jump_map"] = camdyn::Json::parse(R"({"low_rpm": 600, "high_rpm": 1400, "speeds": 200, "ranges": 1,
                                            "transient_revolutions": 2, "samples": 2})");
  doc["periodic"] = camdyn::Json::parse(R"({"max_period": 1, "lyapunov_revolutions": 10})");
  camdyn::JumpMapStudy study = camdyn::read_jump_map_study(doc, ctx);
  if (state.range(0) == 0) study.geometry = nullptr;
  long builds = 0;
  for (auto _ : state) {
    const long before = camdyn::cam_geometry_builds();
    benchmark::DoNotOptimize(camdyn::run_jump_map_range(study, 0, ctx.config_file));
    builds = camdyn::cam_geometry_builds() - before;
  }
  label(state, builds);
}
BENCHMARK(BM_JumpMap200)->Arg(0)->Arg(1)->ArgName("shared")->Unit(benchmark::kSecond)->Iterations(2);

/// A speed_limit scan of 24 speeds and its bisection, on one thread.
void BM_SpeedLimitScan(benchmark::State& state) {
  const camdyn::StudyContext ctx = context();
  camdyn::Json doc = camdyn::load_config_json(kQuickstart);
  doc["study"] = "speed_limit";
  doc["simulation"]["cycles"] = 2;
  doc["speed_limit"] = camdyn::Json::parse(R"({"low_rpm": 600, "high_rpm": 2400, "scan": 24, "tolerance_rpm": 5})");
  camdyn::SpeedLimitStudy study = camdyn::read_speed_limit_study(doc, ctx);
  if (state.range(0) == 0) study.geometry = nullptr;
  long builds = 0;
  for (auto _ : state) {
    const long before = camdyn::cam_geometry_builds();
    benchmark::DoNotOptimize(camdyn::run_speed_limit(study, ctx));
    builds = camdyn::cam_geometry_builds() - before;
  }
  label(state, builds);
}
BENCHMARK(BM_SpeedLimitScan)->Arg(0)->Arg(1)->ArgName("shared")->Unit(benchmark::kSecond)->Iterations(2);

}  // namespace

BENCHMARK_MAIN();
