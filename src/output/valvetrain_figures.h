// The valvetrain figures of `outputs.valvetrain` (docs/valvetrain.md):
// geometry/valve_timing.h at the valve (the law carried to the last body of
// the follower train through the links' ratios and lash, held at its seat:
// dynamics/kinematic_lift.h) or at the cam (`at`), in cam degrees and in crank
// degrees from the crank's TDC, the timing events before/after the dead
// centres, and beside them the valve's simulated lift from the run's time
// series; as summary.json's `valvetrain` object and as a table and a lift plot
// against crank angle in the report.
#pragma once

#include <cstddef>
#include <optional>
#include <string>

#include "common/constants.h"
#include "dynamics/model.h"
#include "dynamics/simulation.h"
#include "geometry/lift_chain.h"
#include "geometry/valve_timing.h"
#include "io/config.h"
#include "output/report.h"

namespace camdyn {

/// Crank angles from the scene's TDC (docs/valvetrain.md, "Conventions"):
/// crank = r (cam − tdc_deg), the cam angle taken in [tdc_deg, tdc_deg + 360)
/// for an event's start.
struct CrankScale {
  static constexpr double kTurnDeg = 360.0;  // a cam turn, and a TDC (and a BDC) every crank revolution [deg]

  double ratio = 2.0;  ///< r [-]
  double tdc_deg = 0.0;

  /// The crank angle of cam angle `cam_rad` in [0, 360) [rad], in [0, 360 r) [deg].
  double of(double cam_rad) const { return ratio * (cam_rad * kRadToDeg - tdc_deg + shift(cam_rad)); }
  /// The crank angle of any cam angle `cam_deg` (a running one too), in [0, 360 r) [deg].
  double of_deg(double cam_deg) const;
  /// The crank angle of `cam_rad`, a cam angle after `from_rad` (an interval's end), on `from_rad`'s turn [deg].
  double of_end(double from_rad, double cam_rad) const {
    return ratio * (cam_rad * kRadToDeg - tdc_deg + shift(from_rad));
  }
  double cycle() const { return kTurnDeg * ratio; }  ///< one cam turn in crank degrees

 private:
  double shift(double cam_rad) const { return cam_rad * kRadToDeg - tdc_deg < 0.0 ? kTurnDeg : 0.0; }
};

/// The scene's `outputs.valvetrain` crank_ratio and tdc_deg.
CrankScale crank_scale(const ValvetrainOutputConfig& config);

/// The scene's crank scale; unset without `outputs.valvetrain`.
std::optional<CrankScale> scene_crank_scale(const SceneConfig& scene);

/// The valvetrain figures of a scene, at the place its config asks for.
struct ValvetrainFigures {
  ValveTiming timing;           ///< at `at`: lifts above `timing.datum`
  LiftChain chain;              ///< the law to the body at `at` (empty at the cam)
  std::size_t body = 0;         ///< the train body whose position is the lift at `at` (0, the follower, at the cam)
  std::string body_name;        ///< its name ("follower" without a train)
  double valve_datum = 0.0;     ///< the valve's datum, its seat or base-circle position [m]
  double max_valve_lift = 0.0;  ///< the valve's kinematic lift, whatever `at` [m]
  std::size_t valve = 0;        ///< the valve's body: the last of the train
  std::string valve_name;       ///< its name
};

/// The figures of the scene's law at its checking heights; unset without `outputs.valvetrain`.
std::optional<ValvetrainFigures> scene_valvetrain(const SceneConfig& scene, const Model& model);

/// The timing at `at` (ValvetrainFigures::timing); unset without `outputs.valvetrain`.
std::optional<ValveTiming> scene_valve_timing(const SceneConfig& scene, const Model& model);

/// The largest lift of train body `body` above `datum` over the run's
/// evaluated window, from its time series at the output step [m]; unset
/// without samples there.
std::optional<double> simulated_max_lift(const Model& model, const SimulationResult& result, std::size_t body,
                                         double datum);

/// summary.json's `valvetrain` object (angles in degrees, lengths in metres,
/// velocities per radian of cam and in m/s at the run's cam speed); the
/// simulated lifts from `result` (null without one); null without
/// `outputs.valvetrain`.
Json valvetrain_json(const SceneConfig& scene, const Model& model, const SimulationResult* result = nullptr);

/// The report's "Valvetrain" table and lift-against-crank-angle plot (with
/// `result`, the simulated lift of its last revolution beside the kinematic
/// one); nothing without `outputs.valvetrain`.
void add_valvetrain_report(const SceneConfig& scene, const Model& model, Report& report,
                           const SimulationResult* result = nullptr);

/// A crank angle [deg] wrapped into (−period/2, period/2]: the signed angle
/// after the nearest dead centre of a kind that repeats every `period`.
double crank_after(double crank_deg, double period_deg);

}  // namespace camdyn
