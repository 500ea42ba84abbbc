// The `periodic` study: what the mechanism settles into at the scene's speed.
// It finds the periodic orbit by shooting on the once-per-revolution map
// (study/periodic_orbit.h), says whether the orbit is stable (Floquet
// multipliers), lists its impacts and evaluates the usual metrics on one
// period of it; when no orbit up to `max_period` converges it estimates the
// largest Lyapunov exponent and calls the motion chaotic, quasi-periodic or
// unresolved. Outputs: periodic.json, orbit.csv (the orbit as a time series)
// and report.html.
#pragma once

#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "common/study_budget.h"
#include "dynamics/chatter.h"
#include "dynamics/simulation.h"
#include "io/config.h"
#include "io/json_archive.h"
#include "study/periodic_orbit.h"
#include "study/study.h"

namespace camdyn {

/// The longest period the shooting may try [revolutions].
inline constexpr int kMaxPeriodTried = 64;
/// The most Newton iterations per period.
inline constexpr int kMaxNewtonIterations = 100;

/// The study's own fields (`periodic` in the config).
struct PeriodicConfig {
  PeriodicOptions options;  ///< max_period … chaos_threshold (threads and log are not config)
};

/// The `periodic` fields, read and written in one place.
template <class A>
void visit(A& a, PeriodicConfig& c) {
  PeriodicOptions& o = c.options;
  a.field("max_period", o.max_period, at_least(1));
  a.field("transient_revolutions", o.transient_revolutions, at_least(1));
  a.field("tolerance", o.tolerance, open_closed(0, 0.1));
  a.field("max_newton_iterations", o.max_newton_iterations, at_least(1));
  a.field("lyapunov_revolutions", o.lyapunov_revolutions, at_least(10));
  a.field("chaos_threshold", o.chaos_threshold, positive());
  a.field("jacobian", o.jacobian);
  // Work bounds (the shooting on period k integrates k revolutions per map
  // and per Jacobian column): beyond them the study could not finish.
  a.require(o.max_period <= kMaxPeriodTried, "max_period",
            "must be at most " + std::to_string(kMaxPeriodTried) + ", got " + std::to_string(o.max_period));
  a.require(
      o.max_newton_iterations <= kMaxNewtonIterations, "max_newton_iterations",
      "must be at most " + std::to_string(kMaxNewtonIterations) + ", got " + std::to_string(o.max_newton_iterations));
  for (const auto& [key, revolutions] :
       {std::pair{"transient_revolutions", o.transient_revolutions}, {"lyapunov_revolutions", o.lyapunov_revolutions}})
    a.require(revolutions <= kMaxRevolutionsPerRun, key,
              "asks for " + std::to_string(revolutions) + " revolutions (at most " +
                  format_shortest(kMaxRevolutionsPerRun) + ")");
}

struct PeriodicStudy {
  SceneConfig scene;
  /// The scene's geometry, built when the config is read (null: built where needed).
  std::shared_ptr<const CamGeometry> geometry;
  PeriodicConfig config;
  Json resolved;  ///< the resolved study config (`camdyn validate` prints it)
};

/// An impact on the orbit (a contact onset after a separation), or a take-off.
struct OrbitEvent {
  double cam_angle_deg = 0.0;      ///< [deg] within the revolution
  double speed = 0.0;              ///< normal approach speed of an impact, separation speed of a take-off [m/s]
  double follower_velocity = 0.0;  ///< q̇ there [m/s | rad/s]
};

/// The analysis and one period of the orbit it found (or the last revolution
/// of the Lyapunov run when none).
struct PeriodicResult {
  PeriodicAnalysis analysis;
  SimulationResult orbit_run;         ///< one period from the fixed point: metrics on the orbit, series, events
  std::vector<OrbitEvent> impacts;    ///< on the orbit
  std::vector<OrbitEvent> take_offs;  ///< separations on the orbit
  std::vector<ChatterSequence>
      chatter;  ///< accumulating impact sequences over two periods (or revolutions) from the orbit's start
  double jump_speed_rpm = 0.0;  ///< rigid model, or the held train's (docs/model.md §12) [rpm]
  std::string jump_speed_name = "rigid-model jump speed";
  double rpm = 0.0;
  double run_time_s = 0.0;
};

/// Reads a `periodic` study config; throws InputError.
PeriodicStudy read_periodic_study(const Json& doc, const StudyContext& ctx);

/// Runs the analysis on ctx.threads() threads; `log` is told what it is doing.
PeriodicResult run_periodic(const PeriodicStudy& study, const StudyContext& ctx,
                            const std::function<void(const std::string&)>& log = {});

/// The verdict in one sentence ("period-1 orbit, stable …", "chaotic …").
std::string periodic_verdict(const PeriodicResult& r);

/// periodic.json.
Json periodic_json(const PeriodicStudy& study, const PeriodicResult& r, const std::vector<std::string>& coordinates);

/// Runs (or, with ctx.validate_only, checks) the study and writes its
/// outputs; returns the exit code.
int run_periodic_study(const Json& doc, const StudyContext& ctx);

}  // namespace camdyn
