// Cost of the valve-lobe design by LP on studies/optimize_valve_lobe.json
// (docs/optimize.md "Lift area"): the rigid stage alone (the lift-area
// programme, its any-law certificate and the checks; target under 1 s), the
// two programmes each alone, and the whole study (target under 10 s).
//
//   build/ci/bench/valve_lobe_bench --benchmark_out=bench/results/valve_lobe.json --benchmark_out_format=json
#include <benchmark/benchmark.h>

#include <numbers>
#include <string>
#include <vector>

#include "dynamics/model.h"
#include "geometry/event_spline.h"
#include "io/config.h"
#include "optim/optimize/design.h"
#include "optim/optimize/jump_bound.h"
#include "optim/optimize/lobe_bound.h"
#include "optim/optimize/optimize.h"
#include "optim/optimize/rigid_design.h"

namespace {

using namespace camdyn;
using namespace camdyn::optim;

const std::string kStudy = std::string(CAMDYN_SOURCE_DIR) + "/studies/optimize_valve_lobe.json";

OptimizeStudy valve_study() { return read_optimize_study(load_config_json(kStudy), config_source(kStudy)); }

/// The rigid stage: the lift-area programme (and its cuts), the certificate, the checks.
void BM_ValveLobeRigidStage(benchmark::State& state) {
  const OptimizeStudy study = valve_study();
  const DesignSpace space(study.baseline, study.config.design, kStudy);
  RigidStageResult r;
  for (auto _ : state) {
    r = run_rigid_stage(study.baseline, study.config, space, kStudy);
    benchmark::DoNotOptimize(r.lp_solves);
  }
  const LiftAreaCertificate& a = r.certificate.lift_area;
  state.counters["lp_solves"] = r.lp_solves;
  state.counters["lift_area_mm_rad"] = 1e3 * a.design;
  state.counters["bound_mm_rad"] = 1e3 * a.bound;
  state.counters["baseline_mm_rad"] = 1e3 * a.baseline;
  state.counters["share_of_bound"] = a.bound > 0.0 ? a.design / a.bound : 0.0;
}
BENCHMARK(BM_ValveLobeRigidStage)->Unit(benchmark::kMillisecond)->UseRealTime();

/// The certificate's programme alone (rigid.certificate_grid intervals).
void BM_ValveLobeCertificate(benchmark::State& state) {
  const OptimizeStudy study = valve_study();
  const DesignSpace space(study.baseline, study.config.design, kStudy);
  const Model model = build_model(study.baseline, kStudy);
  const RigidFollower f = *rigid_follower(model, *study.config.constraints.min_contact_force);
  const MotionLaw kept = build_motion_law(
      space.scene_with_control_points(std::vector<double>(space.control_point_count(), 0.0)).mechanism.cam.motion_law,
      kStudy);
  const ConstraintsConfig& c = study.config.constraints;
  LobeLimits limits;
  limits.omegas = {0.0, 3500.0 * std::numbers::pi / 30.0};
  limits.max_lift = *c.max_lift;
  limits.face_limit = 0.5 * study.baseline.mechanism.follower.shape.face_width - *c.face_edge_margin;
  limits.pitch_height = study.baseline.mechanism.cam.base_radius;
  limits.min_radius = *c.min_radius_of_curvature;
  limits.max_jerk = *c.max_peak_jerk;
  LobeBound b;
  for (auto _ : state) {
    b = lift_area_bound(kept, space.event_basis().from, space.event_basis().to, f, limits,
                        study.config.rigid.certificate_grid);
    // (an int: Benchmark 1.7.1's "+m,r" constraint can overwrite a double it is given, as GCC 12 compiles it)
    benchmark::DoNotOptimize(b.grid);
  }
  state.counters["bound_mm_rad"] = 1e3 * b.area;
  state.counters["grid"] = b.grid;
}
BENCHMARK(BM_ValveLobeCertificate)->Unit(benchmark::kMillisecond)->UseRealTime();

/// The whole study as shipped, on two threads.
void BM_ValveLobeStudy(benchmark::State& state) {
  const OptimizeStudy study = valve_study();
  OptimizeOptions options;
  options.threads = 2;
  OptimizeOutcome o;
  for (auto _ : state) {
    o = run_optimize(study.baseline, study.config, kStudy, options);
    benchmark::DoNotOptimize(o.candidates_tried);
  }
  state.counters["run_time_s"] = o.run_time_s;
  state.counters["rigid_stage_s"] = o.rigid.run_time_s;
  state.counters["feasible"] = o.optimized.feasible ? 1.0 : 0.0;
  state.counters["lift_area_mm_rad"] = 1e3 * o.optimized.lift_area;
}
BENCHMARK(BM_ValveLobeStudy)->Iterations(1)->Unit(benchmark::kSecond)->UseRealTime();

}  // namespace
BENCHMARK_MAIN();
