#include "output/valvetrain_figures.h"

#include <numbers>
#include <string>
#include <utility>
#include <vector>

#include "common/constants.h"

namespace camdyn {

namespace {

constexpr int kPlotSamples = 1440;  // points of the lift-against-crank-angle plot over one cam turn

Json ramp_json(const std::optional<RampEnd>& ramp, double ratio, double omega) {
  if (!ramp) return nullptr;
  return Json{{"cam_deg", ramp->angle * kRadToDeg},
              {"crank_deg", ramp->angle * kRadToDeg * ratio},
              {"height", ramp->height},
              {"velocity_per_cam_rad", ramp->velocity},
              {"velocity_per_crank_deg", ramp->velocity * kDegToRad / ratio},
              {"velocity_m_s", ramp->velocity * omega}};
}

Json height_json(const CheckingHeightTiming& h, double ratio) {
  Json j{{"height", h.height},
         {"duration_cam_deg", h.duration * kRadToDeg},
         {"duration_crank_deg", h.duration * kRadToDeg * ratio},
         {"intervals", h.intervals.size()}};
  if (h.event) {
    j["opening_cam_deg"] = h.event->opening * kRadToDeg;
    j["closing_cam_deg"] = h.event->closing * kRadToDeg;
    j["opening_crank_deg"] = h.event->opening * kRadToDeg * ratio;
    j["closing_crank_deg"] = h.event->closing * kRadToDeg * ratio;
    j["midpoint_cam_deg"] = h.midpoint * kRadToDeg;
  } else {
    for (const char* key :
         {"opening_cam_deg", "closing_cam_deg", "opening_crank_deg", "closing_crank_deg", "midpoint_cam_deg"})
      j[key] = nullptr;
  }
  return j;
}

}  // namespace

std::optional<ValveTiming> scene_valve_timing(const SceneConfig& scene, const Model& model) {
  if (!scene.outputs.valvetrain) return std::nullopt;
  const ValvetrainOutputConfig& config = *scene.outputs.valvetrain;
  std::optional<std::pair<double, double>> ramp_end;
  if (config.ramp_end_deg.size() == 2)
    ramp_end = std::pair(config.ramp_end_deg[0] * kDegToRad, config.ramp_end_deg[1] * kDegToRad);
  return valve_timing(*model.law, config.checking_heights, ramp_end);
}

Json valvetrain_json(const SceneConfig& scene, const Model& model) {
  const std::optional<ValveTiming> timing = scene_valve_timing(scene, model);
  if (!timing) return nullptr;
  const double ratio = scene.outputs.valvetrain->crank_ratio;
  Json heights = Json::array();
  for (const CheckingHeightTiming& h : timing->heights) heights.push_back(height_json(h, ratio));
  return Json{{"crank_ratio", ratio},
              {"lift_datum", "base circle"},
              {"max_lift", timing->max_lift},
              {"lobe_centre_cam_deg", timing->lobe_centre * kRadToDeg},
              {"lobe_centre_crank_deg", timing->lobe_centre * kRadToDeg * ratio},
              {"lobe_centre_is", "the cam angle of maximum lift (the middle of a dwell at full lift)"},
              {"cam_rpm", model.omega * 60.0 / (2.0 * std::numbers::pi)},
              {"checking_heights", std::move(heights)},
              {"opening_ramp", ramp_json(timing->opening_ramp, ratio, model.omega)},
              {"closing_ramp", ramp_json(timing->closing_ramp, ratio, model.omega)}};
}

void add_valvetrain_report(const SceneConfig& scene, const Model& model, Report& report) {
  const std::optional<ValveTiming> timing = scene_valve_timing(scene, model);
  if (!timing) return;
  const double ratio = scene.outputs.valvetrain->crank_ratio;
  auto crank = [&](double cam_rad) { return format_number(cam_rad * kRadToDeg * ratio, 6); };
  Table table{"Valvetrain (lift from the base circle; crank angle = " + format_number(ratio) + " × cam angle)",
              {"quantity", "cam", "crank", "unit"},
              {},
              false};
  table.rows.push_back({"maximum lift", format_number(timing->max_lift * 1e3), "", "mm"});
  table.rows.push_back({"lobe centre (angle of maximum lift)", format_number(timing->lobe_centre * kRadToDeg),
                        crank(timing->lobe_centre), "°"});
  for (const CheckingHeightTiming& h : timing->heights) {
    const std::string at = " at " + format_number(h.height * 1e3) + " mm";
    table.rows.push_back({"duration" + at, format_number(h.duration * kRadToDeg), crank(h.duration), "°"});
    if (h.event) {
      table.rows.push_back({"opens" + at, format_number(h.event->opening * kRadToDeg), crank(h.event->opening), "°"});
      table.rows.push_back({"closes" + at, format_number(h.event->closing * kRadToDeg), crank(h.event->closing), "°"});
    }
  }
  for (const auto& [name, ramp] :
       {std::pair("opening ramp end", timing->opening_ramp), std::pair("closing ramp start", timing->closing_ramp)}) {
    if (!ramp) continue;
    table.rows.push_back({std::string(name), format_number(ramp->angle * kRadToDeg), crank(ramp->angle), "°"});
    table.rows.push_back({std::string(name) + ": height", format_number(ramp->height * 1e3), "", "mm"});
    table.rows.push_back({std::string(name) + ": velocity", format_number(ramp->velocity * 1e3),
                          format_number(ramp->velocity * 1e3 * kDegToRad / ratio), "mm/rad cam; mm/° crank"});
    table.rows.push_back(
        {std::string(name) + ": velocity at the run's speed", format_number(ramp->velocity * model.omega), "", "m/s"});
  }
  report.tables.push_back(std::move(table));

  Series lift{"valve lift", {}, {}, "lines"};
  for (int i = 0; i <= kPlotSamples; ++i) {
    const double cam = 2.0 * std::numbers::pi * i / kPlotSamples;
    lift.x.push_back(cam * kRadToDeg * ratio);
    lift.y.push_back(lift_above_base(*model.law, cam));  // [m]
  }
  const LengthUnit unit = length_unit({&lift.y});
  lift.y = unit.of(lift.y);
  Plot plot{"Valve lift against crank angle (lift from the base circle)", "crank angle [°]", unit.axis("lift"), {lift}};
  for (const CheckingHeightTiming& h : timing->heights)
    plot.series.push_back(Series{"checking height " + format_number(h.height * 1e3) + " mm",
                                 {0.0, 360.0 * ratio},
                                 {h.height * unit.per_metre, h.height * unit.per_metre},
                                 "dashes",
                                 PlotRole::limit});
  plot.xrange = std::pair(0.0, 360.0 * ratio);
  report.plots.push_back(std::move(plot));
}

}  // namespace camdyn
