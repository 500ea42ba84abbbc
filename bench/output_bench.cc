// The cost of a simulate run's outputs after the integration: timeseries.csv,
// events.csv + summary.json, the report's plot data and the whole report
// (gnuplot SVGs), and all of them together as `camdyn run` writes them, for
// a 200-revolution run (the quickstart scene, 200 revolutions at the default
// 0.5° output step: 144,001 time-series rows, about the size of the
// long-flight benchmark's). The run is simulated once, before the timing;
// each iteration writes into a fresh temporary directory. Wall time, since
// gnuplot runs in child processes. Goal: everything within 0.5 s.
//
//   build/release/bench/output_bench --benchmark_out=bench/results/output.json --benchmark_out_format=json
#include <benchmark/benchmark.h>
#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <stdexcept>
#include <string>

#include "dynamics/model.h"
#include "dynamics/simulation.h"
#include "io/config.h"
#include "io/json_writer.h"
#include "output/report.h"
#include "study/simulation_output.h"

namespace {

// The quickstart scene over 200 revolutions, simulated once per process (in
// place: a Model is not to be moved once built).
struct Run {
  camdyn::SceneConfig scene;
  camdyn::Model model;
  camdyn::SimulationResult result;

  explicit Run(camdyn::SceneConfig s) : scene(std::move(s)), model(camdyn::build_model(scene, "quickstart")) {
    camdyn::Workspace ws;
    result = camdyn::simulate(scene, model, ws);
    camdyn::throw_if_failed(result);
  }
};

camdyn::SceneConfig long_quickstart() {
  camdyn::SceneConfig scene = camdyn::load_scene(std::string(CAMDYN_SOURCE_DIR) + "/studies/quickstart.json");
  scene.simulation.cycles = 200.0;
  scene.simulation.output_step_deg = 0.5;
  return scene;
}

const Run& long_run() {
  static const Run run(long_quickstart());
  return run;
}

// A fresh directory under the temporary directory, removed with its contents.
class ScratchDir {
 public:
  ScratchDir() {
    std::string pattern = (std::filesystem::temp_directory_path() / "camdyn-output-bench-XXXXXX").string();
    if (::mkdtemp(pattern.data()) == nullptr) throw std::runtime_error("cannot create " + pattern);
    path_ = pattern;
  }
  ~ScratchDir() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  ScratchDir(const ScratchDir&) = delete;
  ScratchDir& operator=(const ScratchDir&) = delete;
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

// CPU time of this process (all its threads) and of the child processes it
// has waited for (gnuplot) [s]: unlike the wall time, not stretched by other
// work on the machine.
double cpu_seconds() {
  double total = 0.0;
  for (const int who : {RUSAGE_SELF, RUSAGE_CHILDREN}) {
    rusage u{};
    ::getrusage(who, &u);
    for (const timeval& t : {u.ru_utime, u.ru_stime})
      total += static_cast<double>(t.tv_sec) + 1e-6 * static_cast<double>(t.tv_usec);
  }
  return total;
}

// Counters shared by every benchmark: the size of the run and the CPU time
// per iteration, gnuplot included (measured since `cpu_start`).
void label(benchmark::State& state, const Run& run, double cpu_start) {
  state.counters["rows"] = static_cast<double>(run.result.series.time.size());
  state.counters["events"] = static_cast<double>(run.result.events.size());
  state.counters["cpu_s_with_children"] =
      (cpu_seconds() - cpu_start) / static_cast<double>(std::max<benchmark::IterationCount>(state.iterations(), 1));
}

// timeseries.csv alone (144,001 rows of 12 numbers, fsync and rename included).
void BM_TimeSeriesCsv(benchmark::State& state) {
  const Run& run = long_run();
  ScratchDir dir;
  const double cpu_start = cpu_seconds();
  for (auto _ : state) camdyn::write_timeseries_csv(dir.path() / "timeseries.csv", run.result.series);
  label(state, run, cpu_start);
  state.counters["MB_per_s"] =
      benchmark::Counter(static_cast<double>(std::filesystem::file_size(dir.path() / "timeseries.csv")) / 1e6,
                         benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(BM_TimeSeriesCsv)->Unit(benchmark::kMillisecond)->UseRealTime();

// events.csv and summary.json.
void BM_EventsAndSummary(benchmark::State& state) {
  const Run& run = long_run();
  ScratchDir dir;
  const double cpu_start = cpu_seconds();
  for (auto _ : state) {
    camdyn::write_events_csv(dir.path() / "events.csv", run.result.events);
    camdyn::write_json_atomic(dir.path() / "summary.json", camdyn::summary_json(run.scene, run.model, run.result));
  }
  label(state, run, cpu_start);
}
BENCHMARK(BM_EventsAndSummary)->Unit(benchmark::kMillisecond)->UseRealTime();

// The report's content without rendering: verdict, tables, every plot's data.
void BM_ReportData(benchmark::State& state) {
  const Run& run = long_run();
  std::size_t points = 0;
  const double cpu_start = cpu_seconds();
  for (auto _ : state) {
    const camdyn::Report report = camdyn::simulation_report(run.scene, run.model, run.result);
    points = 0;
    for (const camdyn::Plot& plot : report.plots)
      for (const camdyn::Series& s : plot.series) points += s.x.size();
    benchmark::DoNotOptimize(points);
  }
  label(state, run, cpu_start);
  state.counters["plot_points"] = static_cast<double>(points);
}
BENCHMARK(BM_ReportData)->Unit(benchmark::kMillisecond)->UseRealTime();

// report.html: the plot data, gnuplot for every plot (in parallel), the page.
void BM_Report(benchmark::State& state) {
  const Run& run = long_run();
  ScratchDir dir;
  const double cpu_start = cpu_seconds();
  for (auto _ : state)
    camdyn::write_report(dir.path() / "report.html", camdyn::simulation_report(run.scene, run.model, run.result));
  label(state, run, cpu_start);
  state.counters["html_bytes"] = static_cast<double>(std::filesystem::file_size(dir.path() / "report.html"));
}
BENCHMARK(BM_Report)->Unit(benchmark::kMillisecond)->UseRealTime();

// Everything `camdyn run` writes after the integration. Goal: ≤ 0.5 s.
void BM_WriteSimulationOutputs(benchmark::State& state) {
  const Run& run = long_run();
  ScratchDir dir;  // each iteration replaces the files of the one before
  const double cpu_start = cpu_seconds();
  for (auto _ : state) camdyn::write_simulation_outputs(dir.path(), run.scene, run.model, run.result);
  label(state, run, cpu_start);
}
BENCHMARK(BM_WriteSimulationOutputs)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
