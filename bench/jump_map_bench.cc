// Warm-started jump maps (issue 38): a 100-speed jump map run the transient
// way at every speed (`"warm_start": false`, the path before the warm
// start) and warm-started, in the same run, on
//
// * the quickstart (studies/quickstart.json) from 900 to 1250 rpm: across
//   its jump speed (≈ 1045 rpm with the damper), period 1 throughout, the
//   follower leaving the cam from ≈ 1050 rpm on (goal: warm < 10 s);
// * the packaging arm (studies/packaging_arm_jump_map.json) from 1450 to
//   1800 rpm: period 1, a period doubling near 1525 rpm, a chaotic band
//   near 1700–1750 rpm and period 1 again (goal: warm < 30 s).
//
// Each iteration runs both maps on the same 100 speeds (`"refine": 0`: the
// refined speeds would follow each map's classes), the ranges two at a time
// (as `--jobs 2`);
// the benchmark's time is the warm map's, and the counters give both times,
// their ratio, the speeds the warm map predicted and the speeds the two maps
// classify differently (motion kind or period), and the speeds each marks
// coexisting (docs/periodic.md "Coexisting attractors"), and the warm map's
// slowest and fastest range (how evenly the ranges share the work). The two can differ
// where the shooting sees two orbits: the quickstart at 1214.6 rpm is period 1
// warm-started (|μ| 0.015, continued from 1211 rpm) and period 3 the
// transient way (|μ| 0.009), but the period-3 orbit's points lie 1e-6
// (scaled) from the period-1 orbit's and, integrated on, both have the same
// impacts every revolution: one motion through the integration noise.
//
//   build/release/bench/jump_map_bench --benchmark_out=bench/results/jump_map.json --benchmark_out_format=json
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <string>
#include <vector>

#include "common/parallel.h"
#include "io/config.h"
#include "study/jump_map.h"

namespace {

using namespace camdyn;

constexpr int kWorkers = 2;  // as `--jobs 2` on the two cores it was measured on

JumpMapStudy read_map(const std::string& config, const std::string& jump_map, bool warm) {
  StudyContext ctx;
  ctx.config_file = config;
  ctx.source = config_source(config);
  const std::string fields = jump_map + R"(, "warm_start": )" + (warm ? "true}" : "false}");
  return read_jump_map_study(load_config_json(config, {"study=jump_map", "jump_map=" + fields}), ctx);
}

struct MapRun {
  std::vector<JumpMapPoint> points;   ///< in rpm order
  double seconds = 0.0;               ///< wall time [s]
  std::vector<double> range_seconds;  ///< each range's wall time [s]: how evenly the ranges share the work
};

MapRun run_map(const JumpMapStudy& study, const std::string& file) {
  const std::size_t ranges = std::min(study.rpm.size(), static_cast<std::size_t>(study.config.ranges));
  std::vector<std::vector<JumpMapPoint>> by_range(ranges);
  MapRun run;
  run.range_seconds.assign(ranges, 0.0);
  const auto t0 = std::chrono::steady_clock::now();
  parallel_for_workers(ranges, kWorkers, [&](int, std::size_t r) {
    const auto start = std::chrono::steady_clock::now();
    by_range[r] = run_jump_map_range(study, r, file);
    run.range_seconds[r] = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  });
  run.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  for (auto& points : by_range) run.points.insert(run.points.end(), points.begin(), points.end());
  return run;
}

void BM_JumpMap(benchmark::State& state, const std::string& config, const std::string& jump_map) {
  const std::string path = std::string(CAMDYN_SOURCE_DIR) + "/" + config;
  const JumpMapStudy cold_study = read_map(path, jump_map, false), warm_study = read_map(path, jump_map, true);
  MapRun cold, warm;
  for (auto _ : state) {
    state.PauseTiming();
    cold = run_map(cold_study, path);
    state.ResumeTiming();
    warm = run_map(warm_study, path);
  }
  long predicted = 0, different = 0, failed = 0, coexisting_warm = 0, coexisting_cold = 0;
  for (std::size_t i = 0; i < warm.points.size(); ++i) {
    const JumpMapPoint &w = warm.points[i], &c = cold.points[i];
    predicted += w.start == JumpMapStart::predicted ? 1 : 0;
    coexisting_warm += w.coexisting ? 1 : 0;
    coexisting_cold += c.coexisting ? 1 : 0;
    failed += (w.ok ? 0 : 1) + (c.ok ? 0 : 1);
    if (w.ok != c.ok || w.motion != c.motion || w.period != c.period) ++different;
  }
  state.counters["speeds"] = static_cast<double>(warm.points.size());
  state.counters["cold_s"] = cold.seconds;
  state.counters["warm_s"] = warm.seconds;
  state.counters["cold_over_warm"] = cold.seconds / warm.seconds;
  state.counters["warm_slowest_range_s"] = *std::max_element(warm.range_seconds.begin(), warm.range_seconds.end());
  state.counters["warm_fastest_range_s"] = *std::min_element(warm.range_seconds.begin(), warm.range_seconds.end());
  state.counters["predicted_speeds"] = static_cast<double>(predicted);
  state.counters["failed_speeds"] = static_cast<double>(failed);
  state.counters["classed_differently"] = static_cast<double>(different);
  state.counters["coexisting_warm"] = static_cast<double>(coexisting_warm);
  state.counters["coexisting_cold"] = static_cast<double>(coexisting_cold);
}

BENCHMARK_CAPTURE(BM_JumpMap, quickstart_100_speeds_across_the_jump_speed, "studies/quickstart.json",
                  R"({"low_rpm": 900, "high_rpm": 1250, "speeds": 100, "ranges": 2, "refine": 0)")
    ->Unit(benchmark::kSecond)
    ->Iterations(1)
    ->UseRealTime();
BENCHMARK_CAPTURE(BM_JumpMap, packaging_arm_100_speeds_chaotic_band, "studies/packaging_arm_jump_map.json",
                  R"({"low_rpm": 1450, "high_rpm": 1800, "speeds": 100, "ranges": 2, "refine": 0)")
    ->Unit(benchmark::kSecond)
    ->Iterations(1)
    ->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
