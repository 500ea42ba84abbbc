#include "study/train_report.h"

#include <algorithm>
#include <cstddef>
#include <string>
#include <vector>

#include "dynamics/kinematic_lift.h"
#include "study/train_revolution.h"

namespace camdyn {

namespace {

/// Each body's position, and its kinematic lift: the law through the links'
/// ratios less their lash, held by the seats, in µm, mm or m
/// as the largest lift needs.
Plot lift_plot(const Model& model, const TimeSeries& ts) {
  Plot plot{"Train: each body's lift against its kinematic lift", "time [s]", "", {}};
  std::vector<double> kinematic = ts.kinematic_position;
  for (std::size_t i = 0; i < model.train.bodies.size(); ++i) {
    const TrainBody& b = model.train.bodies[i];
    const std::vector<double>* x = train_column(ts, b.name + "_position");
    const LiftStep step = lift_step(model.train, i);
    for (double& k : kinematic) k = step.carry(k);
    if (!x) continue;
    plot.series.push_back({b.name, ts.time, *x});  // [m] until the unit is known
    plot.series.push_back({b.name + " kinematic", ts.time, kinematic, "dashes"});
  }
  std::vector<const std::vector<double>*> columns;
  for (const Series& s : plot.series) columns.push_back(&s.y);
  const LengthUnit unit = length_unit(columns);
  plot.ylabel = unit.axis("lift");
  for (Series& s : plot.series) s.y = unit.of(s.y);
  return plot;
}

/// Each spring's force at its frame end against F₀ + k x of a massless spring at the body's position [N].
Plot spring_plot(const SceneConfig& scene, const Model& model, const TimeSeries& ts) {
  Plot plot{"Train: spring force at the frame end against the static force (surge)", "time [s]", "force [N]", {}};
  for (std::size_t i = 0; i < model.train.bodies.size(); ++i) {
    const TrainBody& b = model.train.bodies[i];
    const std::vector<double>* force = train_column(ts, b.name + "_spring_force");
    const std::vector<double>* x = train_column(ts, b.name + "_position");
    if (!force || !x) continue;
    const SpringConfig& spring = i == 0 ? scene.mechanism.follower.spring : scene.mechanism.train[i - 1].spring;
    std::vector<double> static_force(x->size());
    std::transform(x->begin(), x->end(), static_force.begin(),
                   [&](double p) { return spring.preload + spring.stiffness * p; });
    plot.series.push_back({b.name + " spring (dynamic)", ts.time, *force});
    plot.series.push_back({b.name + " spring (static F0 + k x)", ts.time, static_force, "dashes"});
  }
  return plot;
}

/// Each seat's force, with the seatings (the force rising from zero) as points [N].
Plot seat_plot(const Model& model, const TimeSeries& ts) {
  Plot plot{"Train: seat forces, seatings marked", "time [s]", "force [N]", {}};
  for (const TrainBody& b : model.train.bodies) {
    const std::vector<double>* force = train_column(ts, b.name + "_seat_force");
    if (!force) continue;
    Series seatings{b.name + " seatings", {}, {}, "points", PlotRole::seat};
    for (std::size_t k = 1; k < force->size(); ++k)
      if ((*force)[k - 1] <= 0.0 && (*force)[k] > 0.0) {
        seatings.x.push_back(ts.time[k]);
        seatings.y.push_back((*force)[k]);
      }
    plot.series.push_back({b.name + " seat", ts.time, *force});
    if (!seatings.x.empty()) plot.series.push_back(std::move(seatings));
  }
  return plot;
}

}  // namespace

void add_train_plots(const SceneConfig& scene, const Model& model, const SimulationResult& result, Report& report) {
  const TimeSeries& ts = result.series;
  if (!model.train.present() || ts.time.empty()) return;
  if (model.follower.oscillating()) return;  // lifts in rad and m together: the time series has them
  add_train_revolution_plots(scene, model, result, report);
  for (Plot plot : {lift_plot(model, ts), spring_plot(scene, model, ts), seat_plot(model, ts)})
    if (!plot.series.empty()) report.plots.push_back(std::move(plot));
}

}  // namespace camdyn
