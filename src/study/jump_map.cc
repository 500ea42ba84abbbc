#include "study/jump_map.h"

#include <algorithm>
#include <cmath>
#include <complex>
#include <limits>
#include <memory>
#include <optional>

#include "common/errors.h"
#include "common/parallel.h"
#include "common/study_budget.h"
#include "dynamics/model.h"
#include "dynamics/poincare_map.h"
#include "dynamics/rigid_jump_speed.h"
#include "dynamics/train_jump_speed.h"
#include "io/json_writer.h"
#include "study/progress.h"

namespace camdyn {

/// What a speed of the map holds to the end of the study: its analysis and
/// journal record [bytes], and each of its samples (section point, impacts).
constexpr double kBytesPerSpeed = 4096.0;
constexpr double kBytesPerSample = 256.0;

template <class A>
void visit(A& a, JumpMapConfig& c) {
  a.field("low_rpm", c.low_rpm, at_least(kMinCamRpm), open_closed(0, kMaxCamRpm));
  a.field("high_rpm", c.high_rpm, at_least(kMinCamRpm), open_closed(0, kMaxCamRpm));
  a.field("speeds", c.speeds, at_least(2));
  a.field("ranges", c.ranges, at_least(1));
  a.field("transient_revolutions", c.transient_revolutions, at_least(1));
  a.field("samples", c.samples, at_least(1));
  a.field("warm_start", c.warm_start);
  a.field("check_coexistence", c.check_coexistence);
  a.field("refine", c.refine, at_least(0));
  a.require(c.refine <= kMaxRefineLevels, "refine",
            "must be at most " + std::to_string(kMaxRefineLevels) + " levels, got " + std::to_string(c.refine));
  a.require(c.high_rpm > c.low_rpm, "high_rpm", "must be above low_rpm");
  // Work bounds: each speed's run, and the samples of every speed held to the end.
  a.require(static_cast<double>(c.transient_revolutions) + c.samples <= kMaxRevolutionsPerRun, "samples",
            "transient_revolutions + samples asks for " +
                format_shortest(static_cast<double>(c.transient_revolutions) + c.samples) +
                " revolutions at each speed (at most " + format_shortest(kMaxRevolutionsPerRun) + ")");
  // Each change between neighbours may add `refine` speeds.
  const double held = static_cast<double>(c.speeds) + static_cast<double>(c.speeds - 1) * c.refine;
  const double bytes = held * (kBytesPerSpeed + kBytesPerSample * c.samples);
  a.require(bytes <= memory_budget_bytes(), "speeds",
            std::to_string(c.speeds) + " speeds of " + std::to_string(c.samples) + " samples need about " +
                format_shortest(std::ceil(bytes / kBytesPerMb)) + " MB: " + memory_budget_text());
}

namespace {

const std::vector<std::string> kJumpMapKeys = {"jump_map", "periodic"};

// The section samples after the transient: `samples` revolutions from `from`,
// the state sampled once per revolution, the metrics over every step.
SimulationResult sample_run(const PoincareMap& map, const SectionPoint& from, int samples) {
  SimulationOptions options;
  options.record_series = false;
  options.start = std::make_shared<const StartState>(map.start(from));
  for (int j = 1; j <= samples; ++j) options.sample_times.push_back(j * map.period());
  Workspace ws = make_workspace(map.model());
  SimulationResult r = simulate(map.scene_for(samples), map.model(), ws, options);
  throw_if_failed(r);
  return r;
}

// A stable orbit a speed converged to: what the next speeds predict theirs from.
struct ConvergedOrbit {
  double rpm = 0.0;  ///< [rpm]
  int period = 0;    ///< [revolutions]
  SectionPoint fixed_point;
  Eigen::MatrixXd monodromy;  ///< ∂P^k/∂x at fixed_point
};

// What a range carries from one speed to the next: the motion's end (the
// transient path's start) and the last stable orbits of one period, oldest
// first (at most two: the secant's).
struct Continuation {
  std::optional<SectionPoint> carry;
  std::vector<ConvergedOrbit> orbits;
  /// The speed below reached no stable orbit: the next one's Lyapunov run
  /// comes first (PeriodicOptions::lyapunov_first; when it does not find
  /// chaos, the orbit search follows and its estimate is kept, so it costs
  /// nothing then).
  bool aperiodic = false;
};

// The fixed point predicted at `rpm`: the secant in rpm through the last two
// orbits, or the last orbit's own fixed point when there is one.
SectionPoint predicted_fixed_point(const std::vector<ConvergedOrbit>& orbits, double rpm) {
  const ConvergedOrbit& last = orbits.back();
  SectionPoint p = last.fixed_point;
  if (orbits.size() < 2) return p;
  const ConvergedOrbit& before = orbits[orbits.size() - 2];
  const double s = (rpm - last.rpm) / (last.rpm - before.rpm);  // [-]
  for (std::size_t j = 0; j < p.x.size(); ++j) p.x[j] += s * (last.fixed_point.x[j] - before.fixed_point.x[j]);
  return p;
}

// Of the k section points of a period-k orbit, the one nearest `reference`
// (the previous speed's fixed point, scaled by the map's scales): Newton may
// land on any of them, and a secant through two different ones predicts
// nothing.
SectionPoint nearest_phase(const PoincareMap& map, const SectionPoint& fixed_point, int period,
                           const SectionPoint& reference, Workspace& ws) {
  auto distance = [&](const SectionPoint& p) {
    double d = 0.0;
    for (std::size_t j = 0; j < p.x.size(); ++j) d = std::max(d, std::abs(p.x[j] - reference.x[j]) / map.scales()[j]);
    return d;
  };
  SectionPoint best = fixed_point, p = fixed_point;
  for (int j = 1; j < period; ++j) {
    const MapResult r = map.apply(p, 1, ws);
    if (!r.ok) return fixed_point;
    p = r.end;
    if (distance(p) < distance(best)) best = p;
  }
  return best;
}

// The point's metrics from those of the run over its samples.
void fill_metrics(JumpMapPoint& p, const Metrics& m) {
  p.separation_fraction = m.separation_fraction;
  if (m.train) {
    p.link_separation_fraction = m.train->link_separation_fraction;
    p.seat_bounces = m.train->seat_bounces;
  }
  p.floats = p.floats || separates(m);
  if (p.float_cause.empty()) p.float_cause = separation_place(m);
  if (p.floats && p.float_cause.empty()) p.float_cause = "float";  // an impact that ends a float
  p.max_gap = m.max_separation_gap;
  p.peak_contact_force = m.peak_contact_force;
}

// The point's motion, samples and metrics from `samples`, the run from the
// analysis' orbit or start.
void fill_from_run(JumpMapPoint& p, const SimulationResult& samples) {
  for (const ContactEvent& e : samples.events)
    if (e.onset && e.impact) {
      p.impact_angle_deg.push_back(std::fmod(e.cam_angle_deg, 360.0));
      p.impact_speed.push_back(e.speed);
      p.floats = p.floats || floats(e.cause);
    }
  p.section_position = samples.samples.follower_position;
  fill_metrics(p, samples.metrics);
}

// A periodic orbit's `samples` section samples and their impacts from one
// period (`cycle`, `period` revolutions from the fixed point), repeated: the
// same as `samples` revolutions would give, within the shooting tolerance.
void fill_from_cycle(JumpMapPoint& p, const SimulationResult& cycle, const PoincareMap& map, int period, int samples) {
  const std::vector<double>& positions = cycle.samples.follower_position;
  std::vector<std::vector<std::size_t>> impacts_in(static_cast<std::size_t>(period));  // by revolution of the cycle
  for (std::size_t i = 0; i < cycle.events.size(); ++i) {
    const ContactEvent& e = cycle.events[i];
    if (!e.onset || !e.impact) continue;
    p.floats = p.floats || floats(e.cause);
    const int revolution = std::clamp(static_cast<int>(std::floor(e.time / map.period())), 0, period - 1);
    impacts_in[static_cast<std::size_t>(revolution)].push_back(i);
  }
  for (int j = 0; j < samples; ++j) {
    const std::size_t r = static_cast<std::size_t>(j % period);
    if (r < positions.size()) p.section_position.push_back(positions[r]);
    for (const std::size_t i : impacts_in[r]) {
      p.impact_angle_deg.push_back(std::fmod(cycle.events[i].cam_angle_deg, 360.0));
      p.impact_speed.push_back(cycle.events[i].speed);
    }
  }
  fill_metrics(p, cycle.metrics);
}

// Chord iterations on P^k(x) − x = 0 from `x` with the neighbour's
// monodromy M in place of this speed's (whose 2n map evaluations a Newton
// step would cost): x ← x − (M − I)⁻¹ (P^k(x) − x) while the scaled residual
// falls, at most kChordIterations map evaluations. Returns the point of least
// residual evaluated (x itself when nothing helped); the shooting confirms it.
constexpr int kChordIterations = 4;
SectionPoint chord_iterations(const PoincareMap& map, SectionPoint x, const ConvergedOrbit& neighbour,
                              double tolerance) {
  const Eigen::Index n = map.dimension();
  if (neighbour.monodromy.rows() != n || neighbour.monodromy.cols() != n) return x;
  const Eigen::FullPivLU<Eigen::MatrixXd> lu(neighbour.monodromy - Eigen::MatrixXd::Identity(n, n));
  if (!lu.isInvertible()) return x;
  Workspace ws = make_workspace(map.model());
  double best = std::numeric_limits<double>::infinity();
  SectionPoint kept = x;  // the point of least residual so far
  for (int it = 0; it < kChordIterations; ++it) {
    const MapResult image = map.apply(x, neighbour.period, ws);
    if (!image.ok) return kept;
    Eigen::VectorXd residual(n);
    double norm = 0.0;  // max |R_j| / scale_j [-]
    for (Eigen::Index j = 0; j < n; ++j) {
      const auto u = static_cast<std::size_t>(j);
      residual[j] = image.end.x[u] - x.x[u];
      norm = std::max(norm, std::abs(residual[j]) / map.scales()[u]);
    }
    if (!(norm < best)) return kept;
    best = norm;
    kept = x;
    if (norm <= tolerance) return kept;
    const Eigen::VectorXd step = lu.solve(-residual);
    if (!step.allFinite()) return kept;
    for (Eigen::Index j = 0; j < n; ++j) x.x[static_cast<std::size_t>(j)] += step[j];
    x.approach_speed = image.end.approach_speed;
  }
  return kept;
}

// The warm start: the chord iterations (period 1) and Newton from the
// predicted fixed point at the predicted period only (past a period
// doubling, shooting period 1 first found the unstable orbit the
// neighbours' doubled from, at the cost of a period-1 search per speed); the
// orbit when it is stable and that is its minimal period (else the transient path decides: the
// shortcut only reports a stable orbit the shooting confirmed; where two
// stable orbits coexist it keeps to the one continued from the neighbours,
// docs/periodic.md "Warm start").
std::optional<Orbit> shoot_predicted(const PoincareMap& map, const JumpMapStudy& study, const Continuation& c,
                                     double rpm) {
  PeriodicOptions options = study.periodic.options;
  options.threads = study.threads_per_speed;
  options.max_period = c.orbits.back().period;
  options.min_period = options.max_period;
  options.lyapunov_revolutions = 0;
  options.reach_revolutions = 0;  // the branch continued from the neighbours, not a motion's end
  SectionPoint start = predicted_fixed_point(c.orbits, rpm);
  // A period-k orbit's monodromy is the neighbour's at its own phase only for k = 1.
  if (options.max_period == 1) start = chord_iterations(map, std::move(start), c.orbits.back(), options.tolerance);
  const PeriodicAnalysis a = find_periodic_orbit(map, start, options);
  if (!a.orbit || !a.orbit->stable || a.orbit->period != options.max_period) return std::nullopt;
  return a.orbit;
}

// A stable orbit as one of a speed's attractors, reached as `reached`.
JumpMapAttractor periodic_attractor(int period, const SectionPoint& fixed_point,
                                    const std::vector<std::complex<double>>& multipliers, JumpMapReach reached,
                                    MotionKind motion = MotionKind::periodic) {
  JumpMapAttractor a;
  a.reached = reached;
  a.motion = motion;
  a.period = period;
  a.fixed_point = fixed_point.x;
  a.approach_speed = fixed_point.approach_speed;
  a.spectral_radius = multipliers.empty() ? 0.0 : std::abs(multipliers.front());
  for (const std::complex<double>& mu : multipliers) {
    a.multipliers_re.push_back(mu.real());
    a.multipliers_im.push_back(mu.imag());
  }
  return a;
}

// The present path: the transient from the neighbour's end (or from the
// scene's own start), the periodic analysis, `samples` revolutions from its
// orbit (or from where the transient ended).
JumpMapPoint transient_path(const JumpMapStudy& study, const PoincareMap& map, double rpm, Continuation& c,
                            std::optional<Orbit>& orbit) {
  Workspace ws = make_workspace(map.model());
  const int transient = study.config.transient_revolutions;
  SectionPoint start;
  if (c.carry) {
    const MapResult r = map.apply(*c.carry, transient, ws);
    if (!r.ok) throw NumericalError(r.message);
    start = r.end;
  } else {
    SimulationOptions options;
    options.record_series = false;
    options.step_metrics = false;
    options.quadratures = false;  // the transient's end state is all it gives
    const SimulationResult r = simulate(map.scene_for(transient), map.model(), ws, options);
    throw_if_failed(r);
    start = map.point(r);
  }
  PeriodicOptions options = study.periodic.options;
  options.threads = study.threads_per_speed;
  options.lyapunov_first = c.aperiodic;
  PeriodicAnalysis a;
  std::optional<SimulationResult> run;
  if (options.lyapunov_first && options.threads > 1) {
    // The motion is expected aperiodic, so its samples start where the
    // transient ended: they run beside the analysis, and again from the
    // orbit (or after a failure) only if it finds one.
    parallel_for(2, 2, [&](std::size_t i) {
      if (i == 0) a = analyse_from(map, start, options);
      if (i != 1) return;
      try {
        run = sample_run(map, start, study.config.samples);
      } catch (const NumericalError&) {
        // run again below, where a failure is the speed's
      }
    });
    if (a.orbit) run.reset();
  } else {
    a = analyse_from(map, start, options);
  }
  if (!run) run = sample_run(map, a.orbit ? a.orbit->fixed_point : start, study.config.samples);
  const SimulationResult& samples = *run;
  JumpMapPoint p;
  p.rpm = rpm;
  p.ok = true;
  p.start = JumpMapStart::transient;
  p.motion = a.motion;
  if (a.orbit) {
    p.period = a.orbit->period;
    p.spectral_radius = a.orbit->spectral_radius();
  }
  if (a.lyapunov) {
    p.lyapunov = a.lyapunov->per_revolution;
    p.lyapunov_standard_error = a.lyapunov->standard_error;
    p.lyapunov_fallback_revolutions = a.lyapunov->fallback_revolutions;
  }
  if (!a.unreached_orbits.empty() && (a.orbit || a.motion == MotionKind::chaotic)) {
    // Newton found stable orbits the motion does not go to: they coexist
    // with it (a motion that settles nowhere clear is no attractor to set beside them).
    p.coexisting = true;
    if (a.orbit) {
      p.attractors.push_back(
          periodic_attractor(a.orbit->period, a.orbit->fixed_point, a.orbit->multipliers, JumpMapReach::continuation));
    } else {
      JumpMapAttractor own;
      own.motion = a.motion;
      p.attractors.push_back(std::move(own));
    }
    for (const Orbit& o : a.unreached_orbits)
      p.attractors.push_back(periodic_attractor(o.period, o.fixed_point, o.multipliers, JumpMapReach::shooting));
  }
  fill_from_run(p, samples);
  c.carry = map.point(samples);
  orbit = std::move(a.orbit);
  return p;
}

// The model a range runs its speeds on (one range runs them one at a time):
// a copy of the study's, its speed set in place at each speed, or without
// one (JumpMapStudy::model null) a model assembled at each speed.
class RangeModel {
 public:
  explicit RangeModel(const JumpMapStudy& study) : study_(study) {
    if (study.model) model_ = *study.model;
  }
  /// The model at `scene`'s speed (the study's scene at another speed); valid until the next call.
  const Model& at(const SceneConfig& scene, const std::string& file) {
    if (study_.model)
      set_cam_speed(*model_, scene, file);
    else
      model_ = build_model(study_.geometry, scene, file);
    return *model_;
  }

 private:
  const JumpMapStudy& study_;
  std::optional<Model> model_;
};

// One speed: shot from the predicted orbit when the neighbours converged to a
// stable one (study.config.warm_start), else (or when that fails) the
// transient path; `c` carries this speed's end and orbit to the next.
JumpMapPoint run_speed(const JumpMapStudy& study, double rpm, const std::string& file, Continuation& c,
                       RangeModel& range) {
  SceneConfig scene = study.scene;
  scene.mechanism.cam.rpm = rpm;
  const Model& model = range.at(scene, file);
  const PoincareMap map(scene, model, file);
  std::optional<Orbit> orbit;
  if (study.config.warm_start && !c.orbits.empty()) orbit = shoot_predicted(map, study, c, rpm);
  JumpMapPoint p;
  if (orbit) {
    const SimulationResult cycle = sample_run(map, orbit->fixed_point, orbit->period);
    p.rpm = rpm;
    p.ok = true;
    p.start = JumpMapStart::predicted;
    p.motion = MotionKind::periodic;
    p.period = orbit->period;
    p.spectral_radius = orbit->spectral_radius();
    fill_from_cycle(p, cycle, map, orbit->period, study.config.samples);
    c.carry = map.point(cycle);
  } else {
    p = transient_path(study, map, rpm, c, orbit);
  }
  c.aperiodic = p.ok && p.motion != MotionKind::periodic;
  if (!orbit || !orbit->stable) {
    c.orbits.clear();
    return p;
  }
  ConvergedOrbit now{rpm, orbit->period, orbit->fixed_point, orbit->monodromy};
  if (!c.orbits.empty() && c.orbits.back().period == now.period) {
    if (now.period > 1) {
      Workspace ws = make_workspace(model);
      now.fixed_point = nearest_phase(map, now.fixed_point, now.period, c.orbits.back().fixed_point, ws);
    }
    if (c.orbits.size() == 2) c.orbits.erase(c.orbits.begin());
  } else {
    c.orbits.clear();
  }
  c.orbits.push_back(std::move(now));
  return p;
}

}  // namespace

JumpMapStudy read_jump_map_study(const Json& doc, const StudyContext& ctx) {
  JumpMapStudy study;
  Json part;
  study.scene = scene_from_study_json(doc, ctx.source, kJumpMapKeys, part);
  const Json fields = read_study_fields(part, "jump_map", ctx.source, study.config);
  study.periodic.options.lyapunov_revolutions = 100;  // per speed: a shorter default than the periodic study's
  study.periodic.options.settle_revolutions = 300;    // likewise: a contracting speed is followed 200 more
  const Json periodic = read_study_fields(part, "periodic", ctx.source, study.periodic);
  study.periodic.options.stable_orbits_only = true;  // a speed's class needs its stable orbit only
  study.geometry = build_cam_geometry(study.scene, ctx.config_file);
  study.model = std::make_shared<const Model>(build_model(*study.geometry, study.scene, ctx.config_file));
  const Model& model = *study.model;
  const PoincareMap map(study.scene, model, ctx.config_file);  // the drive sets the speed
  study.rigid_jump_speed_rpm = model_jump_speed_rpm(model);
  study.damped_rigid_jump_speed_rpm =
      model.train.has_coordinates() ? study.rigid_jump_speed_rpm : damped_jump_speed_rpm(model);
  study.jump_speed_name = jump_speed_name(model);
  study.section_dimension = map.dimension();
  study.threads_per_speed = ctx.threads();
  const JumpMapConfig& c = study.config;
  for (int i = 0; i < c.speeds; ++i) study.rpm.push_back(c.low_rpm + (c.high_rpm - c.low_rpm) * i / (c.speeds - 1));
  study.resolved = resolved_study_json(study.scene, "jump_map", Json{{"jump_map", fields}, {"periodic", periodic}});
  return study;
}

namespace {

// The contiguous ranges of the grid: as many as asked, at most one a speed.
std::size_t range_count(const JumpMapStudy& study) {
  return std::min(study.rpm.size(), static_cast<std::size_t>(study.config.ranges));
}

// The index of range r's first speed (r = range_count: one past the last speed).
std::size_t range_start(const JumpMapStudy& study, std::size_t r) { return r * study.rpm.size() / range_count(study); }

}  // namespace

std::vector<std::size_t> jump_map_range(const JumpMapStudy& study, std::size_t r) {
  std::vector<std::size_t> indices;
  for (std::size_t i = range_start(study, r); i < range_start(study, r + 1); ++i) indices.push_back(i);
  return indices;
}

double jump_map_speed_work(const JumpMapStudy& study, std::size_t i) {
  const double jacobian = 1.0 + 2.0 * study.section_dimension;  // [revolutions]
  const double rpm = study.rpm.at(i);
  const bool past_jump = std::isfinite(study.damped_rigid_jump_speed_rpm) && rpm >= study.damped_rigid_jump_speed_rpm;
  // The first speed of a range has no neighbour to start from.
  bool first_of_range = false;
  for (std::size_t r = 0; r < range_count(study) && !first_of_range; ++r) first_of_range = range_start(study, r) == i;
  if (study.config.warm_start && !past_jump && !first_of_range) return jacobian + 3.0;
  const double transient_path = study.config.transient_revolutions + study.config.samples + 2.0 * jacobian;
  return past_jump ? transient_path + 2.0 * study.periodic.options.lyapunov_revolutions : transient_path;
}

namespace {

// Two speeds of one class: both ran, the same kind of motion, and the same period.
bool same_class(const JumpMapPoint& a, const JumpMapPoint& b) {
  return a.ok == b.ok && a.motion == b.motion && a.period == b.period;
}

// Between neighbouring grid speeds of different classes, study.config.refine
// speeds by bisection, each run from the continuation of the speed below
// it: each halves the bracket of the change. Appended to `points` (marked
// refined); a speed that fails or the study's budget ends that bracket.
void refine_range(const JumpMapStudy& study, const std::string& file, std::vector<JumpMapPoint>& points,
                  std::vector<Continuation>& after, RangeModel& range) {
  const std::size_t grid = points.size();
  for (std::size_t j = 0; j + 1 < grid; ++j) {
    if (!points[j].ok || !points[j + 1].ok || same_class(points[j], points[j + 1])) continue;
    JumpMapPoint below = points[j];
    const JumpMapPoint above = points[j + 1];
    Continuation from = after[j];
    double lo = below.rpm, hi = above.rpm;  // [rpm]
    for (int level = 0; level < study.config.refine && !study_budget_exhausted(); ++level) {
      const double mid = 0.5 * (lo + hi);
      Continuation c = from;
      JumpMapPoint p;
      try {
        p = run_speed(study, mid, file, c, range);
      } catch (const std::exception&) {
        break;  // the bracket stays as the speeds that ran leave it
      }
      p.refined = true;
      points.push_back(p);
      after.push_back(c);
      if (same_class(below, p)) {
        lo = mid;
        below = std::move(p);
        from = std::move(c);
      } else {
        hi = mid;
      }
    }
  }
  // Both in rpm order, the continuations beside their points.
  std::vector<std::size_t> order(points.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return points[a].rpm < points[b].rpm; });
  std::vector<JumpMapPoint> sorted_points;
  std::vector<Continuation> sorted_after;
  for (const std::size_t i : order) {
    sorted_points.push_back(std::move(points[i]));
    sorted_after.push_back(std::move(after[i]));
  }
  points = std::move(sorted_points);
  after = std::move(sorted_after);
}

// Coexisting attractors (docs/periodic.md "Coexisting attractors").

// The stable orbit point `p` reached along its continuation, as `c` (what it
// handed on) holds it; null when it reached none.
const ConvergedOrbit* own_orbit(const JumpMapPoint& p, const Continuation& c) {
  if (!p.ok || c.orbits.empty() || c.orbits.back().rpm != p.rpm) return nullptr;
  return &c.orbits.back();
}

// The k section points of a period-k orbit from its fixed point; empty when
// one cannot be computed.
std::vector<std::vector<double>> orbit_phases(const PoincareMap& map, SectionPoint x, int period) {
  Workspace ws = make_workspace(map.model());
  std::vector<std::vector<double>> phases{x.x};
  for (int j = 1; j < period; ++j) {
    const MapResult r = map.apply(x, 1, ws);
    if (!r.ok) return {};
    x = r.end;
    phases.push_back(x.x);
  }
  return phases;
}

// Whether every point of `of` lies within `near` (scaled) of a point of `in`.
bool phases_within(const PoincareMap& map, const std::vector<std::vector<double>>& of,
                   const std::vector<std::vector<double>>& in, double near) {
  for (const std::vector<double>& x : of) {
    double least = std::numeric_limits<double>::infinity();  // [-]
    for (const std::vector<double>& y : in) least = std::min(least, map.scaled_distance(x, y));
    if (!(least < near)) return false;
  }
  return true;
}

// Whether `o` is the attractor `a` (a stable orbit): every section point of
// each within 1e3 shooting tolerances (scaled) of one of the other's, the
// shooting's own test for an orbit found before (study/periodic_orbit.cc).
// Of another period too: an orbit of period 2 whose two points both lie that
// near a period-1 orbit's is the same motion seen through the map's
// integration noise (the quickstart near 1214.6 rpm: period 1, 2 and 3
// "orbits" 1e-6 apart with the same impacts every revolution, followed on).
// A phase that cannot be computed counts as the same: coexistence is only
// claimed when shown.
bool same_orbit(const PoincareMap& map, const JumpMapAttractor& a, const Orbit& o, double tolerance) {
  if (a.period <= 0 || a.fixed_point.size() != o.fixed_point.x.size()) return false;
  SectionPoint from_a = o.fixed_point;
  from_a.x = a.fixed_point;
  from_a.approach_speed = a.approach_speed;
  const std::vector<std::vector<double>> pa = orbit_phases(map, from_a, a.period),
                                         po = orbit_phases(map, o.fixed_point, o.period);
  if (pa.empty() || po.empty()) return true;
  const double near = 1e3 * tolerance;
  return phases_within(map, pa, po, near) && phases_within(map, po, pa, near);
}

// A stable orbit from a transient of transient_revolutions from `carry`, the
// motion of the speed below, as the transient path (warm_start false) takes
// it; no Lyapunov run: only a stable orbit counts.
std::optional<Orbit> transient_orbit(const JumpMapStudy& study, const PoincareMap& map, const SectionPoint& carry) {
  Workspace ws = make_workspace(map.model());
  const MapResult r = map.apply(carry, study.config.transient_revolutions, ws);
  if (!r.ok) throw NumericalError(r.message);
  PeriodicOptions options = study.periodic.options;
  options.threads = study.threads_per_speed;
  options.lyapunov_revolutions = 0;
  PeriodicAnalysis a = find_periodic_orbit(map, r.end, options);
  return std::move(a.orbit);
}

// The neighbour's stable orbit shot at `rpm`: the warm start's prediction,
// chord iterations and shooting, but any stable orbit the shooting converges
// to, of any period up to periodic.max_period, is an attractor of this speed.
std::optional<Orbit> shoot_across(const PoincareMap& map, const JumpMapStudy& study, const Continuation& c,
                                  double rpm) {
  PeriodicOptions options = study.periodic.options;
  options.threads = study.threads_per_speed;
  options.lyapunov_revolutions = 0;
  options.reach_revolutions = 0;  // any stable orbit there is an attractor of the speed
  SectionPoint start = predicted_fixed_point(c.orbits, rpm);
  if (c.orbits.back().period == 1) start = chord_iterations(map, std::move(start), c.orbits.back(), options.tolerance);
  PeriodicAnalysis a = find_periodic_orbit(map, start, options);
  return std::move(a.orbit);
}

// A speed next to a change of class: the stable orbits of its neighbours
// across the change (each with how it would be reached).
struct AcrossOrbit {
  ConvergedOrbit orbit;
  JumpMapReach reached = JumpMapReach::from_below;
};

// Looks for attractors of speed `p` besides the one its continuation `own`
// reached: each neighbour's orbit in `across` shot at p's speed (the
// hysteresis check), and, when p was reached the warm way, the transient
// path from the motion of the speed below (`below_carry`). Two or more: p is
// coexisting, with every one listed.
void look_for_attractors(const JumpMapStudy& study, const std::string& file, JumpMapPoint& p, const Continuation& own,
                         const std::vector<AcrossOrbit>& across, const std::optional<SectionPoint>& below_carry,
                         RangeModel& range) {
  // Only a stable orbit or a chaotic motion is an attractor to set beside a stable orbit.
  const ConvergedOrbit* own_stable = own_orbit(p, own);
  if (!own_stable && p.motion != MotionKind::chaotic) return;
  SceneConfig scene = study.scene;
  scene.mechanism.cam.rpm = p.rpm;
  const PoincareMap map(scene, range.at(scene, file), file);
  const double tolerance = study.periodic.options.tolerance;
  std::vector<JumpMapAttractor> found;
  if (p.coexisting) {
    found = p.attractors;  // the motion's own, then the stable orbits it did not reach
  } else if (const ConvergedOrbit* o = own_stable) {
    found.push_back(periodic_attractor(o->period, o->fixed_point, floquet_multipliers(o->monodromy),
                                       JumpMapReach::continuation, p.motion));
  } else {
    JumpMapAttractor a;
    a.motion = p.motion;
    a.spectral_radius = p.spectral_radius;
    found.push_back(std::move(a));
  }
  auto add = [&](const std::optional<Orbit>& o, JumpMapReach reached) {
    if (!o || !o->stable) return;
    for (const JumpMapAttractor& a : found)
      if (same_orbit(map, a, *o, tolerance)) return;
    found.push_back(periodic_attractor(o->period, o->fixed_point, o->multipliers, reached));
  };
  for (const AcrossOrbit& a : across) {
    if (study_budget_exhausted()) return;
    Continuation c;
    c.orbits.push_back(a.orbit);
    add(shoot_across(map, study, c, p.rpm), a.reached);
  }
  if (p.start == JumpMapStart::predicted && below_carry && !study_budget_exhausted())
    add(transient_orbit(study, map, *below_carry), JumpMapReach::transient);
  if (found.size() < 2) return;
  p.coexisting = true;
  p.attractors = std::move(found);
}

// At every change of class between neighbouring speeds of the range (points
// in rpm order, `after` what each handed on), the hysteresis check: each
// side's stable orbit continued one step across, and the transient path where
// the warm start was used. A check that fails finds nothing.
void check_coexistence(const JumpMapStudy& study, const std::string& file, std::vector<JumpMapPoint>& points,
                       const std::vector<Continuation>& after, RangeModel& range) {
  std::vector<std::vector<AcrossOrbit>> across(points.size());
  std::vector<bool> at_change(points.size(), false);
  for (std::size_t j = 0; j + 1 < points.size(); ++j) {
    if (!points[j].ok || !points[j + 1].ok || same_class(points[j], points[j + 1])) continue;
    at_change[j] = at_change[j + 1] = true;
    if (const ConvergedOrbit* below = own_orbit(points[j], after[j]))
      across[j + 1].push_back({*below, JumpMapReach::from_below});
    if (const ConvergedOrbit* above = own_orbit(points[j + 1], after[j + 1]))
      across[j].push_back({*above, JumpMapReach::from_above});
    // The stable orbits a speed's own motion did not reach are shot across too.
    for (const std::size_t side : {j, j + 1}) {
      for (const JumpMapAttractor& a : points[side].attractors) {
        if (a.reached != JumpMapReach::shooting) continue;
        const ConvergedOrbit orbit{points[side].rpm, a.period, SectionPoint{a.fixed_point, a.approach_speed, 0.0}, {}};
        if (side == j)
          across[j + 1].push_back({orbit, JumpMapReach::from_below});
        else
          across[j].push_back({orbit, JumpMapReach::from_above});
      }
    }
  }
  for (std::size_t j = 0; j < points.size(); ++j) {
    if (!at_change[j] || study_budget_exhausted()) continue;
    std::optional<SectionPoint> below_carry;
    if (j > 0) below_carry = after[j - 1].carry;
    try {
      look_for_attractors(study, file, points[j], after[j], across[j], below_carry, range);
    } catch (const std::exception&) {
      // A run that failed shows no attractor: the speed keeps its one class.
    }
  }
}

}  // namespace

std::vector<JumpMapPoint> run_jump_map_range(const JumpMapStudy& study, std::size_t r, const std::string& file) {
  std::vector<JumpMapPoint> points;
  std::vector<Continuation> after;  // what each grid speed hands on
  Continuation continuation;
  RangeModel range(study);
  for (const std::size_t i : jump_map_range(study, r)) {
    if (study_budget_exhausted()) {
      JumpMapPoint p;
      p.rpm = study.rpm[i];
      p.error = study_budget_text() + " before this speed";
      p.budget = "--max-study-time";
      points.push_back(std::move(p));
      after.push_back(continuation);
      continue;
    }
    try {
      points.push_back(run_speed(study, study.rpm[i], file, continuation, range));
    } catch (const std::exception& e) {
      JumpMapPoint p;
      p.rpm = study.rpm[i];
      p.error = e.what();
      p.budget = budget_that_cut(p.error);
      points.push_back(std::move(p));
      continuation = Continuation{};  // the next speed starts afresh
    }
    after.push_back(continuation);
    report_work_done(jump_map_speed_work(study, i));  // the progress line's unit: expected revolutions
  }
  if (study.config.refine > 0) refine_range(study, file, points, after, range);
  if (study.config.check_coexistence) check_coexistence(study, file, points, after, range);
  return points;
}

JumpMapLimit jump_map_limit(const std::vector<JumpMapPoint>& points) {
  JumpMapLimit limit;
  for (const JumpMapPoint& p : points) {  // in rpm order
    if (!p.ok) continue;
    if (p.floats && !limit.rpm) {
      limit.rpm = p.rpm;
      limit.cause = p.float_cause.empty() ? "float" : p.float_cause;
    }
    if (p.seat_bounces > 0 && !limit.seat_bounce_rpm) limit.seat_bounce_rpm = p.rpm;
  }
  return limit;
}

std::vector<JumpMapTransition> jump_map_transitions(const std::vector<JumpMapPoint>& points) {
  std::vector<JumpMapTransition> t;
  const JumpMapPoint* previous = nullptr;
  for (const JumpMapPoint& p : points) {
    if (!p.ok) continue;
    if (p.coexisting) {
      const int first = p.attractors.front().period, second = p.attractors[1].period;
      t.push_back({"coexistence", p.rpm, p.rpm, first, second});
    }
    if (previous) {
      const JumpMapPoint& a = *previous;
      const bool left_a = a.floats, left_b = p.floats;
      const int pa = a.motion == MotionKind::periodic ? a.period : 0;
      const int pb = p.motion == MotionKind::periodic ? p.period : 0;
      auto add = [&](const char* kind) { t.push_back({kind, a.rpm, p.rpm, pa, pb}); };
      if (!left_a && left_b) add("separation");
      if (left_a && !left_b) add("reattachment");
      // A coexisting speed has no single class: no change of class is stated to or from it.
      if (a.coexisting || p.coexisting) {
        previous = &p;
        continue;
      }
      if (pa > 0 && pb > 0 && pa != pb)
        add(pb == 2 * pa ? "period_doubling" : pb == pa + 1 ? "period_adding" : "period_change");
      if (a.motion != MotionKind::chaotic && p.motion == MotionKind::chaotic) add("chaos_onset");
      if (a.motion == MotionKind::chaotic && p.motion != MotionKind::chaotic) add("chaos_end");
    }
    previous = &p;
  }
  return t;
}

Json jump_map_point_json(const JumpMapPoint& p) {
  Json attractors = Json::array();
  for (const JumpMapAttractor& a : p.attractors)
    attractors.push_back(Json{{"reached", to_string(a.reached)},
                              {"motion", to_string(a.motion)},
                              {"period", a.period},
                              {"spectral_radius", a.spectral_radius},
                              {"fixed_point", a.fixed_point},
                              {"approach_speed", a.approach_speed},
                              {"floquet_multipliers", Json{{"re", a.multipliers_re}, {"im", a.multipliers_im}}}});
  return Json{{"rpm", p.rpm},
              {"ok", p.ok},
              {"start", to_string(p.start)},
              {"refined", p.refined},
              {"error", p.error},
              {"budget", p.budget},
              {"motion", to_string(p.motion)},
              {"period", p.period},
              {"spectral_radius", p.spectral_radius},
              {"lyapunov", p.lyapunov},
              {"lyapunov_standard_error", p.lyapunov_standard_error ? Json(*p.lyapunov_standard_error) : Json()},
              {"lyapunov_fallback_revolutions", p.lyapunov_fallback_revolutions},
              {"impact_angle_deg", p.impact_angle_deg},
              {"impact_speed", p.impact_speed},
              {"section_position", p.section_position},
              {"separation_fraction", p.separation_fraction},
              {"link_separation_fraction", p.link_separation_fraction},
              {"floats", p.floats},
              {"float_cause", p.float_cause},
              {"seat_bounces", p.seat_bounces},
              {"max_gap", p.max_gap},
              {"peak_contact_force", p.peak_contact_force},
              {"coexisting", p.coexisting},
              {"attractors", attractors}};
}

JumpMapPoint jump_map_point_from_json(const Json& j) {
  JumpMapPoint p;
  p.rpm = j.at("rpm").get<double>();
  p.ok = j.at("ok").get<bool>();
  p.error = j.at("error").get<std::string>();
  p.budget = j.value("budget", std::string());
  p.start = parse_enum<JumpMapStart>(j.value("start", std::string("transient")));  // older records: no shortcut
  p.refined = j.value("refined", false);
  p.motion = parse_enum<MotionKind>(j.at("motion").get<std::string>());
  p.period = j.at("period").get<int>();
  p.spectral_radius = j.at("spectral_radius").get<double>();
  p.lyapunov = j.at("lyapunov").get<double>();
  if (const auto se = j.find("lyapunov_standard_error"); se != j.end() && !se->is_null())  // older records: none
    p.lyapunov_standard_error = se->get<double>();
  p.lyapunov_fallback_revolutions = j.value("lyapunov_fallback_revolutions", 0L);  // older records: none
  p.impact_angle_deg = j.at("impact_angle_deg").get<std::vector<double>>();
  p.impact_speed = j.at("impact_speed").get<std::vector<double>>();
  p.section_position = j.at("section_position").get<std::vector<double>>();
  p.separation_fraction = j.at("separation_fraction").get<double>();
  p.link_separation_fraction = j.value("link_separation_fraction", 0.0);  // older records: none
  // Older records: every impact and separation was taken as leaving the cam.
  p.floats = j.value("floats", !p.impact_speed.empty() || p.separation_fraction > 0);
  p.float_cause = j.value("float_cause", std::string(p.floats ? "float" : ""));  // older records: none
  p.seat_bounces = j.value("seat_bounces", 0L);
  p.max_gap = j.at("max_gap").get<double>();
  p.peak_contact_force = j.at("peak_contact_force").get<double>();
  p.coexisting = j.at("coexisting").get<bool>();
  for (const Json& a : j.at("attractors")) {
    JumpMapAttractor attractor;
    attractor.reached = parse_enum<JumpMapReach>(a.at("reached").get<std::string>());
    attractor.motion = parse_enum<MotionKind>(a.at("motion").get<std::string>());
    attractor.period = a.at("period").get<int>();
    attractor.spectral_radius = a.at("spectral_radius").get<double>();
    attractor.fixed_point = a.at("fixed_point").get<std::vector<double>>();
    attractor.approach_speed = a.at("approach_speed").get<double>();
    attractor.multipliers_re = a.at("floquet_multipliers").at("re").get<std::vector<double>>();
    attractor.multipliers_im = a.at("floquet_multipliers").at("im").get<std::vector<double>>();
    p.attractors.push_back(std::move(attractor));
  }
  if (p.coexisting) static_cast<void>(j.at("attractors").at(1));  // throws: a coexisting speed lists two or more
  return p;
}

}  // namespace camdyn
