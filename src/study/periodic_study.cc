#include "study/periodic_study.h"

#include <camdyn/version.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <numbers>

#include "common/errors.h"
#include "dynamics/chatter.h"
#include "dynamics/model.h"
#include "dynamics/rigid_jump_speed.h"
#include "dynamics/train_jump_speed.h"
#include "io/json_archive.h"
#include "io/json_writer.h"
#include "study/periodic_report.h"
#include "study/simulation_output.h"

namespace camdyn {

namespace {

const std::vector<std::string> kPeriodicKeys = {"periodic"};

// One period of the orbit from its fixed point (or `revolutions` from `p`),
// with the series and the metrics over every step.
SimulationResult run_orbit(const PoincareMap& map, const SectionPoint& p, int revolutions) {
  SceneConfig scene = map.scene_for(revolutions);
  scene.simulation.output_step_deg = map.scene().simulation.output_step_deg.value_or(0.5);
  Workspace ws = make_workspace(map.model());
  SimulationOptions options;
  options.start = std::make_shared<const StartState>(map.start(p));
  SimulationResult r = simulate(scene, map.model(), ws, options);
  throw_if_failed(r);
  return r;
}

// The impacts (onset = true) or the take-offs of a run.
std::vector<OrbitEvent> orbit_events(const SimulationResult& r, bool onset) {
  std::vector<OrbitEvent> events;
  for (const ContactEvent& e : r.events)
    if (onset ? e.onset && e.impact : !e.onset)
      events.push_back({std::fmod(e.cam_angle_deg, 360.0), e.speed, e.follower_velocity});
  return events;
}

Json events_json(const std::vector<OrbitEvent>& events, const char* speed) {
  Json j = Json::array();
  for (const OrbitEvent& e : events)
    j.push_back({{"cam_angle_deg", e.cam_angle_deg}, {speed, e.speed}, {"follower_velocity", e.follower_velocity}});
  return j;
}

Json chatter_json(const std::vector<ChatterSequence>& chatter) {
  Json j = Json::array();
  for (const ChatterSequence& c : chatter)
    j.push_back({{"impacts", c.impacts}, {"flight_ratio", c.ratio}, {"accumulation_deg", c.accumulation_deg}});
  return j;
}

Json section_json(const SectionPoint& p, const std::vector<std::string>& names) {
  Json j = Json::object();
  for (std::size_t i = 0; i < names.size(); ++i) j[names[i]] = p.x[i];
  return j;
}

Json orbit_json(const Orbit& o, const std::vector<std::string>& names) {
  Json multipliers = Json::array();
  for (const std::complex<double>& mu : o.multipliers)
    multipliers.push_back({{"re", mu.real()}, {"im", mu.imag()}, {"modulus", std::abs(mu)}});
  return Json{{"period", o.period},
              {"stable", o.stable},
              {"fixed_point", section_json(o.fixed_point, names)},
              {"floquet_multipliers", multipliers},
              {"jacobian_method", to_string(o.jacobian_method)},
              {"spectral_radius", o.spectral_radius()},
              {"newton_iterations", o.newton_iterations},
              {"residual", o.residual}};
}

}  // namespace

PeriodicStudy read_periodic_study(const Json& doc, const StudyContext& ctx) {
  PeriodicStudy study;
  Json part;
  study.scene = scene_from_study_json(doc, ctx.source, kPeriodicKeys, part);
  const Json fields = read_study_fields(part, "periodic", ctx.source, study.config);
  study.geometry = build_cam_geometry(study.scene, ctx.config_file);
  const Model model = build_model(study.geometry, study.scene, ctx.config_file);  // the contact law is checked here
  [[maybe_unused]] const PoincareMap map(study.scene, model, ctx.config_file);    // and that the drive sets the speed
  study.resolved = resolved_study_json(study.scene, "periodic", Json{{"periodic", fields}});
  return study;
}

PeriodicResult run_periodic(const PeriodicStudy& study, const StudyContext& ctx,
                            const std::function<void(const std::string&)>& log) {
  const auto t0 = std::chrono::steady_clock::now();
  const Model model = build_model(study.geometry, study.scene, ctx.config_file);
  const PoincareMap map(study.scene, model, ctx.config_file);
  PeriodicOptions options = study.config.options;
  options.threads = ctx.threads();
  options.log = log;
  PeriodicResult r;
  r.rpm = study.scene.mechanism.cam.rpm;
  r.jump_speed_rpm = model_jump_speed_rpm(model);
  r.jump_speed_name = jump_speed_name(model);
  r.analysis = analyse_steady_state(map, options);
  const PeriodicAnalysis& a = r.analysis;
  SectionPoint start = a.transient_end;  // of the run the metrics are over
  if (a.orbit) {
    start = a.orbit->fixed_point;
  } else if (a.lyapunov && !a.lyapunov->section_points.empty()) {
    start = a.lyapunov->last;
  }
  const int period = a.orbit ? a.orbit->period : 1;
  r.orbit_run = run_orbit(map, start, period);
  r.analysis.revolutions += a.orbit ? a.orbit->period : 1;
  r.impacts = orbit_events(r.orbit_run, true);
  r.take_offs = orbit_events(r.orbit_run, false);
  // Chatter over two periods, so that a sequence across the section is seen whole.
  const SimulationResult twice = run_orbit(map, start, 2 * period);
  // Over two periods each sequence of the orbit is seen twice: keep one of each.
  for (const ChatterSequence& c : find_chatter(twice.events, twice.end_time, 6.0 * r.rpm))
    if (std::none_of(r.chatter.begin(), r.chatter.end(), [&](const ChatterSequence& seen) {
          return std::abs(seen.accumulation_deg - c.accumulation_deg) < 0.01 && seen.impacts == c.impacts;
        }))
      r.chatter.push_back(c);
  if (!r.chatter.empty()) r.analysis.motion = MotionKind::chattering;
  r.run_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return r;
}

namespace {

// "chattering: 7 impacts accumulating at 212.4 deg (flight ratio 0.61), then contact" for the first sequence.
std::string chatter_text(const std::vector<ChatterSequence>& chatter) {
  const ChatterSequence& c = chatter.front();
  char buffer[256];
  std::snprintf(buffer, sizeof buffer,
                "chattering: %zu impacts accumulating at %.4g deg (flight ratio %.3g), then contact%s", c.impacts,
                c.accumulation_deg, c.ratio, chatter.size() > 1 ? " (and more sequences)" : "");
  return buffer;
}

// Why the Lyapunov estimate (when there is one) gave no class, in words
// (unresolved_reason, docs/periodic.md).
const char* unresolved_text(const std::optional<LyapunovEstimate>& l) {
  switch (l ? unresolved_reason(*l) : UnresolvedReason::contracts) {
    case UnresolvedReason::contracts:
      return "unresolved: the motion contracts but its samples did not repeat within the settling budget (a longer "
             "period: raise periodic.max_period)";
    case UnresolvedReason::drifts:
      return "unresolved: the largest Lyapunov exponent is not clearly positive, yet the samples drift away "
             "instead of returning near where they have been (a slow transient, as near a bifurcation: raise "
             "periodic.lyapunov_revolutions)";
    case UnresolvedReason::straddles:
      break;
  }
  return "unresolved: the Lyapunov estimate straddles a bound and does not tell (raise periodic.lyapunov_revolutions)";
}

}  // namespace

std::string periodic_verdict(const PeriodicResult& r) {
  const PeriodicAnalysis& a = r.analysis;
  if (!r.chatter.empty()) {
    const std::string chatter = chatter_text(r.chatter);
    if (a.orbit)
      return chatter + "; period-" + std::to_string(a.orbit->period) + " orbit with chatter, " +
             (a.orbit->stable ? "stable" : "unstable");
    return chatter +
           "; no stable periodic orbit found (a Lyapunov estimate across the accumulations is no sign of "
           "chaos)";
  }
  char buffer[512];
  if (a.orbit) {
    const Metrics& m = r.orbit_run.metrics;
    std::snprintf(buffer, sizeof buffer,
                  "period-%d orbit, stable (largest |Floquet multiplier| %.3g); %zu impact%s per period, max gap "
                  "%.3g m, contact force %.4g to %.4g N",
                  a.orbit->period, a.orbit->spectral_radius(), r.impacts.size(), r.impacts.size() == 1 ? "" : "s",
                  m.max_separation_gap, m.min_contact_force, m.peak_contact_force);
    std::string verdict = buffer;
    if (a.settled_after >= 0)
      verdict +=
          "; the motion settled onto it after a transient of " + std::to_string(a.settled_after) + " revolutions";
    return verdict;
  }
  const int max_period = a.newton.empty() ? 0 : a.newton.back().period;
  const double lambda = a.lyapunov ? a.lyapunov->per_revolution : 0.0;
  const double per_impact = a.lyapunov ? a.lyapunov->per_impact : 0.0;
  const char* kind = a.motion == MotionKind::chaotic ? "chaotic: the largest Lyapunov exponent is positive"
                     : a.motion == MotionKind::quasi_periodic
                         ? "quasi-periodic: the largest Lyapunov exponent is ~0 and the samples return near "
                           "where they have been"
                         : unresolved_text(a.lyapunov);
  std::snprintf(buffer, sizeof buffer,
                "no stable periodic orbit up to period %d; %s (%+.3g per revolution, %+.3g per impact)", max_period,
                kind, lambda, per_impact);
  std::string verdict = buffer;
  for (const Orbit& o : a.unreached_orbits) {
    std::snprintf(buffer, sizeof buffer,
                  "; a stable period-%d orbit (largest |Floquet multiplier| %.3g) coexists, but the motion from "
                  "this start does not reach it",
                  o.period, o.spectral_radius());
    verdict += buffer;
  }
  return verdict;
}

Json periodic_json(const PeriodicStudy& study, const PeriodicResult& r, const std::vector<std::string>& coordinates) {
  const PeriodicAnalysis& a = r.analysis;
  Json unstable = Json::array();
  for (const Orbit& o : a.unstable_orbits) unstable.push_back(orbit_json(o, coordinates));
  Json unreached = Json::array();
  for (const Orbit& o : a.unreached_orbits) unreached.push_back(orbit_json(o, coordinates));
  Json newton = Json::array();
  for (const NewtonStep& s : a.newton)
    newton.push_back({{"period", s.period}, {"iteration", s.iteration}, {"residual", s.residual}});
  Json lyapunov = nullptr;
  if (a.lyapunov)
    lyapunov = {{"per_revolution", a.lyapunov->per_revolution},
                {"per_impact", a.lyapunov->per_impact},
                {"standard_error", a.lyapunov->standard_error ? Json(*a.lyapunov->standard_error) : Json()},
                {"revolutions", a.lyapunov->revolutions},
                {"aligning_revolutions", a.lyapunov->aligning_revolutions},
                {"samples_recur", a.lyapunov->samples_recur},
                {"impacts", a.lyapunov->impacts},
                {"method", to_string(a.lyapunov->method)},
                {"sensitivity_revolutions", a.lyapunov->sensitivity_revolutions},
                {"fallback_revolutions", a.lyapunov->fallback_revolutions},
                {"fallback_reason", a.lyapunov->fallback_reason.empty() ? Json() : Json(a.lyapunov->fallback_reason)}};
  const Metrics& m = r.orbit_run.metrics;
  const Json jacobians{{"sensitivity", a.sensitivity_jacobians},
                       {"finite_difference", a.finite_difference_jacobians},
                       {"fallback_reason", a.jacobian_fallback.empty() ? Json() : Json(a.jacobian_fallback)}};
  return Json{{"name", study.scene.name},
              {"study", "periodic"},
              {"camdyn_version", CAMDYN_VERSION},
              {"rpm", r.rpm},
              {"rigid_jump_speed_rpm", std::isfinite(r.jump_speed_rpm) ? Json(r.jump_speed_rpm) : Json()},
              {"motion", to_string(a.motion)},
              {"verdict", periodic_verdict(r)},
              {"coordinates", coordinates},
              {"orbit", a.orbit ? orbit_json(*a.orbit, coordinates) : Json()},
              {"unstable_orbits", unstable},
              {"unreached_orbits", unreached},
              {"impacts", events_json(r.impacts, "approach_speed")},
              {"chatter", chatter_json(r.chatter)},
              {"take_offs", events_json(r.take_offs, "separation_speed")},
              {"max_gap", m.max_separation_gap},
              {"peak_contact_force", m.peak_contact_force},
              {"min_contact_force", m.min_contact_force},
              {"metrics_on", a.orbit ? "orbit" : "last_revolution"},
              {"metrics", metrics_json(m)},
              {"lyapunov", lyapunov},
              {"newton", newton},
              {"settled_after_revolutions", a.settled_after >= 0 ? Json(a.settled_after) : Json()},
              {"reached_after_revolutions", a.reached_after >= 0 ? Json(a.reached_after) : Json()},
              {"revolutions_integrated", a.revolutions},
              {"map_evaluations", a.map_evaluations},
              {"jacobians", jacobians},
              {"run_time_s", r.run_time_s}};
}

int run_periodic_study(const Json& doc, const StudyContext& ctx) {
  const PeriodicStudy study = read_periodic_study(doc, ctx);
  if (ctx.validate_only) {
    std::cout << dump_json(study.resolved);
    return 0;
  }
  const std::string& name = study.scene.name;
  const PeriodicResult r =
      run_periodic(study, ctx, [&](const std::string& line) { std::printf("%s: %s\n", name.c_str(), line.c_str()); });
  const Model model = build_model(study.geometry, study.scene, ctx.config_file);
  const PoincareMap map(study.scene, model, ctx.config_file);
  std::filesystem::create_directories(ctx.out_dir);
  write_json_atomic(ctx.out_dir / "periodic.json", periodic_json(study, r, map.coordinate_names()));
  write_simulation_outputs(ctx.out_dir / "orbit", map.scene_for(r.analysis.orbit ? r.analysis.orbit->period : 1), model,
                           r.orbit_run);
  write_report(ctx.out_dir / "report.html", periodic_report(study, r, map));
  std::printf("%s at %.6g rpm (%s %.6g rpm): %s\n", name.c_str(), r.rpm, r.jump_speed_name.c_str(), r.jump_speed_rpm,
              periodic_verdict(r).c_str());
  std::printf("  %ld revolutions integrated, %.3g s; report: %s\n", r.analysis.revolutions, r.run_time_s,
              std::filesystem::absolute(ctx.out_dir / "report.html").lexically_normal().c_str());
  return 0;
}

}  // namespace camdyn
