// Step cost of the follower train (docs/model.md §12) on a bucket-tappet
// scene: a translating flat follower on a cycloidal rise and return, a
// Hunt–Crossley cam contact, a seat 0.2 mm above the base circle (the valve
// lash) and a return spring with mass lumped in 0 (massless), 4, 8 or 16
// coils. Reports the CPU time per integrator step (total time /
// solver.counters.steps) and per cam revolution, the steps and evaluations
// behind them, the per-step cost relative to the massless spring of the same
// run, and the cost a coil adds to a step: against the massless spring, and
// as the slope of the least-squares line through the cases with coils (on the
// 16-coil case), with the largest relative distance of a case from it.
// The goal of the issue: ≤ 4 µs a step with an 8-coil spring, and a cost
// linear in the coils.
//
//   build/ci/bench/train_step_bench --benchmark_out=bench/results/train_step.json --benchmark_out_format=json
#include <benchmark/benchmark.h>
#include <time.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <optional>
#include <string>

#include "dynamics/model.h"
#include "dynamics/simulation.h"
#include "scene/scene.h"

namespace {

/// The bucket tappet: 8 mm cycloidal rise over 120°, return over 120°, base
/// circle dwell; base radius 18 mm, face 30 mm; follower 50 g on a
/// 35 kN/m spring with 250 N preload (45 g, surge ≈ 440 Hz, ζ = 0.03 when it
/// has mass); Hunt–Crossley cam contact K = 1e10 N/m^1.5, e = 0.8; the
/// follower's seat 0.2 mm above the base circle, Hunt–Crossley K = 5e8 N/m,
/// n = 1, e = 0.3. 3000 rpm (a 6000 rpm engine), below the jump speed; two
/// revolutions at the default tolerances (rtol 1e-8, atol 1e-12).
camdyn::SceneConfig bucket_tappet(int coils) {
  using namespace camdyn;
  SceneConfig s;
  s.name = "bucket-tappet";
  CamConfig& cam = s.mechanism.cam;
  cam.base_radius = 0.018;
  cam.rpm = 3000.0;
  cam.motion_law.segments = {{SegmentType::rise, SegmentLaw::cycloidal, 120.0, 0.008, std::nullopt, 5, {}},
                             {SegmentType::return_, SegmentLaw::cycloidal, 240.0, 0.008, std::nullopt, 5, {}},
                             {SegmentType::dwell, SegmentLaw::none, 360.0, std::nullopt, std::nullopt, 5, {}}};
  FollowerConfig& f = s.mechanism.follower;
  f.shape.type = FollowerShape::flat;
  f.shape.face_width = 0.03;
  f.mass = 0.05;
  f.spring.stiffness = 35000.0;
  f.spring.preload = 250.0;
  if (coils > 0) {
    f.spring.mass = 0.045;
    f.spring.coils = coils;
    f.spring.damping_ratio = 0.03;
  }
  SeatConfig seat;
  seat.position = 0.0002;
  seat.model = ContactModel::hunt_crossley;
  seat.stiffness = 5e8;
  seat.exponent = 1.0;
  seat.restitution = 0.3;
  f.seat = seat;
  ContactConfig& c = s.mechanism.contact;
  c.model = ContactModel::hunt_crossley;
  c.stiffness = 1e10;
  c.exponent = 1.5;
  c.restitution = 0.8;
  s.gravity = 0.0;
  s.simulation.cycles = 2.0;
  s.simulation.discard_cycles = 1;
  return s;
}

/// Process CPU time [s], the clock Google Benchmark's cpu_time and the rate
/// counters use (the 2 shared cores make wall time a measure of the load).
double cpu_seconds() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

/// CPU seconds per step of the massless spring in this run (arg 0), for the peer ratio.
std::optional<double> massless_step_time;
/// CPU seconds per step by coils (> 0) of the cases run so far, for the linear fit.
std::map<int, double> step_times;

/// Least-squares line through `step_times`: the cost a coil adds to a step
/// [s] (slope), the step without coils [s] (intercept), and the largest
/// relative distance of a case from the line (small when the cost is linear).
struct LinearFit {
  double slope = 0.0, intercept = 0.0, worst_residual = 0.0;
};
LinearFit fit_step_times() {
  const auto n = static_cast<double>(step_times.size());
  double sx = 0.0, sy = 0.0, sxx = 0.0, sxy = 0.0;
  for (const auto& [coils, y] : step_times) {
    const auto x = static_cast<double>(coils);
    sx += x;
    sy += y;
    sxx += x * x;
    sxy += x * y;
  }
  LinearFit f;
  f.slope = (n * sxy - sx * sy) / (n * sxx - sx * sx);
  f.intercept = (sy - f.slope * sx) / n;
  for (const auto& [coils, y] : step_times)
    f.worst_residual =
        std::max(f.worst_residual, std::abs(y - (f.intercept + f.slope * static_cast<double>(coils))) / y);
  return f;
}

void BM_TrainStep(benchmark::State& state) {
  const int coils = static_cast<int>(state.range(0));
  const camdyn::SceneConfig scene = bucket_tappet(coils);
  const camdyn::Model model = camdyn::build_model(scene, "bucket tappet");
  camdyn::Workspace ws = camdyn::make_workspace(model);
  camdyn::SimulationOptions options;
  options.record_series = false;
  camdyn::SolverCounters counters;
  long seat_impacts = 0;
  double seconds = 0.0;  // CPU time of the runs [s]
  for (auto _ : state) {
    const double start = cpu_seconds();
    const camdyn::SimulationResult r = camdyn::simulate(scene, model, ws, options);
    seconds += cpu_seconds() - start;
    camdyn::throw_if_failed(r);
    counters = r.solver.counters;
    seat_impacts = r.metrics.train ? r.metrics.train->seat_impacts : 0;
    benchmark::DoNotOptimize(r.metrics.peak_contact_force);
  }
  const double revolutions = scene.simulation.cycles.value_or(1.0);
  const auto steps = static_cast<double>(std::max(1L, counters.steps));
  const double step_time = seconds / static_cast<double>(state.iterations()) / steps;  // [s]
  if (coils == 0)
    massless_step_time = step_time;
  else
    step_times[coils] = step_time;  // the last of Google Benchmark's runs of the case
  state.SetLabel(coils == 0 ? "massless spring" : std::to_string(coils) + " coils");
  state.counters["states"] = static_cast<double>(model.layout.size);
  state.counters["steps_per_rev"] = steps / revolutions;
  state.counters["rhs_per_step"] = static_cast<double>(counters.rhs_evaluations) / steps;
  state.counters["jacobians_per_step"] = static_cast<double>(counters.jacobian_evaluations) / steps;
  state.counters["newton_per_step"] = static_cast<double>(counters.nonlinear_iterations) / steps;
  state.counters["seat_impacts"] = static_cast<double>(seat_impacts);
  state.counters["s_per_step"] =
      benchmark::Counter(steps, benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
  state.counters["s_per_rev"] =
      benchmark::Counter(revolutions, benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
  if (massless_step_time) {
    state.counters["step_cost_vs_massless"] = step_time / *massless_step_time;
    // The cost a coil adds to a step: constant if the cost is linear in the coils.
    if (coils > 0) state.counters["s_per_step_per_coil"] = (step_time - *massless_step_time) / coils;
  }
  // From the third case with coils on (16), the line through them (4, 8, 16
  // coils: the banded solve; the massless spring is a 3-state dense one).
  if (step_times.size() >= 3) {
    const LinearFit fit = fit_step_times();
    state.counters["fit_s_per_step_per_coil"] = fit.slope;
    state.counters["fit_s_per_step_no_coils"] = fit.intercept;
    state.counters["fit_worst_relative_residual"] = fit.worst_residual;
  }
}
BENCHMARK(BM_TrainStep)->Arg(0)->Arg(4)->Arg(8)->Arg(16)->Unit(benchmark::kMillisecond)->MinTime(2.0);

}  // namespace

BENCHMARK_MAIN();
