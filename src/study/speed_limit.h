// The `speed_limit` study: "how fast can this go?" The highest cam speed at
// which the follower stays on the cam in the compliant simulation (no
// separation over the evaluated cycles, and at least `min_contact_force`),
// with the rigid-model jump speed beside it.
//
// Separation is not monotone in speed in general (resonances of the follower
// on its spring), so the study does not bisect blindly: it simulates a scan
// of `scan` speeds from `low_rpm` to `high_rpm`, takes the first speed that
// fails, and bisects between it and the scan speed below to `tolerance_rpm`.
// The scan runs from the bottom in batches, the first reaching just past the
// rigid-model jump speed, and stops at the batch where a speed first fails:
// the speeds above it cannot change the answer.
// The answer is "every scanned speed up to here keeps contact, and the speed
// just above the limit does not", which is what a designer can rely on.
#pragma once

#include <cstddef>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "dynamics/cam_geometry.h"
#include "dynamics/model.h"
#include "io/config.h"
#include "study/study.h"

namespace camdyn {

/// The study's own fields (`speed_limit` in the config).
struct SpeedLimitConfig {
  double low_rpm = 100.0;          ///< lowest speed checked [rpm], > 0
  std::optional<double> high_rpm;  ///< highest [rpm]; null: twice the rigid-model jump speed
  int scan = 12;                   ///< speeds of the first scan, ≥ 2
  double tolerance_rpm = 5.0;      ///< width of the final bracket [rpm]
  double min_contact_force = 0.0;  ///< contact force to keep [N]; 0: no separation is enough

  bool operator==(const SpeedLimitConfig&) const = default;
};

struct SpeedLimitStudy {
  SceneConfig scene;
  /// The scene's geometry, built once when the config is read and shared by
  /// every speed (null: each speed builds its own).
  std::shared_ptr<const CamGeometry> geometry;
  /// The scene's model, assembled once when the config is read: each worker
  /// thread runs its speeds on a copy of it, the speed set in place
  /// (set_cam_speed) (null: each speed assembles its own, as the study did
  /// before; bench/model_reuse_bench.cc compares).
  std::shared_ptr<const Model> model;
  SpeedLimitConfig config;
  Json resolved;                      ///< the resolved study config (`camdyn validate` prints it)
  double rigid_jump_speed_rpm = 0.0;  ///< of the scene's model, built when the config is read
  /// With a follower train the figure is the train's (docs/model.md §12): its name for messages.
  std::string jump_speed_name = "rigid-model jump speed";
  bool train = false;
  bool lash = false;  ///< the scene has a seat (docs/valvetrain.md)
};

/// One simulated speed.
struct SpeedCheck {
  double rpm = 0.0;
  bool ok = false;                   ///< no float, no link off its seat in float (and the force floor held)
  bool converged = true;             ///< the simulation finished (else ok is false)
  double separation_fraction = 0.0;  ///< [-]
  /// Valve-train verdicts (docs/valvetrain.md): the part of the separation
  /// that floats [-] (all of it without a seat), a link open off every seat
  /// in float [-], and the bounces the lash makes in the window.
  double float_fraction = 0.0, link_float_fraction = 0.0;
  long take_up_bounces = 0, seat_bounces = 0;
  double min_contact_force = 0.0;   ///< [N]
  double peak_contact_force = 0.0;  ///< [N]
  std::string message;              ///< the solver's message when it did not converge
  /// The budget that cut the run short (common/study_budget.h:
  /// budget_that_cut), empty when none did: such a run neither keeps
  /// contact nor separates, and a limit that rests on it is withheld.
  std::string budget;
};

struct SpeedLimitResult {
  /// The highest speed known to keep contact [rpm]: 0 when even low_rpm
  /// fails, high_rpm when nothing failed up to it (`limited` false).
  double speed_limit_rpm = 0.0;
  double first_failure_rpm = 0.0;  ///< the lowest speed known to fail [rpm] (0 when none did)
  bool limited = false;            ///< some speed in [low_rpm, high_rpm] failed
  /// What failed at first_failure_rpm: "float" (the cam contact), "link" (a
  /// link off every seat), "force" (the contact force floor), "solver".
  std::string limit_cause;
  /// The lowest simulated speed at which a body bounces off its seat [rpm]; unset when none did.
  std::optional<double> seat_bounce_rpm;
  bool lash = false;                  ///< the scene has a seat: take-up and seat bounces are told apart from float
  double rigid_jump_speed_rpm = 0.0;  ///< the train's where SpeedLimitStudy::train
  std::string jump_speed_name = "rigid-model jump speed";
  bool train = false;
  std::vector<SpeedCheck> checks;  ///< every simulation, in the order run
  double run_time_s = 0.0;
  std::size_t budget_cut = 0;  ///< checks a budget cut short
  std::size_t resumed = 0;     ///< checks found in the journal (replayed, not simulated)
  /// Scan speeds above the first that failed, not simulated (they cannot change the answer).
  std::size_t scan_skipped = 0;
  /// Why the limit is withheld (a check it rests on was cut short by a
  /// budget); empty when it stands.
  std::string withheld;
};

/// Reads a `speed_limit` study config; throws InputError.
SpeedLimitStudy read_speed_limit_study(const Json& doc, const StudyContext& ctx);

/// Runs it on ctx.threads() threads (the scan in parallel).
SpeedLimitResult run_speed_limit(const SpeedLimitStudy& study, const StudyContext& ctx);

/// speed_limit.json.
Json speed_limit_json(const SpeedLimitStudy& study, const SpeedLimitResult& result);

/// Runs (or, with ctx.validate_only, checks) the study and writes
/// speed_limit.json and report.html; returns the exit code.
int run_speed_limit_study(const Json& doc, const StudyContext& ctx);

}  // namespace camdyn
