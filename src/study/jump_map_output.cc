// The jump map's run (ranges journalled on threads or MPI ranks) and its
// outputs: jump_map.json, jump_map.csv (one row per speed), impacts.csv (one
// row per impact) and report.html with the diagram and the cam.
#include <camdyn/version.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <map>
#include <optional>
#include <set>
#include <string_view>

#include "common/errors.h"
#include "common/study_budget.h"
#include "dynamics/coordinate_units.h"
#include "io/csv_writer.h"
#include "io/json_writer.h"
#include "output/cam_plots.h"
#include "output/report.h"
#include "study/journal.h"
#include "study/journaled_runs.h"
#include "study/jump_map.h"
#include "study/mpi_runner.h"

namespace camdyn {

namespace {

/// The meaning of a range's record: 2 since a speed carries `coexisting` and
/// its `attractors` (a record of 1 was never checked for them). Part of the
/// journal's fingerprint, so an older journal is refused, not misread.
constexpr int kRangeRecordFormat = 2;

/// Range `r` as its journal record: status "budget" (with the budget's
/// name) when a budget cut one of its speeds short, so that a study stopped
/// by its wall-time budget does not journal it and a re-run computes the
/// range again from its start (the continuation as in an uninterrupted run).
Json range_record(const JumpMapStudy& study, std::size_t r, const std::string& file) {
  Json points = Json::array();
  std::string budget;
  for (const JumpMapPoint& p : run_jump_map_range(study, r, file)) {
    points.push_back(jump_map_point_json(p));
    if (budget.empty()) budget = p.budget;
  }
  Json record{{"index", r}, {"status", budget.empty() ? "ok" : "budget"}, {"points", points}};
  if (!budget.empty()) record[kBudgetKey] = budget;
  return record;
}

/// A speed's status in jump_map.csv.
std::string point_status(const JumpMapPoint& p) {
  if (p.ok) return "ok";
  return p.budget.empty() ? "failed" : "failed: budget";
}

// An attractor's class: its period, or its kind of motion.
std::string attractor_label(const JumpMapAttractor& a) {
  return a.motion == MotionKind::periodic ? "period " + std::to_string(a.period) : to_string(a.motion);
}

// A coexisting speed's attractors, "period 1 (continuation); period 3 (from_below)"; empty for any other.
std::string attractors_text(const JumpMapPoint& p) {
  std::string text;
  for (const JumpMapAttractor& a : p.attractors)
    text += (text.empty() ? "" : "; ") + attractor_label(a) + " (" + to_string(a.reached) + ")";
  return text;
}

void write_csvs(const std::filesystem::path& dir, const std::vector<JumpMapPoint>& points) {
  CsvWriter speeds(dir / "jump_map.csv",
                   {"rpm", "motion", "period", "spectral_radius", "lyapunov_per_revolution", "lyapunov_standard_error",
                    "impacts", "max_impact_speed", "separation_fraction", "max_gap", "peak_contact_force", "status",
                    "error", "start", "refined", "coexisting", "attractors", "floats", "seat_bounces"});
  CsvWriter impacts(dir / "impacts.csv", {"rpm", "motion", "period", "cam_angle_deg", "approach_speed"});
  for (const JumpMapPoint& p : points) {
    double fastest = 0.0;
    for (std::size_t i = 0; i < p.impact_speed.size(); ++i) {
      fastest = std::max(fastest, p.impact_speed[i]);
      impacts.row({CsvCell(p.rpm), CsvCell(to_string(p.motion)), CsvCell(p.period), CsvCell(p.impact_angle_deg[i]),
                   CsvCell(p.impact_speed[i])});
    }
    speeds.row({CsvCell(p.rpm), CsvCell(p.ok ? to_string(p.motion) : ""), CsvCell(p.period), CsvCell(p.spectral_radius),
                CsvCell(p.lyapunov), p.lyapunov_standard_error ? CsvCell(*p.lyapunov_standard_error) : CsvCell(""),
                CsvCell(static_cast<long>(p.impact_speed.size())), CsvCell(fastest), CsvCell(p.separation_fraction),
                CsvCell(p.max_gap), CsvCell(p.peak_contact_force), CsvCell(point_status(p)), CsvCell(p.error),
                CsvCell(p.ok ? to_string(p.start) : ""), CsvCell(p.refined ? 1L : 0L), CsvCell(p.coexisting ? 1L : 0L),
                CsvCell(attractors_text(p)), CsvCell(p.floats ? 1L : 0L), CsvCell(p.seat_bounces)});
  }
  speeds.commit();
  impacts.commit();
}

// The class a speed is drawn in: its period, or its kind of motion.
std::string motion_label(const JumpMapPoint& p) {
  if (p.coexisting) return "coexisting attractors";
  if (p.motion == MotionKind::periodic) return "period " + std::to_string(p.period);
  return to_string(p.motion);
}

// `y(p)` against rpm for every speed, one series per motion label, and the
// rigid jump speed as a vertical line.
template <class Values>
Plot diagram(const std::vector<JumpMapPoint>& points, double jump_rpm, const std::string& jump_name, Plot plot,
             Values values) {
  std::map<std::string, Series> by_label;
  double lo = 0.0, hi = 0.0;
  for (const JumpMapPoint& p : points) {
    if (!p.ok) continue;
    Series& s = by_label.try_emplace(motion_label(p), Series{motion_label(p), {}, {}, "points"}).first->second;
    for (const double v : values(p)) {
      s.x.push_back(p.rpm);
      s.y.push_back(v);
      lo = std::min(lo, v);
      hi = std::max(hi, v);
    }
  }
  for (auto& [label, s] : by_label) plot.series.push_back(std::move(s));
  if (std::isfinite(jump_rpm))
    plot.series.push_back({jump_name, {jump_rpm, jump_rpm}, {lo, hi}, "lines", PlotRole::limit});
  return plot;
}

}  // namespace

Report jump_map_report(const JumpMapStudy& study, const std::vector<JumpMapPoint>& points,
                       const std::vector<JumpMapTransition>& transitions, double run_time, const std::string& file) {
  Report rep;
  rep.title = "camdyn jump_map: " + study.scene.name;
  const auto first = std::find_if(points.begin(), points.end(), [](const JumpMapPoint& p) { return p.ok && p.floats; });
  rep.subtitle = "jump map: the steady motion at each cam speed from " + format_number(study.config.low_rpm) + " to " +
                 format_number(study.config.high_rpm) + " rpm";
  rep.verdict = Verdict{first == points.end() ? Verdict::Tone::good : Verdict::Tone::warning,
                        first == points.end() ? "the follower stays on the cam at every speed of the map"
                                              : "the follower first leaves the cam at " + format_number(first->rpm, 5) +
                                                    " rpm (" + study.jump_speed_name + " " +
                                                    format_number(study.damped_rigid_jump_speed_rpm, 5) + " rpm)",
                        {}};
  const JumpMapLimit limit = jump_map_limit(points);
  if (limit.rpm)
    rep.verdict->details.push_back(limit.cause == "link" ? "what leaves first: a link of the train opens off its seats"
                                                         : "what leaves first: the follower floats off the cam");
  if (limit.seat_bounce_rpm)
    rep.verdict->details.push_back("a body bounces off its seat from " + format_number(*limit.seat_bounce_rpm, 5) +
                                   " rpm (no jump: docs/valvetrain.md)");
  rep.facts = {{"speeds", std::to_string(points.size()) + " from " + format_number(study.config.low_rpm) + " to " +
                              format_number(study.config.high_rpm) + " rpm"},
               {study.jump_speed_name, format_number(study.damped_rigid_jump_speed_rpm, 5) + " rpm with the damper, " +
                                           format_number(study.rigid_jump_speed_rpm, 5) + " rpm without"},
               {"run time", format_number(run_time, 3) + " s"}};
  for (const JumpMapTransition& t : transitions) {
    if (t.kind == "coexistence") {
      const auto p = std::find_if(points.begin(), points.end(),
                                  [&](const JumpMapPoint& q) { return q.coexisting && q.rpm == t.from_rpm; });
      rep.facts.push_back({t.kind, "at " + format_number(t.from_rpm, 5) +
                                       " rpm: " + (p == points.end() ? std::string() : attractors_text(*p))});
      continue;
    }
    rep.facts.push_back({t.kind, "between " + format_number(t.from_rpm, 5) + " and " + format_number(t.to_rpm, 5) +
                                     " rpm (period " + std::to_string(t.from_period) + " → " +
                                     std::to_string(t.to_period) + ")"});
  }
  const double jump = study.damped_rigid_jump_speed_rpm;
  rep.plots.push_back(diagram(
      points, jump, study.jump_speed_name,
      Plot{"Jump map: impact speed against cam speed", "cam speed [rpm]", "normal approach speed at impact [m/s]", {}},
      [](const JumpMapPoint& p) { return p.impact_speed; }));
  // The section samples are q: an arm's in rad (coordinate_units.h).
  // A translating follower's position in µm, mm or m as the largest needs (output/plot_style.h).
  const CoordinateUnits units = coordinate_units(study.scene);
  LengthUnit unit{1.0, units.position};
  if (std::string_view(units.position) == "m") {
    std::vector<const std::vector<double>*> columns;
    for (const JumpMapPoint& p : points)
      if (p.ok) columns.push_back(&p.section_position);
    unit = length_unit(columns);
  }
  rep.plots.push_back(
      diagram(points, jump, study.jump_speed_name,
              Plot{"Poincaré section: " + std::string(units.position_name) + " once per revolution",
                   "cam speed [rpm]",
                   CoordinateUnits::axis(std::string(units.position_name) + " at the section", unit.symbol),
                   {}},
              [&unit](const JumpMapPoint& p) { return unit.of(p.section_position); }));
  rep.plots.push_back(diagram(points, jump, study.jump_speed_name,
                              Plot{"Impact angles", "cam speed [rpm]", "cam angle at impact [deg]", {}},
                              [](const JumpMapPoint& p) { return p.impact_angle_deg; }));
  // The cam, its SVAJ per radian of cam angle: the map runs at many speeds.
  std::optional<Model> built;  // a study read from its config has its model
  const Model& model = study.model ? *study.model : built.emplace(build_model(study.geometry, study.scene, file));
  for (Plot& p : cam_plots(model, study.scene.mechanism.cam.limits, 0.0)) rep.plots.push_back(std::move(p));
  Table table{
      "Speeds", {"rpm", "motion", "impacts", "separation fraction", "max gap [m]", "peak force [N]", "error"}, {}};
  for (const JumpMapPoint& p : points)
    table.rows.push_back({format_number(p.rpm) + (p.refined ? " (refined)" : ""),
                          !p.ok          ? "failed"
                          : p.coexisting ? "coexisting: " + attractors_text(p)
                                         : motion_label(p),
                          std::to_string(p.impact_speed.size()), format_number(p.separation_fraction),
                          format_number(p.max_gap), format_number(p.peak_contact_force), p.error});
  table.wrap = true;  // the error column
  rep.appendix.push_back(table);
  rep.notes.push_back(
      "Each speed whose neighbours settled on a stable orbit is shot from the orbit they predict (a secant in "
      "rpm); the others, and any whose prediction gives no stable orbit of that period, are followed past "
      "their transient (starting from the neighbour's motion), analysed by shooting (the periodic study) and "
      "sampled once per revolution. A periodic orbit's samples are its one period repeated.");
  rep.notes.push_back(
      "Where the class changes between neighbouring speeds, each side's stable orbit is continued one step "
      "across and a speed reached from a predicted orbit is also followed from the scene's own start. A speed "
      "where two different attractors were found is drawn as \"coexisting attractors\" (its samples: the "
      "attractor reached along the continuation) and has no single class: the table lists every attractor "
      "and how it was reached.");
  return rep;
}

int run_jump_map_study(const Json& doc, const StudyContext& ctx) {
  const JumpMapStudy study = read_jump_map_study(doc, ctx);
  if (ctx.validate_only) {
    std::cout << dump_json(study.resolved);
    return 0;
  }
  const auto t0 = std::chrono::steady_clock::now();
  const std::size_t ranges = std::min(study.rpm.size(), static_cast<std::size_t>(study.config.ranges));
  JournaledRuns runs;
  if (const std::optional<int> code = run_journaled(
          "jump_map",
          fingerprint(dump_json(study.resolved) + "\nrange record format " + std::to_string(kRangeRecordFormat)),
          ranges, [&](std::size_t r) { return range_record(study, r, ctx.config_file); }, ctx, runs,
          [&](std::size_t r) {
            double work = 0.0;  // [expected revolutions]
            for (const std::size_t i : jump_map_range(study, r)) work += jump_map_speed_work(study, i);
            return work;
          }))
    return *code;
  if (mpi::rank() != 0) return 0;  // rank 0 writes the outputs
  std::vector<JumpMapPoint> points;
  for (std::size_t r = 0; r < ranges; ++r) {
    try {
      for (const Json& j : runs.records.at(r).at("points")) points.push_back(jump_map_point_from_json(j));
    } catch (const Json::exception& e) {  // its checksum holds, so it was written so on purpose
      throw InputError((ctx.out_dir / "journal.jsonl").string(), "",
                       "the record of speed range " + std::to_string(r) + " is not one camdyn writes (" + e.what() +
                           "): delete that line or the journal and run again");
    }
  }
  // Speeds a budget cut short say nothing about the motion: no transition or
  // verdict rests on them (docs/outputs-and-resume.md, "Budgets").
  std::size_t cut = 0;
  std::set<std::string> budget_names;
  for (const JumpMapPoint& p : points)
    if (!p.budget.empty()) {
      ++cut;
      budget_names.insert(p.budget);
    }
  std::string budgets;
  for (const std::string& name : budget_names) budgets += (budgets.empty() ? "" : ", ") + name;
  const std::string withheld =
      cut == 0 ? std::string()
               : withheld_text(cut, points.size(), "speeds", budgets,
                               "the jump map's conclusion (its transitions, where the follower leaves the cam)");
  const std::vector<JumpMapTransition> transitions =
      withheld.empty() ? jump_map_transitions(points) : std::vector<JumpMapTransition>{};
  const double run_time = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  Json speeds = Json::array(), changes = Json::array();
  for (const JumpMapPoint& p : points) speeds.push_back(jump_map_point_json(p));
  for (const JumpMapTransition& t : transitions)
    changes.push_back({{"kind", t.kind},
                       {"from_rpm", t.from_rpm},
                       {"to_rpm", t.to_rpm},
                       {"from_period", t.from_period},
                       {"to_period", t.to_period}});
  const double jump = study.rigid_jump_speed_rpm, damped = study.damped_rigid_jump_speed_rpm;
  long predicted = 0;   // speeds shot from their neighbours' orbit, without a transient
  long coexisting = 0;  // speeds with two attractors or more: no single class
  for (const JumpMapPoint& p : points) {
    predicted += p.ok && p.start == JumpMapStart::predicted ? 1 : 0;
    coexisting += p.ok && p.coexisting ? 1 : 0;
  }
  const JumpMapLimit limit = jump_map_limit(points);
  write_json_atomic(
      ctx.out_dir / "jump_map.json",
      Json{{"name", study.scene.name},
           {"study", "jump_map"},
           {"camdyn_version", CAMDYN_VERSION},
           {"rigid_jump_speed_rpm", std::isfinite(jump) ? Json(jump) : Json()},
           {"damped_rigid_jump_speed_rpm", std::isfinite(damped) ? Json(damped) : Json()},
           {"transitions", withheld.empty() ? changes : Json()},
           {"limit_rpm", withheld.empty() && limit.rpm ? Json(*limit.rpm) : Json()},
           {"limit_cause", withheld.empty() && limit.rpm ? Json(limit.cause) : Json()},
           {"seat_bounce_rpm", withheld.empty() && limit.seat_bounce_rpm ? Json(*limit.seat_bounce_rpm) : Json()},
           {"speeds", speeds},
           {"budget_cut_speeds", cut},
           {"predicted_speeds", predicted},
           {"coexisting_speeds", coexisting},
           {"conclusion_withheld", withheld.empty() ? Json() : Json(withheld)},
           {"resumed_ranges", runs.resumed},
           {"run_time_s", run_time}});
  write_csvs(ctx.out_dir, points);
  if (!withheld.empty()) {
    std::filesystem::remove(ctx.out_dir / "report.html");  // an earlier run's verdict must not stand
    std::cerr << "camdyn: error: " << withheld << "\n";
    return 3;
  }
  write_report(ctx.out_dir / "report.html", jump_map_report(study, points, transitions, run_time, ctx.config_file));
  long failed = 0;
  for (const JumpMapPoint& p : points) failed += p.ok ? 0 : 1;
  std::printf(
      "%s: %zu speeds (%ld failed, %ld from a predicted orbit, %ld with coexisting attractors), %zu "
      "transitions, %.3g s\n",
      study.scene.name.c_str(), points.size(), failed, predicted, coexisting, transitions.size(), run_time);
  for (const JumpMapTransition& t : transitions) {
    if (t.kind == "coexistence")
      std::printf("  coexisting attractors at %.6g rpm\n", t.from_rpm);
    else
      std::printf("  %s between %.6g and %.6g rpm\n", t.kind.c_str(), t.from_rpm, t.to_rpm);
  }
  std::printf("  report: %s\n", std::filesystem::absolute(ctx.out_dir / "report.html").lexically_normal().c_str());
  return failed == static_cast<long>(points.size()) ? 3 : 0;
}

}  // namespace camdyn
