// Cost of a measured lift table (issue 15): building the motion law of a
// table of N rows (0.1°, 0.01°, 0.001° encoder data) — the periodic quintic
// through every row, by the banded solve — and one evaluation of it. Time and
// memory must grow linearly in N (the dense solve it replaced was O(N³) time
// and O(N²) memory: 3,600 rows took 2.7 s and 233 MB).
//
//   build/release/bench/table_bench --benchmark_out=bench/results/table.json --benchmark_out_format=json
#include <benchmark/benchmark.h>

#include <cmath>
#include <numbers>
#include <string>

#include "geometry/motion_law.h"

namespace {

using namespace camdyn;

MotionLawConfig table_of(int rows) {
  TableConfig t;
  t.file = "encoder.csv";
  for (int i = 0; i < rows; ++i) {
    const double theta = 2.0 * std::numbers::pi * i / rows;
    t.angle_deg.push_back(360.0 * i / rows);
    t.lift.push_back(0.01 * (1.0 - std::cos(theta)) + 0.002 * std::sin(3.0 * theta));
    t.lines.push_back(i + 2);
  }
  MotionLawConfig c;
  c.table = t;
  return c;
}

void BM_TableLawBuild(benchmark::State& state) {
  const MotionLawConfig config = table_of(static_cast<int>(state.range(0)));
  for (auto _ : state) {
    const MotionLaw law = build_motion_law(config, "bench.json");
    benchmark::DoNotOptimize(&law);
  }
  state.counters["rows"] = static_cast<double>(state.range(0));
  state.counters["us_per_row"] = benchmark::Counter(
      static_cast<double>(state.range(0)), benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}
BENCHMARK(BM_TableLawBuild)->Arg(3600)->Arg(36000)->Arg(360000)->Unit(benchmark::kMillisecond);

void BM_TableLawEval(benchmark::State& state) {
  const MotionLaw law = build_motion_law(table_of(static_cast<int>(state.range(0))), "bench.json");
  double theta = 0.0;
  for (auto _ : state) {
    const LawSample s = law.eval(theta);
    benchmark::DoNotOptimize(&s);
    theta += 0.001;
  }
}
BENCHMARK(BM_TableLawEval)->Arg(3600)->Arg(360000);

}  // namespace

BENCHMARK_MAIN();
