#include "output/valvetrain_figures.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

#include "common/constants.h"
#include "dynamics/kinematic_lift.h"

namespace camdyn {

namespace {

constexpr int kPlotSamples = 1440;              // points of the lift-against-crank-angle plot over one cam turn
constexpr double kDeadCentrePeriodDeg = 360.0;  // a TDC (and a BDC) every crank revolution [deg]
constexpr double kBdcAfterTdcDeg = 180.0;       // [deg of crank]

Json ramp_json(const std::optional<RampEnd>& ramp, const CrankScale& crank, double omega) {
  if (!ramp) return nullptr;
  return Json{{"cam_deg", ramp->angle * kRadToDeg},
              {"crank_deg", crank.of(ramp->angle)},
              {"height", ramp->height},
              {"velocity_per_cam_rad", ramp->velocity},
              {"velocity_per_crank_deg", ramp->velocity * kDegToRad / crank.ratio},
              {"velocity_m_s", ramp->velocity * omega}};
}

/// The event's figures before/after the dead centres (docs/valvetrain.md, "Timing events"):
/// signed crank degrees after the scene's TDC, and, for a named valve, its IVO/IVC or EVO/EVC.
void add_dead_centre_figures(Json& j, double opening, double closing, const CrankScale& crank,
                             const std::optional<ValveKind>& valve) {
  j["opening_atdc_deg"] = crank_after(opening, crank.cycle());
  j["closing_atdc_deg"] = j["opening_atdc_deg"].get<double>() + (closing - opening);
  if (!valve) return;
  if (*valve == ValveKind::intake) {
    j["IVO_btdc_deg"] = -crank_after(opening, kDeadCentrePeriodDeg);
    j["IVC_abdc_deg"] = crank_after(closing - kBdcAfterTdcDeg, kDeadCentrePeriodDeg);
  } else {
    j["EVO_bbdc_deg"] = -crank_after(opening - kBdcAfterTdcDeg, kDeadCentrePeriodDeg);
    j["EVC_atdc_deg"] = crank_after(closing, kDeadCentrePeriodDeg);
  }
}

/// The dead-centre keys of a checking height's entry (null where the height is never reached).
std::vector<std::string> dead_centre_keys(const std::optional<ValveKind>& valve) {
  std::vector<std::string> keys = {"opening_atdc_deg", "closing_atdc_deg"};
  if (valve == ValveKind::intake) keys.insert(keys.end(), {"IVO_btdc_deg", "IVC_abdc_deg"});
  if (valve == ValveKind::exhaust) keys.insert(keys.end(), {"EVO_bbdc_deg", "EVC_atdc_deg"});
  return keys;
}

Json height_json(const CheckingHeightTiming& h, const CrankScale& crank, const std::optional<ValveKind>& valve) {
  Json j{{"height", h.height},
         {"duration_cam_deg", h.duration * kRadToDeg},
         {"duration_crank_deg", h.duration * kRadToDeg * crank.ratio},
         {"intervals", h.intervals.size()}};
  if (h.event) {
    const double opening = crank.of(h.event->opening), closing = crank.of_end(h.event->opening, h.event->closing);
    j["opening_cam_deg"] = h.event->opening * kRadToDeg;
    j["closing_cam_deg"] = h.event->closing * kRadToDeg;
    j["opening_crank_deg"] = opening;
    j["closing_crank_deg"] = closing;
    j["midpoint_cam_deg"] = h.midpoint * kRadToDeg;
    add_dead_centre_figures(j, opening, closing, crank, valve);
  } else {
    for (const char* key :
         {"opening_cam_deg", "closing_cam_deg", "opening_crank_deg", "closing_crank_deg", "midpoint_cam_deg"})
      j[key] = nullptr;
    for (const std::string& key : dead_centre_keys(valve)) j[key] = nullptr;
  }
  return j;
}

/// The column of train body `body`'s position in the series (the follower's for 0), or null.
const std::vector<double>* position_column(const Model& model, const TimeSeries& ts, std::size_t body) {
  if (body == 0 || body >= model.train.bodies.size()) return &ts.follower_position;
  const std::string name = model.train.bodies[body].name + "_position";
  const auto it = std::find(ts.train_names.begin(), ts.train_names.end(), name);
  return it == ts.train_names.end() ? nullptr : &ts.train[static_cast<std::size_t>(it - ts.train_names.begin())];
}

Json optional_json(const std::optional<double>& v) { return v ? Json(*v) : Json(nullptr); }

/// The overall lever ratio of a chain: the product of its steps' ratios [m/m].
double chain_ratio(const LiftChain& chain) {
  double ratio = 1.0;
  for (const LiftStep& step : chain.steps) ratio *= step.ratio;
  return ratio;
}

/// The simulated lift of the figures' body over the run's last revolution, on the plot's crank axis (a
/// break, NaN, where the axis wraps); empty when the run has less than a revolution.
Series simulated_series(const Model& model, const SimulationResult& result, const ValvetrainFigures& f,
                        const CrankScale& crank) {
  Series s{"simulated " + f.body_name, {}, {}, "lines", PlotRole::dynamic};
  const TimeSeries& ts = result.series;
  const std::vector<double>* x = position_column(model, ts, f.body);
  if (!x || ts.cam_angle_deg.empty() || ts.cam_angle_deg.back() - ts.cam_angle_deg.front() < 360.0) return s;
  const double begin = ts.cam_angle_deg.back() - 360.0;  // [deg of cam]
  double previous = -1.0;
  for (std::size_t i = 0; i < ts.cam_angle_deg.size() && i < x->size(); ++i) {
    if (ts.cam_angle_deg[i] < begin) continue;
    const double at = crank.of_deg(ts.cam_angle_deg[i]);
    if (at < previous) {
      s.x.push_back(std::numeric_limits<double>::quiet_NaN());
      s.y.push_back(std::numeric_limits<double>::quiet_NaN());
    }
    s.x.push_back(at);
    s.y.push_back((*x)[i] - f.timing.datum);  // [m]
    previous = at;
  }
  return s;
}

}  // namespace

double CrankScale::of_deg(double cam_deg) const {
  const double after = std::fmod(cam_deg - tdc_deg, 360.0);  // [deg of cam] after TDC, in (−360, 360)
  return ratio * (after < 0.0 ? after + 360.0 : after);
}

CrankScale crank_scale(const ValvetrainOutputConfig& config) { return {config.crank_ratio, config.tdc_deg}; }

std::optional<CrankScale> scene_crank_scale(const SceneConfig& scene) {
  if (!scene.outputs.valvetrain) return std::nullopt;
  return crank_scale(*scene.outputs.valvetrain);
}

double crank_after(double crank_deg, double period_deg) {
  double a = std::fmod(crank_deg, period_deg);
  if (a > 0.5 * period_deg) a -= period_deg;
  if (a <= -0.5 * period_deg) a += period_deg;
  return a;
}

std::optional<ValvetrainFigures> scene_valvetrain(const SceneConfig& scene, const Model& model) {
  if (!scene.outputs.valvetrain) return std::nullopt;
  const ValvetrainOutputConfig& config = *scene.outputs.valvetrain;
  std::optional<std::pair<double, double>> ramp_end;
  if (config.ramp_end_deg.size() == 2)
    ramp_end = std::pair(config.ramp_end_deg[0] * kDegToRad, config.ramp_end_deg[1] * kDegToRad);
  ValvetrainFigures f;
  f.valve = last_body(model.train);
  const LiftChain valve_chain = lift_chain(model.train, f.valve);
  const MotionLaw& law = *model.law;
  f.valve_datum = valve_chain.datum(law.min_s());
  const bool at_valve = config.at == ValvetrainAt::valve;
  if (at_valve) {
    f.chain = valve_chain;
    f.body = f.valve;
  }
  auto name = [&](std::size_t body) {
    return body < model.train.bodies.size() ? model.train.bodies[body].name : std::string("follower");
  };
  f.body_name = name(f.body);
  f.valve_name = name(f.valve);
  f.timing = valve_timing(law, config.checking_heights, ramp_end, f.chain);
  // The peak as valve_timing finds it (a root of ds/dθ), not the law's sampled max s.
  f.max_valve_lift = at_valve ? f.timing.max_lift : valve_timing(law, {}, std::nullopt, valve_chain).max_lift;
  return f;
}

std::optional<ValveTiming> scene_valve_timing(const SceneConfig& scene, const Model& model) {
  std::optional<ValvetrainFigures> f = scene_valvetrain(scene, model);
  if (!f) return std::nullopt;
  return std::move(f->timing);
}

std::optional<double> simulated_max_lift(const Model& model, const SimulationResult& result, std::size_t body,
                                         double datum) {
  const TimeSeries& ts = result.series;
  const std::vector<double>* x = position_column(model, ts, body);
  if (!x) return std::nullopt;
  std::optional<double> max;
  for (std::size_t i = 0; i < ts.time.size() && i < x->size(); ++i)
    if (ts.time[i] >= result.evaluated_from && std::isfinite((*x)[i]))
      max = std::max(max.value_or(-std::numeric_limits<double>::infinity()), (*x)[i] - datum);
  return max;
}

Json valvetrain_json(const SceneConfig& scene, const Model& model, const SimulationResult* result) {
  const std::optional<ValvetrainFigures> figures = scene_valvetrain(scene, model);
  if (!figures) return nullptr;
  const ValvetrainFigures& f = *figures;
  const ValveTiming& timing = f.timing;
  const ValvetrainOutputConfig& config = *scene.outputs.valvetrain;
  const CrankScale crank = crank_scale(config);
  Json heights = Json::array();
  for (const CheckingHeightTiming& h : timing.heights) heights.push_back(height_json(h, crank, config.valve));
  const bool seat = !f.chain.steps.empty() && f.chain.steps.back().seat.has_value();
  std::optional<double> simulated, simulated_valve;
  if (result) {
    simulated = simulated_max_lift(model, *result, f.body, timing.datum);
    simulated_valve = simulated_max_lift(model, *result, f.valve, f.valve_datum);
  }
  const double centre = crank.of(timing.lobe_centre);
  return Json{{"at", to_string(config.at)},
              {"body", f.body_name},
              {"ratio", chain_ratio(f.chain)},
              {"crank_ratio", config.crank_ratio},
              {"tdc_deg", config.tdc_deg},
              {"valve", config.valve ? Json(to_string(*config.valve)) : Json(nullptr)},
              {"lift_datum", seat ? "seat" : "base circle"},
              {"datum", timing.datum},
              {"max_lift", timing.max_lift},
              {"max_simulated_lift", optional_json(simulated)},
              {"max_valve_lift", f.max_valve_lift},
              {"max_simulated_valve_lift", optional_json(simulated_valve)},
              {"lobe_centre_cam_deg", timing.lobe_centre * kRadToDeg},
              {"lobe_centre_crank_deg", centre},
              {"lobe_centre_atdc_deg", crank_after(centre, crank.cycle())},
              {"lobe_centre_is", "the cam angle of maximum lift (the middle of a dwell at full lift)"},
              {"cam_rpm", model.omega * 60.0 / (2.0 * std::numbers::pi)},
              {"checking_heights", std::move(heights)},
              {"opening_ramp", ramp_json(timing.opening_ramp, crank, model.omega)},
              {"closing_ramp", ramp_json(timing.closing_ramp, crank, model.omega)}};
}

namespace {

/// The rows of a checking height: its duration, its opening and closing, and a named valve's events.
void add_height_rows(const CheckingHeightTiming& h, const CrankScale& crank, const std::optional<ValveKind>& valve,
                     Table& table) {
  auto deg = [](double cam_rad) { return format_number(cam_rad * kRadToDeg); };
  const std::string at = " at " + format_number(h.height * 1e3) + " mm";
  table.rows.push_back({"duration" + at, deg(h.duration), format_number(h.duration * kRadToDeg * crank.ratio, 6), "°"});
  if (!h.event) return;
  const double opening = crank.of(h.event->opening), closing = crank.of_end(h.event->opening, h.event->closing);
  table.rows.push_back({"opens" + at, deg(h.event->opening), format_number(opening, 6), "°"});
  table.rows.push_back({"closes" + at, deg(h.event->closing), format_number(closing, 6), "°"});
  if (!valve) return;
  Json j;
  add_dead_centre_figures(j, opening, closing, crank, valve);
  const bool intake = *valve == ValveKind::intake;
  const std::pair<const char*, const char*> events[] = {
      intake ? std::pair("IVO", "IVO_btdc_deg") : std::pair("EVO", "EVO_bbdc_deg"),
      intake ? std::pair("IVC", "IVC_abdc_deg") : std::pair("EVC", "EVC_atdc_deg")};
  const char* refs[] = {intake ? "BTDC" : "BBDC", intake ? "ABDC" : "ATDC"};
  for (int k = 0; k < 2; ++k)
    table.rows.push_back({std::string(events[k].first) + at, "", format_number(j[events[k].second].get<double>(), 6),
                          std::string("° ") + refs[k]});
}

}  // namespace

void add_valvetrain_report(const SceneConfig& scene, const Model& model, Report& report,
                           const SimulationResult* result) {
  const std::optional<ValvetrainFigures> figures = scene_valvetrain(scene, model);
  if (!figures) return;
  const ValvetrainFigures& f = *figures;
  const ValveTiming& timing = f.timing;
  const ValvetrainOutputConfig& config = *scene.outputs.valvetrain;
  const CrankScale crank = crank_scale(config);
  const bool at_valve = config.at == ValvetrainAt::valve;
  const bool seat = !f.chain.steps.empty() && f.chain.steps.back().seat.has_value();
  const std::string where = at_valve ? "at the " + f.body_name + " (lift from its " +
                                           std::string(seat ? "seat" : "base-circle position") + ")"
                                     : "at the cam (lift from the base circle)";
  Table table{"Valvetrain " + where + "; crank angle = " + format_number(crank.ratio) + " × (cam angle − " +
                  format_number(crank.tdc_deg) + "°), 0 at TDC",
              {"quantity", "cam", "crank", "unit"},
              {},
              false};
  table.rows.push_back({"maximum lift (kinematic)", format_number(timing.max_lift * 1e3), "", "mm"});
  if (!at_valve)
    table.rows.push_back(
        {"maximum lift at the " + f.valve_name + " (kinematic)", format_number(f.max_valve_lift * 1e3), "", "mm"});
  const std::optional<double> simulated =
      result ? simulated_max_lift(model, *result, f.body, timing.datum) : std::nullopt;
  if (simulated) table.rows.push_back({"maximum lift (simulated)", format_number(*simulated * 1e3), "", "mm"});
  table.rows.push_back({"lobe centre (angle of maximum lift)", format_number(timing.lobe_centre * kRadToDeg),
                        format_number(crank.of(timing.lobe_centre), 6), "°"});
  for (const CheckingHeightTiming& h : timing.heights) add_height_rows(h, crank, config.valve, table);
  for (const auto& [name, ramp] :
       {std::pair("opening ramp end", timing.opening_ramp), std::pair("closing ramp start", timing.closing_ramp)}) {
    if (!ramp) continue;
    table.rows.push_back(
        {std::string(name), format_number(ramp->angle * kRadToDeg), format_number(crank.of(ramp->angle), 6), "°"});
    table.rows.push_back({std::string(name) + ": height", format_number(ramp->height * 1e3), "", "mm"});
    table.rows.push_back({std::string(name) + ": velocity", format_number(ramp->velocity * 1e3),
                          format_number(ramp->velocity * 1e3 * kDegToRad / crank.ratio), "mm/rad cam; mm/° crank"});
    table.rows.push_back(
        {std::string(name) + ": velocity at the run's speed", format_number(ramp->velocity * model.omega), "", "m/s"});
  }
  report.tables.push_back(std::move(table));

  const MotionLaw& law = *model.law;
  Series lift{"kinematic " + f.body_name + " lift", {}, {}, "lines", PlotRole::rigid};
  for (int i = 0; i <= kPlotSamples; ++i) {
    const double turn = static_cast<double>(i) / kPlotSamples;  // [-] of a cam turn after TDC
    lift.x.push_back(crank.cycle() * turn);
    lift.y.push_back(f.chain.at(law.eval(crank.tdc_deg * kDegToRad + kTwoPi * turn).s) - timing.datum);  // [m]
  }
  Plot plot{"Valve lift against crank angle (" + where + ")", "crank angle [°]", "", {}};
  if (result) {
    Series dynamic = simulated_series(model, *result, f, crank);
    if (!dynamic.x.empty()) plot.series.push_back(std::move(dynamic));
  }
  plot.series.insert(plot.series.begin(), std::move(lift));
  std::vector<const std::vector<double>*> columns;
  for (const Series& s : plot.series) columns.push_back(&s.y);
  const LengthUnit unit = length_unit(columns);
  plot.ylabel = unit.axis("lift");
  for (Series& s : plot.series) s.y = unit.of(s.y);
  for (const CheckingHeightTiming& h : timing.heights)
    plot.series.push_back(Series{"checking height " + format_number(h.height * 1e3) + " mm",
                                 {0.0, crank.cycle()},
                                 {h.height * unit.per_metre, h.height * unit.per_metre},
                                 "dashes",
                                 PlotRole::limit});
  plot.xrange = std::pair(0.0, crank.cycle());
  report.plots.push_back(std::move(plot));
}

}  // namespace camdyn
