// A study's model assembled once and its speed set in place at each speed,
// against a model assembled at every speed, in the same run (issue 57 item
// 4: "the Model and the geometry are built once per study"): `in_place:1` is
// what jump_map and speed_limit do (a copy of the study's model per range or
// worker thread, set_cam_speed at each speed), `in_place:0` what they did
// before (JumpMapStudy::model / SpeedLimitStudy::model null: build_model at
// each speed on the shared geometry). On
//
// * the models alone, 200 speeds, nothing simulated, for the quickstart and
//   for the bucket tappet (studies/valvetrain/bucket_tappet.json: a spring
//   with mass, whose held-train jump speed every assembly computes);
// * the quickstart's jump map over 800–1800 rpm (21 speeds, one range,
//   2 transient revolutions, 2 samples, period 1, no refinement or
//   coexistence check: a cheap map, so that the model's share shows);
// * a speed_limit scan of each valve-train study (studies/valvetrain/: the
//   bucket tappet and the pushrod-rocker train from 1000 rpm, 16 speeds,
//   tolerance 5 rpm; the DOHC lash train from 2000 rpm, 12 speeds,
//   tolerance 10 rpm), on one thread.
//
// The counters give the models assembled per iteration.
//
//   build/ci/bench/model_reuse_bench --benchmark_out=bench/results/model_reuse.json --benchmark_out_format=json
#include <benchmark/benchmark.h>

#include <memory>
#include <string>

#include "dynamics/cam_geometry.h"
#include "dynamics/model.h"
#include "io/config.h"
#include "study/jump_map.h"
#include "study/speed_limit.h"
#include "study/study.h"

namespace {

const std::string kQuickstart = std::string(CAMDYN_SOURCE_DIR) + "/studies/quickstart.json";
const std::string kValveTrains = std::string(CAMDYN_SOURCE_DIR) + "/studies/valvetrain/";
const std::string kBucketTappet = kValveTrains + "bucket_tappet.json";
constexpr int kSpeeds = 200;

camdyn::StudyContext context(const std::string& config) {
  camdyn::StudyContext ctx;
  ctx.config_file = config;
  ctx.source = camdyn::config_source(config);
  ctx.jobs = 1;
  return ctx;
}

void label(benchmark::State& state, long builds) {
  state.counters["model_builds"] = static_cast<double>(builds);
  state.SetLabel(state.range(0) ? "in place" : "assembled per speed");
}

/// The models of 200 speeds (the scene's rpm ± 40 %), nothing simulated.
void BM_SpeedModels(benchmark::State& state, const std::string& config) {
  camdyn::SceneConfig scene = camdyn::load_scene(config);
  const double rpm = scene.mechanism.cam.rpm;  // [rpm]
  const auto geometry = camdyn::build_cam_geometry(scene, config);
  const camdyn::Model study_model = camdyn::build_model(*geometry, scene, config);
  const bool in_place = state.range(0) != 0;
  long builds = 0;
  for (auto _ : state) {
    const long before = camdyn::model_builds();
    camdyn::Model model = study_model;
    for (int i = 0; i < kSpeeds; ++i) {
      scene.mechanism.cam.rpm = rpm * (0.6 + 0.8 * i / kSpeeds);
      if (in_place)
        camdyn::set_cam_speed(model, scene, config);
      else
        model = camdyn::build_model(*geometry, scene, config);
      benchmark::DoNotOptimize(model.omega);
    }
    builds = camdyn::model_builds() - before;
  }
  label(state, builds);
}
BENCHMARK_CAPTURE(BM_SpeedModels, quickstart, kQuickstart)
    ->Arg(0)
    ->Arg(1)
    ->ArgName("in_place")
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_SpeedModels, bucket_tappet, kBucketTappet)
    ->Arg(0)
    ->Arg(1)
    ->ArgName("in_place")
    ->Unit(benchmark::kMillisecond);

/// The quickstart's jump map over 800–1800 rpm.
void BM_JumpMapQuickstart(benchmark::State& state) {
  const camdyn::StudyContext ctx = context(kQuickstart);
  camdyn::Json doc = camdyn::load_config_json(kQuickstart);
  doc["study"] = "jump_map";
  doc["jump_map"] = camdyn::Json::parse(R"({"low_rpm": 800, "high_rpm": 1800, "speeds": 21, "ranges": 1,
                                            "transient_revolutions": 2, "samples": 2, "refine": 0,
                                            "check_coexistence": false})");
  doc["periodic"] = camdyn::Json::parse(R"({"max_period": 1, "lyapunov_revolutions": 10})");
  camdyn::JumpMapStudy study = camdyn::read_jump_map_study(doc, ctx);
  if (state.range(0) == 0) study.model = nullptr;
  long builds = 0;
  for (auto _ : state) {
    const long before = camdyn::model_builds();
    benchmark::DoNotOptimize(camdyn::run_jump_map_range(study, 0, ctx.config_file));
    builds = camdyn::model_builds() - before;
  }
  label(state, builds);
}
BENCHMARK(BM_JumpMapQuickstart)->Arg(0)->Arg(1)->ArgName("in_place")->Unit(benchmark::kSecond)->Iterations(2);

/// A speed_limit scan of a valve-train study and its bisection, on one thread.
void BM_SpeedLimitValveTrain(benchmark::State& state, const std::string& file, const char* scan) {
  const camdyn::StudyContext ctx = context(file);
  camdyn::Json doc = camdyn::load_config_json(file);
  doc["study"] = "speed_limit";
  doc["speed_limit"] = camdyn::Json::parse(scan);
  camdyn::SpeedLimitStudy study = camdyn::read_speed_limit_study(doc, ctx);
  if (state.range(0) == 0) study.model = nullptr;
  long builds = 0;
  for (auto _ : state) {
    const long before = camdyn::model_builds();
    benchmark::DoNotOptimize(camdyn::run_speed_limit(study, ctx));
    builds = camdyn::model_builds() - before;
  }
  label(state, builds);
}
/// The valve-train studies' scans: name, config, speed_limit block, iterations.
struct ValveTrainScan {
  const char* name;
  std::string file;
  const char* scan;
  int iterations;
};

const bool kValveTrainScans = [] {
  const ValveTrainScan scans[] = {
      {"bucket_tappet", kBucketTappet, R"({"low_rpm": 1000, "scan": 16, "tolerance_rpm": 5})", 2},
      {"pushrod_rocker", kValveTrains + "pushrod_rocker.json", R"({"low_rpm": 1000, "scan": 16, "tolerance_rpm": 5})",
       2},
      {"dohc_bucket_lash", kValveTrains + "dohc_bucket_lash.json",
       R"({"low_rpm": 2000, "scan": 12, "tolerance_rpm": 10})", 1},
  };
  for (const ValveTrainScan& s : scans)
    benchmark::RegisterBenchmark((std::string("BM_SpeedLimitValveTrain/") + s.name).c_str(),
                                 [s](benchmark::State& state) { BM_SpeedLimitValveTrain(state, s.file, s.scan); })
        ->Arg(0)
        ->Arg(1)
        ->ArgName("in_place")
        ->Unit(benchmark::kSecond)
        ->Iterations(s.iterations);
  return true;
}();

}  // namespace

BENCHMARK_MAIN();
