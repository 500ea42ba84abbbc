// The outputs of a `simulate` run (docs/config.md, "Outputs of simulate"): summary.json,
// timeseries.csv, events.csv and report.html, each written atomically.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "dynamics/model.h"
#include "dynamics/plausibility.h"
#include "dynamics/simulation.h"
#include "io/config.h"
#include "output/report.h"
#include "output/valvetrain_figures.h"

namespace camdyn {

/// The metrics as JSON, in their one order; an infinite jump speed is null.
Json metrics_json(const Metrics& m);

/// summary.json `warnings` (docs/warnings.md): one {cause, field, message} per warning.
Json warnings_json(const std::vector<PlausibilityWarning>& warnings);

/// summary.json: name, study, version, metrics, solver counters, the model
/// that was assembled, the plausibility warnings (dynamics/plausibility.h)
/// and the fully resolved config. No NaN/inf: an infinite
/// jump speed (a law that never decelerates) is written as null.
Json summary_json(const SceneConfig& scene, const Model& model, const SimulationResult& result);

/// summary.json `spring_sizing` (dynamics/spring_sizing.h): the smallest
/// preload at the spring's rate, and the smallest rate at its preload, that
/// keep the rigid-model force ≥ 0 at every cam speed up to the run's.
Json spring_sizing_json(const Model& model);

/// The report a user looks at first: follower motion against the law, gap,
/// contact force against cam angle (with the rigid-model force), energy
/// residual, the cam plots (output/cam_plots.h: the cam to scale, pressure angle,
/// radius of curvature, SVAJ), metrics and solver tables.
Report simulation_report(const SceneConfig& scene, const Model& model, const SimulationResult& result);

/// The angles the report's verdict names, each in the evaluated window, as
/// cam angles in [0, 360) [deg] (the verdict prints each with its crank angle
/// where the scene has `outputs.valvetrain`, and the train's last-revolution
/// plots mark them: study/train_revolution.h). Unset where the verdict names
/// none: a drop test, a valve held open.
struct VerdictAngles {
  std::optional<double> min_force_deg;  ///< in contact: where the least contact force is (simulation_verdict)
  std::optional<double> lift_off_deg;   ///< the cam contact's first float separation
  std::optional<double> landing_deg;    ///< where it lands again
  double landing_speed = 0.0;           ///< its approach speed there [m/s]
  std::optional<double> lets_go_deg;    ///< `separates_first`'s angle, where the verdict names it
  std::string lets_go_where;            ///< `separates_first`: "cam contact" or "link <body>"
};

/// The verdict's angles of a run (simulation_verdict prints these, and no others).
VerdictAngles verdict_angles(const Model& model, const SimulationResult& result);

/// A cam angle as the verdict prints it: in [0, 360) to 4 digits, "95.5°",
/// and with a crank scale its crank angle after TDC beside it (CrankScale::of_deg),
/// "95.5° (191° crank)".
std::string verdict_angle_text(double cam_deg, const std::optional<CrankScale>& crank);

/// The report's banner: "stays in contact, minimum contact force X N at Y°",
/// or "separates at X°, lands at Y° at Z m/s; rigid-model jump speed ..."
/// (from the events of the evaluated window; the angles of verdict_angles,
/// printed by verdict_angle_text), or for a drop test (cam held still) where
/// the follower lands, the peak force and its rebounds.
Verdict simulation_verdict(const SceneConfig& scene, const Model& model, const SimulationResult& result);

/// timeseries.csv: the header (TimeSeries::column_names) and one row per
/// output step, every number in its shortest round-trip form.
void write_timeseries_csv(const std::filesystem::path& path, const TimeSeries& series);

/// events.csv: time, cam_angle_deg, kind (onset | separation), speed, impact (0/1).
void write_events_csv(const std::filesystem::path& path, const std::vector<ContactEvent>& events);

/// Writes summary.json, timeseries.csv, events.csv and report.html into `dir`
/// (created if missing).
void write_simulation_outputs(const std::filesystem::path& dir, const SceneConfig& scene, const Model& model,
                              const SimulationResult& result);

/// summary.json `model`'s words for what drives the cam ("constant_speed",
/// "stationary", "shaft:constant_speed_motor", "shaft:torque_speed_motor"),
/// for the follower ("translating_roller", "oscillating_flat", ...) and for
/// how the contact pair is tracked (a sentence).
std::string drive_name(const Model& model);
std::string follower_name(const Model& model);
std::string contact_pair_name(const Model& model);

/// Rigid-model normal contact force of a follower on the law at the model's
/// speed at each cam angle of `thetas` [rad] (docs/model.md §9): P / cos φ with
/// P = m ω² s'' + c ω s' + k (s + x₀) + m g [N] (negative: the follower would
/// need to be pulled); on a follower train the held train's
/// (dynamics/held_train_force.h, docs/model.md §12).
std::vector<double> rigid_contact_force(const Model& model, const std::vector<double>& thetas);

}  // namespace camdyn
