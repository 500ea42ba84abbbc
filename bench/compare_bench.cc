// Wall time of a small compare study (3 laws × 8 speeds of the quickstart cam,
// 24 independent runs) with 1 and 2 worker threads: the parallel speed-up of
// `camdyn run --jobs N`. Each iteration starts from an empty output folder
// (otherwise the journal would resume, i.e. skip, every run).
//
//   build/release/bench/compare_bench --benchmark_out=bench/results/compare.json --benchmark_out_format=json
#include <benchmark/benchmark.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <string>

#include "io/config.h"
#include "study/compare_study.h"
#include "study/study.h"

namespace {

namespace fs = std::filesystem;

void BM_CompareStudy(benchmark::State& state) {
  const std::string quickstart = std::string(CAMDYN_SOURCE_DIR) + "/studies/quickstart.json";
  const fs::path dir = fs::temp_directory_path() / ("camdyn_compare_bench_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const fs::path study = dir / "study.json";
  {
    std::FILE* f = std::fopen(study.c_str(), "w");
    std::fprintf(f, R"({
      "extends": "%s", "name": "bench", "study": "compare",
      "simulation": { "cycles": 3, "discard_cycles": 1, "output_step_deg": 1.0 },
      "cases": [ { "name": "cycloidal" },
                 { "name": "polynomial_345", "set": ["mechanism.cam.motion_law=profiles/polynomial_345.json"] },
                 { "name": "polynomial_4567", "set": ["mechanism.cam.motion_law=profiles/polynomial_4567.json"] } ],
      "grid": { "mechanism.cam.rpm": [800, 900, 1000, 1100, 1200, 1300, 1400, 1500] } })",
                 quickstart.c_str());
    std::fclose(f);
  }
  camdyn::StudyContext ctx;
  ctx.config_file = study.string();
  ctx.source = camdyn::config_source(study.string());
  ctx.jobs = static_cast<int>(state.range(0));
  const camdyn::Json doc = camdyn::load_config_json(study.string());
  for (auto _ : state) {
    state.PauseTiming();
    fs::remove_all(dir / "out");
    ctx.out_dir = dir / "out";
    state.ResumeTiming();
    if (camdyn::run_compare_study(doc, ctx) != 0) state.SkipWithError("the study failed");
  }
  state.counters["runs"] = 24;
  state.counters["jobs"] = static_cast<double>(ctx.jobs);
  fs::remove_all(dir);
}
BENCHMARK(BM_CompareStudy)->Arg(1)->Arg(2)->ArgName("jobs")->UseRealTime()->Iterations(3)->Unit(benchmark::kSecond);

}  // namespace

BENCHMARK_MAIN();
