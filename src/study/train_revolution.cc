#include "study/train_revolution.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <utility>

#include "common/constants.h"
#include "dynamics/kinematic_lift.h"
#include "study/simulation_output.h"

namespace camdyn {

double RevolutionAxis::of(double cam_deg) const {
  if (crank) return crank->of_deg(cam_deg);
  const double a = std::fmod(cam_deg, CrankScale::kTurnDeg);
  return a < 0.0 ? a + CrankScale::kTurnDeg : a;
}

double RevolutionAxis::span() const { return crank ? crank->cycle() : CrankScale::kTurnDeg; }

std::string RevolutionAxis::label() const {
  if (!crank) return "cam angle [deg]";
  return "crank angle from TDC, " + format_number(crank->ratio) + " × (cam angle − " + format_number(crank->tdc_deg) +
         "°) [deg]";
}

RevolutionAxis revolution_axis(const SceneConfig& scene) { return {scene_crank_scale(scene)}; }

const std::vector<double>* train_column(const TimeSeries& ts, const std::string& name) {
  if (name == "follower_position") return &ts.follower_position;
  if (name == "follower_velocity") return &ts.follower_velocity;
  if (name == "follower_acceleration") return &ts.follower_acceleration;
  const auto it = std::find(ts.train_names.begin(), ts.train_names.end(), name);
  return it == ts.train_names.end() ? nullptr : &ts.train[static_cast<std::size_t>(it - ts.train_names.begin())];
}

namespace {

/// A sample counts in the last revolution when its cam angle lies more than
/// this above the one a turn before the last sample's [deg]: the sample a
/// whole turn back is the last one's angle again, not drawn twice.
constexpr double kTurnEndDeg = 1e-6;

/// The run's last cam revolution: its samples, cam angles in (last − 360°,
/// last], in the order of their place on the axis (so the curve runs from 0
/// to the span without a break where the angle wraps).
struct Revolution {
  std::vector<std::size_t> index;  ///< into the series
  std::vector<double> x;           ///< on the axis, ascending in [0, span) [deg]

  /// `column` at the revolution's samples, times `k`.
  std::vector<double> pick(const std::vector<double>& column, double k = 1.0) const {
    std::vector<double> out;
    out.reserve(index.size());
    for (const std::size_t i : index) out.push_back(column[i] * k);
    return out;
  }
};

Revolution train_last_revolution(const TimeSeries& ts, const RevolutionAxis& axis) {
  Revolution r;
  const double begin = ts.cam_angle_deg.back() - CrankScale::kTurnDeg + kTurnEndDeg;  // [deg of cam]
  std::vector<std::pair<double, std::size_t>> at;
  for (std::size_t i = 0; i < ts.cam_angle_deg.size(); ++i)
    if (ts.cam_angle_deg[i] > begin) at.emplace_back(axis.of(ts.cam_angle_deg[i]), i);
  std::sort(at.begin(), at.end());
  for (const auto& [x, i] : at) {
    r.x.push_back(x);
    r.index.push_back(i);
  }
  return r;
}

/// d(column)/dt at sample i: a central difference over the neighbouring
/// output steps, one-sided at the series' ends [column's unit / s].
double time_derivative(const TimeSeries& ts, const std::vector<double>& column, std::size_t i) {
  const std::size_t lo = i > 0 ? i - 1 : i, hi = i + 1 < column.size() ? i + 1 : i;
  const double dt = ts.time[hi] - ts.time[lo];
  return dt > 0.0 ? (column[hi] - column[lo]) / dt : 0.0;
}

/// The valve (the last train body, dynamics/kinematic_lift.h last_body) over the revolution, dynamic and
/// kinematic: lift above its datum [m], velocity [m/s], acceleration [m/s²], and where each dynamic one comes from.
struct ValveRevolution {
  std::string name;
  bool seat = false;  ///< the lift is measured from the valve's seat (else from its base-circle position)
  std::vector<double> lift, velocity, acceleration;
  std::vector<double> kinematic_lift, kinematic_velocity, kinematic_acceleration;
  std::string velocity_from, acceleration_from;
};

/// The kinematic motion: the law's s, ds/dθ ω and d²s/dθ² ω² through the
/// chain's ratios (its slope, 0 while a seat holds the valve) at the cam's
/// speed of each sample (the speed's own change, with a shaft drive, left out).
void add_kinematic(const Model& model, const TimeSeries& ts, const LiftChain& chain, double datum, std::size_t i,
                   ValveRevolution& v) {
  const LawSample law = model.law->eval(ts.cam_angle_deg[i] * kDegToRad);
  const double omega = i < ts.cam_speed_rpm.size() ? ts.cam_speed_rpm[i] * kTwoPi / 60.0 : model.omega;  // [rad/s]
  const double slope = chain.slope(law.s);                                                               // [m/m]
  v.kinematic_lift.push_back(chain.at(law.s) - datum);
  v.kinematic_velocity.push_back(slope * law.ds * omega);
  v.kinematic_acceleration.push_back(slope * law.d2s * omega * omega);
}

/// The valve's motion over `rev`; empty lifts when the series lacks its position.
ValveRevolution valve_revolution(const Model& model, const TimeSeries& ts, const Revolution& rev) {
  ValveRevolution v;
  const std::size_t body = last_body(model.train);
  v.name = body < model.train.bodies.size() ? model.train.bodies[body].name : std::string("follower");
  const LiftChain chain = lift_chain(model.train, body);
  v.seat = !chain.steps.empty() && chain.steps.back().seat.has_value();
  const double datum = chain.datum(model.law->min_s());  // as the valvetrain figures' (output/valvetrain_figures.h)
  const std::vector<double>* position = train_column(ts, v.name + "_position");
  if (!position) return v;
  const std::vector<double>* velocity = train_column(ts, v.name + "_velocity");
  const std::vector<double>* acceleration = train_column(ts, v.name + "_acceleration");
  v.velocity_from = velocity ? v.name + "_velocity" : "central difference of " + v.name + "_position";
  v.acceleration_from = acceleration ? v.name + "_acceleration"
                        : velocity   ? "central difference of " + v.name + "_velocity"
                                     : "central difference of that velocity";
  std::vector<double> rate;  // the velocity column, or the position's derivative at every sample [m/s]
  if (!velocity) {
    rate.resize(position->size());
    for (std::size_t i = 0; i < rate.size(); ++i) rate[i] = time_derivative(ts, *position, i);
    velocity = &rate;
  }
  for (const std::size_t i : rev.index) {
    v.lift.push_back((*position)[i] - datum);
    v.velocity.push_back((*velocity)[i]);
    v.acceleration.push_back(acceleration ? (*acceleration)[i] : time_derivative(ts, *velocity, i));
    add_kinematic(model, ts, chain, datum, i, v);
  }
  return v;
}

/// One angle the verdict names, as the plots mark it.
struct Marker {
  std::string label;
  double x = 0.0;  ///< on the axis [deg]
  PlotRole role = PlotRole::automatic;
};

/// The verdict's angles (study/simulation_output.h) on the axis, labelled with the verdict's own text.
std::vector<Marker> verdict_markers(const VerdictAngles& at, const RevolutionAxis& axis) {
  std::vector<Marker> out;
  auto add = [&](const std::string& what, const std::optional<double>& deg, PlotRole role) {
    if (deg) out.push_back({"verdict: " + what + " at " + verdict_angle_text(*deg, axis.crank), axis.of(*deg), role});
  };
  add("minimum contact force", at.min_force_deg, PlotRole::minimum);
  add("separates", at.lift_off_deg, PlotRole::lift_off);
  add("lands", at.landing_deg, PlotRole::impact);
  add("lets go first (" + at.lets_go_where + ")", at.lets_go_deg, PlotRole::lift_off);
  return out;
}

/// The markers as point series on `plot`, each on the curve `on` (at the
/// revolution's sample nearest its angle, the axis taken round) or at 0 without one.
void add_markers(const std::vector<Marker>& markers, const Revolution& rev, const std::vector<double>* on,
                 const RevolutionAxis& axis, Plot& plot) {
  for (const Marker& m : markers) {
    double y = 0.0;
    if (on && !rev.x.empty()) {
      std::size_t best = 0;
      double distance = axis.span();
      for (std::size_t j = 0; j < rev.x.size(); ++j) {
        const double d = std::abs(rev.x[j] - m.x);
        if (std::min(d, axis.span() - d) < distance) {
          distance = std::min(d, axis.span() - d);
          best = j;
        }
      }
      y = (*on)[best];
    }
    plot.series.push_back({m.label, {m.x}, {y}, "points", m.role});
  }
}

/// A plot of the revolution on the axis, drawn at full resolution.
Plot revolution_plot(std::string title, const RevolutionAxis& axis, std::string ylabel) {
  Plot plot{std::move(title), axis.label(), std::move(ylabel), {}};
  plot.xrange = std::make_pair(0.0, axis.span());
  plot.full_resolution = true;
  return plot;
}

/// The valve's lift, velocity and acceleration, dynamic against kinematic, with the markers on the dynamic curve.
void add_valve_plots(const ValveRevolution& v, const Revolution& rev, const RevolutionAxis& axis,
                     const std::vector<Marker>& markers, Report& report) {
  const LengthUnit unit = length_unit({&v.lift, &v.kinematic_lift});
  const std::string at = "Last revolution at the " + v.name + ": ";
  const std::string kinematic = v.name + " kinematic";
  Plot lift = revolution_plot(at + "lift from its " + (v.seat ? "seat" : "base-circle position") +
                                  ", dynamic against kinematic (the law through the links' ratios less "
                                  "their lash, held by the seats)",
                              axis, unit.axis("lift"));
  const std::vector<double> dynamic_lift = unit.of(v.lift);
  lift.series = {{v.name, rev.x, dynamic_lift, "lines", PlotRole::dynamic},
                 {kinematic, rev.x, unit.of(v.kinematic_lift), "dashes", PlotRole::rigid}};
  add_markers(markers, rev, &dynamic_lift, axis, lift);
  Plot velocity = revolution_plot(
      at + "velocity, dynamic (" + v.velocity_from + ") against kinematic (the law's ds/dθ × ω through the ratios)",
      axis, "velocity [m/s]");
  velocity.series = {{v.name, rev.x, v.velocity, "lines", PlotRole::dynamic},
                     {kinematic, rev.x, v.kinematic_velocity, "dashes", PlotRole::rigid}};
  add_markers(markers, rev, &v.velocity, axis, velocity);
  Plot acceleration = revolution_plot(at + "acceleration, dynamic (" + v.acceleration_from +
                                          ") against kinematic (the law's d²s/dθ² × ω² through the ratios)",
                                      axis, "acceleration [m/s²]");
  acceleration.series = {{v.name, rev.x, v.acceleration, "lines", PlotRole::dynamic},
                         {kinematic, rev.x, v.kinematic_acceleration, "dashes", PlotRole::rigid}};
  add_markers(markers, rev, &v.acceleration, axis, acceleration);
  for (Plot* plot : {&lift, &velocity, &acceleration}) report.plots.push_back(std::move(*plot));
}

/// Every body's `suffix` force column over the revolution in one plot, the markers at 0; none without a column.
void add_force_plot(const Model& model, const TimeSeries& ts, const Revolution& rev, const RevolutionAxis& axis,
                    const std::vector<Marker>& markers, const char* suffix, const std::string& title, Report& report) {
  Plot plot = revolution_plot("Last revolution: " + title, axis, "force [N]");
  for (const TrainBody& b : model.train.bodies)
    if (const std::vector<double>* force = train_column(ts, b.name + suffix))
      plot.series.push_back({b.name, rev.x, rev.pick(*force)});
  if (plot.series.empty()) return;
  add_markers(markers, rev, nullptr, axis, plot);
  report.plots.push_back(std::move(plot));
}

}  // namespace

void add_train_revolution_plots(const SceneConfig& scene, const Model& model, const SimulationResult& result,
                                Report& report) {
  const TimeSeries& ts = result.series;
  if (!model.train.present() || model.follower.oscillating() || !(model.omega > 0.0)) return;
  if (ts.cam_angle_deg.empty() || ts.cam_angle_deg.back() - ts.cam_angle_deg.front() < CrankScale::kTurnDeg) return;
  const RevolutionAxis axis = revolution_axis(scene);
  const Revolution rev = train_last_revolution(ts, axis);
  const std::vector<Marker> markers = verdict_markers(verdict_angles(model, result), axis);
  const ValveRevolution valve = valve_revolution(model, ts, rev);
  if (!valve.lift.empty()) add_valve_plots(valve, rev, axis, markers, report);
  add_force_plot(model, ts, rev, axis, markers, "_seat_force", "seat forces of the train", report);
  add_force_plot(model, ts, rev, axis, markers, "_link_force", "link forces of the train", report);
  add_force_plot(model, ts, rev, axis, markers, "_spring_force", "spring forces of the train at their frame ends",
                 report);
  add_force_plot(model, ts, rev, axis, markers, "_gas_force", "gas loads A (p − p_port) on the train", report);
}

}  // namespace camdyn
