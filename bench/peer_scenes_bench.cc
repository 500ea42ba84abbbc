// The simulation alone of every scene bench/peers/run_scenes.py compares
// with its scipy reference: the scene file loaded as the CLI loads it (with
// the same --set overrides), then only camdyn::simulate, without the time
// series and its output grid — the work the scipy reference's time covers (integration, event
// location, the metrics), where the CLI's wall time adds process start, the
// time series and every output file. run_scenes.py runs this binary in the
// same run as the reference and reports both ratios (bench/peers/README.md).
//
//   build/release/bench/peer_scenes_bench --benchmark_format=json
#include <benchmark/benchmark.h>

#include <string>
#include <vector>

#include "dynamics/model.h"
#include "dynamics/simulation.h"
#include "io/config.h"
#include "scene/scene.h"

namespace {

/// Loads `file` (relative to the source tree) with `overrides`, runs it
/// without the time series, and reports the solver's counters and the
/// contact force's extremes; the CPU time per run is Google Benchmark's.
void simulate_scene_file(benchmark::State& state, const std::string& file, const std::vector<std::string>& overrides) {
  camdyn::SceneConfig scene = camdyn::load_scene(std::string(CAMDYN_SOURCE_DIR) + "/" + file, overrides);
  // No output grid either (one point a revolution, as the Poincaré map's
  // runs): the model evaluated at every 0.5° is the time series' cost, not
  // the simulation's; the metrics come from every step.
  scene.simulation.output_step.reset();
  scene.simulation.output_step_deg = 360.0;
  const camdyn::Model model = camdyn::build_model(scene, file);
  camdyn::Workspace ws = camdyn::make_workspace(model);
  camdyn::SimulationOptions options;
  options.record_series = false;
  camdyn::SimulationResult r;
  for (auto _ : state) {
    r = camdyn::simulate(scene, model, ws, options);
    camdyn::throw_if_failed(r);
  }
  const camdyn::SolverCounters& c = r.solver.counters;
  state.counters["steps"] = static_cast<double>(c.steps);
  state.counters["rhs_evaluations"] = static_cast<double>(c.rhs_evaluations);
  state.counters["error_test_failures"] = static_cast<double>(c.error_test_failures);
  state.counters["impacts"] = static_cast<double>(r.metrics.impact_count);
  state.counters["peak_contact_force_N"] = r.metrics.peak_contact_force;
  state.counters["min_contact_force_N"] = r.metrics.min_contact_force;
}

const std::vector<std::string> kNoOverrides;
const std::vector<std::string> kAdams = {"integrator.method=cvode_adams"};
const std::vector<std::string> kErk8 = {"integrator.method=arkode_erk", "integrator.order=8"};
const std::vector<std::string> kDop853 = {"integrator.method=dop853"};

// The names after '/' are run_scenes.py's scene names.
BENCHMARK_CAPTURE(simulate_scene_file, long_flight, "studies/peers/long_flight.json", kNoOverrides)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(simulate_scene_file, quickstart, "studies/quickstart.json", kNoOverrides)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(simulate_scene_file, stiff_contact, "studies/peers/stiff_contact.json", kNoOverrides)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(simulate_scene_file, stiff_contact_adams, "studies/peers/stiff_contact.json", kAdams)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(simulate_scene_file, stiff_contact_erk, "studies/peers/stiff_contact.json", kErk8)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(simulate_scene_file, stiff_contact_dop853, "studies/peers/stiff_contact.json", kDop853)
    ->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
