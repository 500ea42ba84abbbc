// The Lyapunov estimate's cost per revolution (issue 38, docs/periodic.md, "How",
// the Lyapunov exponent): the tangent stretched by forward sensitivities (one
// run with one sensitivity column a revolution) against a neighbour
// trajectory (two map runs a revolution, in parallel on two threads), A/B
// interleaved in one process so that the machine's load falls on both, on
//
// * 0: the chaotic bouncing ball (studies/periodic/bouncing_ball_chaotic.json, 2 coordinates);
// * 1: the quickstart at 1300 rpm with a 5 N s/m damper (chaotic, 2 coordinates);
// * 2: the packaging arm at 1725 rpm (studies/packaging_arm_jump_map.json's chaotic band);
// * 3: the 8-coil bucket tappet (studies/valvetrain/bucket_tappet.json, 18 coordinates);
//
// each from a section point after 4 revolutions of transient, over
// kRevolutions revolutions. Counters: seconds per revolution of each way on
// one thread (`*_1t`) and the neighbour's on two (`neighbour_s_2t`), their
// ratios, λ of each, and the revolutions the tangent fell back on.
//
//   build/ci/bench/lyapunov_bench
#include <benchmark/benchmark.h>

#include <chrono>
#include <string>
#include <vector>

#include "dynamics/map_sensitivity.h"
#include "dynamics/poincare_map.h"
#include "io/config.h"
#include "study/periodic_orbit.h"
#include "study/periodic_study.h"

namespace {

using namespace camdyn;

constexpr int kRevolutions = 20;

// Any scene or study config read as a periodic study's scene.
PeriodicStudy as_periodic(const std::string& config, const std::vector<std::string>& sets) {
  Json doc = load_config_json(config, sets);
  doc["study"] = "periodic";
  doc.erase("periodic");
  doc.erase("jump_map");
  StudyContext ctx;
  ctx.config_file = config;
  ctx.source = config_source(config);
  return read_periodic_study(doc, ctx);
}

struct Case {
  Case(const std::string& config, const std::vector<std::string>& sets)
      : study(as_periodic(config, sets)),
        model(build_model(study.geometry, study.scene, config)),
        map(study.scene, model, config) {}
  PeriodicStudy study;
  Model model;
  PoincareMap map;
};

Case& lyapunov_case(long which) {
  const std::string dir = std::string(CAMDYN_SOURCE_DIR) + "/studies/";
  static Case ball(dir + "periodic/bouncing_ball_chaotic.json", {});
  static Case quick(dir + "quickstart.json", {"mechanism.follower.damping=5"});
  static Case arm(dir + "packaging_arm_jump_map.json", {"mechanism.cam.rpm=1725"});
  static Case tappet(dir + "valvetrain/bucket_tappet.json", {});
  return which == 0 ? ball : which == 1 ? quick : which == 2 ? arm : tappet;
}

SectionPoint transient_end(Case& c) {
  Workspace ws = make_workspace(c.model);
  SimulationOptions options;
  options.record_series = false;
  return c.map.point(simulate(c.map.scene_for(4), c.model, ws, options));
}

// Seconds per revolution of the estimate by `method` on `threads`, and the estimate.
double seconds_per_revolution(Case& c, const SectionPoint& start, JacobianMethod method, int threads,
                              LyapunovEstimate& e) {
  PeriodicOptions options;
  options.jacobian = method;
  options.threads = threads;
  options.lyapunov_revolutions = kRevolutions;
  const auto t0 = std::chrono::steady_clock::now();
  e = estimate_lyapunov(c.map, start, options);
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() / kRevolutions;
}

void BM_LyapunovTangentAgainstNeighbour(benchmark::State& state) {
  Case& c = lyapunov_case(state.range(0));
  const std::string unsupported = sensitivity_unsupported(c.map);
  if (!unsupported.empty()) {
    state.SkipWithError(unsupported.c_str());
    for (auto _ : state) {
    }
    return;
  }
  const SectionPoint start = transient_end(c);
  double tangent = 0.0, neighbour_1t = 0.0, neighbour_2t = 0.0;
  LyapunovEstimate by_tangent, by_neighbour;
  long runs = 0;
  for (auto _ : state) {
    tangent += seconds_per_revolution(c, start, JacobianMethod::sensitivity, 1, by_tangent);
    neighbour_1t += seconds_per_revolution(c, start, JacobianMethod::finite_difference, 1, by_neighbour);
    neighbour_2t += seconds_per_revolution(c, start, JacobianMethod::finite_difference, 2, by_neighbour);
    ++runs;
  }
  const double n = static_cast<double>(runs);
  state.counters["states"] = c.map.dimension();
  state.counters["tangent_s_1t"] = tangent / n;
  state.counters["neighbour_s_1t"] = neighbour_1t / n;
  state.counters["neighbour_s_2t"] = neighbour_2t / n;
  state.counters["tangent_over_neighbour_1t"] = tangent / neighbour_1t;
  state.counters["tangent_over_neighbour_2t"] = tangent / neighbour_2t;
  state.counters["lambda_tangent"] = by_tangent.per_revolution;
  state.counters["lambda_neighbour"] = by_neighbour.per_revolution;
  state.counters["fallback_revolutions"] = static_cast<double>(by_tangent.fallback_revolutions);
}
BENCHMARK(BM_LyapunovTangentAgainstNeighbour)->DenseRange(0, 3)->Unit(benchmark::kSecond)->UseRealTime()->Iterations(2);

}  // namespace

BENCHMARK_MAIN();
