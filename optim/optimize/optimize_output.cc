#include "optim/optimize/optimize_output.h"

#include <camdyn/version.h>

#include <cmath>
#include <iostream>
#include <vector>

#include "common/errors.h"
#include "dynamics/model.h"
#include "io/csv_writer.h"
#include "io/json_writer.h"
#include "optim/optimize/certificate_text.h"
#include "optim/optimize/optimize_report.h"
#include "output/profile_export.h"
#include "output/report.h"
#include "study/simulation_output.h"

namespace camdyn::optim {

namespace {

Json finite_or_null(double v) { return std::isfinite(v) ? Json(v) : Json(nullptr); }

/// The metrics of one speed exactly as summary.json of `camdyn run` has them.
Json speed_metrics(const DesignEvaluation& e, const SpeedResult& s, const std::string& file) {
  SceneConfig scene = e.scene;
  scene.mechanism.cam.rpm = s.rpm;
  const Model model = build_model(scene, file);
  Json m = Json::object();
  m["rpm"] = s.rpm;
  const Json summary = summary_json(scene, model, s.result);
  for (const auto& [key, value] : summary["metrics"].items()) m[key] = value;
  m["mean_gap"] = s.mean_gap;
  m["run_time_s"] = s.result.solver.run_time_s;
  return m;
}

Json design_json(const DesignEvaluation& e, const OptimizeOutcome& outcome, const std::string& file) {
  Json j = Json::object();
  j["valid"] = e.valid;
  if (!e.valid) j["error"] = e.error;
  j["feasible"] = e.feasible;
  Json metrics = Json::array();
  for (const SpeedResult& s : e.speeds) metrics.push_back(speed_metrics(e, s, file));
  j["metrics"] = metrics;

  Json terms = Json::object();
  for (const TermValue& t : e.terms)
    terms[t.name] = Json{{"weight", t.weight}, {"value", t.value}, {"unit", t.unit}, {"normalised", t.normalised}};
  j["objective"] = Json{{"value", e.objective}, {"aggregate", outcome.config.objective.aggregate}, {"terms", terms}};

  Json constraints = Json::object();
  for (std::size_t i = 0; i < outcome.constraints.size() && i < e.constraints.size(); ++i) {
    const ConstraintSpec& spec = outcome.constraints[i];
    const ConstraintValue& c = e.constraints[i];
    const char* sense = spec.sense == ConstraintSpec::Sense::at_most    ? "at_most"
                        : spec.sense == ConstraintSpec::Sense::at_least ? "at_least"
                                                                        : "zero";
    Json cj{{"limit", spec.limit}, {"sense", sense}, {"unit", spec.unit}};
    if (e.valid) {
      cj["value"] = c.value;
      cj["margin"] = c.margin;
    } else {
      cj["value"] = nullptr;
      cj["margin"] = nullptr;
    }
    cj["holds"] = c.holds;
    constraints[spec.name] = cj;
  }
  j["constraints"] = constraints;

  const LawKinematics& k = e.kinematics;
  Json segments = Json::array();
  for (const SegmentKinematics& s : k.segments) {
    segments.push_back(Json{{"index", s.index},
                            {"type", s.type},
                            {"start_deg", s.start_deg},
                            {"end_deg", s.end_deg},
                            {"lift", s.lift},
                            {"velocity_coefficient", s.velocity_coefficient},
                            {"acceleration_coefficient", s.acceleration_coefficient},
                            {"jerk_coefficient", s.jerk_coefficient}});
  }
  j["kinematics"] = Json{{"peak_velocity", k.peak_velocity},
                         {"peak_acceleration", k.peak_acceleration},
                         {"peak_jerk", k.peak_jerk},
                         {"segments", segments}};
  if (e.valid) {
    j["geometry"] = Json{{"max_pressure_angle_deg", e.geometry.max_pressure_angle_deg},
                         {"max_pressure_angle_at_deg", e.geometry.max_pressure_angle_at_deg},
                         {"min_radius_of_curvature", e.geometry.min_radius_of_curvature},
                         {"min_radius_of_curvature_at_deg", e.geometry.min_radius_of_curvature_at_deg}};
  }
  j["motion_law"] = to_json(e.scene)["mechanism"]["cam"]["motion_law"];
  return j;
}

/// The rigid-model stage: the certificate (jump-free speeds are null when
/// unbounded) and the design the dynamic stage starts from.
Json steady_state_check_json(const SteadyStateCheck& c) {
  if (!c.checked) return Json{{"checked", false}, {"reason", c.reason}};
  return Json{{"checked", true},
              {"speeds_on_orbit", c.speeds_on_orbit},
              {"speeds", c.speeds},
              {"objective", c.objective},
              {"relative_change", c.relative_change},
              {"tolerance", WindowCheck::kTolerance},
              {"agrees", c.agrees},
              {"notes", c.notes}};
}

/// The lift-area certificate (docs/optimize.md "Lift area").
Json lift_area_json(const LiftAreaCertificate& c) {
  Json j{{"available", c.available},   {"unit", "m rad"}, {"design", c.design}, {"baseline", c.baseline},
         {"speeds_rpm", c.speeds_rpm}, {"grid", c.grid}};
  if (!c.available) {
    j["reason"] = c.reason;
    return j;
  }
  j["bound"] = c.bound;
  j["design_share_of_bound"] = c.bound > 0.0 ? c.design / c.bound : 0.0;
  return j;
}

Json rigid_json(const RigidStageResult& r, bool enabled) {
  const Certificate& c = r.certificate;
  Json j = Json::object();
  j["enabled"] = enabled;
  j["available"] = c.available;
  if (!c.available) {
    j["reason"] = enabled ? c.reason : "rigid.enabled is false";
    return j;
  }
  Json speeds = Json::array();
  // No design of the family meeting the linear constraints (a pressure-angle
  // or jerk limit too tight) has no best margin: null, design_exists false.
  for (const SpeedCertificate& s : c.speeds)
    speeds.push_back(Json{{"rpm", s.rpm},
                          {"feasible", s.feasible},
                          {"best_margin", finite_or_null(s.best_margin)},
                          {"design_exists", std::isfinite(s.best_margin)}});
  j["certificate"] = Json{{"min_contact_force", c.min_contact_force},
                          {"margin_unit", c.margin_unit},
                          {"any_law_jump_free_rpm", finite_or_null(c.any_law_rpm)},
                          {"any_law_binding", c.any_law_binding},
                          {"family_jump_free_rpm", finite_or_null(c.family_rpm)},
                          {"family_binding", c.family_binding},
                          {"baseline_jump_free_rpm", finite_or_null(c.baseline_rpm)},
                          {"all_feasible", c.all_feasible()},
                          {"speeds", speeds},
                          {"model", c.model}};
  if (!c.any_law_unavailable.empty()) j["certificate"]["any_law_not_computed"] = c.any_law_unavailable;
  if (c.model == "held train") {
    j["certificate"]["any_law_coarse_rpm"] = finite_or_null(c.any_law_coarse_rpm);
    j["certificate"]["train_harmonics"] = c.train_harmonics;
    j["certificate"]["train_truncation"] = c.train_truncation;
  }
  if (c.lift_area.available || !c.lift_area.reason.empty()) j["certificate"]["lift_area"] = lift_area_json(c.lift_area);
  const RigidDesign& d = r.design;
  Json dj{{"made", d.have}};
  if (d.have) {
    dj["jump_free_rpm"] = finite_or_null(d.jump_free_rpm);
    dj["verified_margin"] = d.verified_margin;
    dj["control_points"] = d.control_points;
  }
  j["design"] = dj;
  j["lp_solves"] = r.lp_solves;
  j["run_time_s"] = r.run_time_s;
  return j;
}

/// One candidate answer as verified: objective, each constraint, the speeds where it separates.
Json candidate_json(const CandidateVerification& c, const OptimizeOutcome& o) {
  Json j{{"available", c.available}};
  if (!c.available) {
    j["reason"] = c.reason;
    return j;
  }
  const DesignEvaluation& e = c.verified;
  j["valid"] = e.valid;
  if (!e.valid) j["error"] = e.error;
  j["objective"] = e.valid ? finite_or_null(e.objective) : Json(nullptr);
  j["feasible"] = c.score.feasible;
  j["violated"] = c.score.violated;
  Json constraints = Json::object();
  for (std::size_t i = 0; i < o.constraints.size() && i < e.constraints.size(); ++i)
    constraints[o.constraints[i].name] = Json{
        {"value", e.valid ? finite_or_null(e.constraints[i].value) : Json(nullptr)}, {"holds", e.constraints[i].holds}};
  j["constraints"] = constraints;
  j["jump_free"] = e.valid && c.separating_rpm.empty();
  if (c.kind == CandidateKind::spring) {
    j["sized_from"] = to_string(c.sized_from);
    j["preload"] = e.scene.mechanism.follower.spring.preload;
  }
  j["separating_rpm"] = c.separating_rpm;
  if (!c.lets_go.empty()) {  // a train: where it lets go first at each separating speed
    Json lets_go = Json::array();
    for (std::size_t i = 0; i < c.lets_go.size() && i < c.separating_rpm.size(); ++i)
      lets_go.push_back(Json{{"rpm", c.separating_rpm[i]},
                             {"element", c.lets_go[i].first},
                             {"cam_angle_deg", finite_or_null(c.lets_go[i].second)}});
    j["lets_go"] = lets_go;
  }
  Json speeds = Json::array();
  for (const SpeedResult& s : e.speeds)
    speeds.push_back(Json{{"rpm", s.rpm},
                          {"metrics_over", s.result.metrics_over},
                          {"separation_fraction", s.result.metrics.separation_fraction},
                          {"min_contact_force", s.result.metrics.min_contact_force},
                          {"peak_contact_force", s.result.metrics.peak_contact_force}});
  j["speeds"] = speeds;
  return j;
}

/// Which candidate the study returns and why, and how each fared.
void add_selection(const OptimizeOutcome& o, Json& r) {
  const Selection& sel = o.selection;
  r["chosen"] = to_string(sel.choice.chosen);
  r["chosen_reason"] = sel.choice.reason;
  r["verdict"] = !o.withheld.empty() ? Json(nullptr) : sel.good() ? "good" : sel.choice.feasible ? "warning" : "bad";
  r["conclusion_withheld"] = o.withheld.empty() ? Json(nullptr) : Json(o.withheld);
  r["lift"] = Json{{"baseline_highest", o.baseline.highest_lift},
                   {"answer_highest", o.optimized.highest_lift},
                   {"baseline_area", o.baseline.lift_area},
                   {"answer_area", o.optimized.lift_area},
                   {"given_up", sel.lift_given_up.empty() ? Json(nullptr) : Json(sel.lift_given_up)}};
  Json candidates = Json::object();
  for (const CandidateVerification& c : sel.candidates) candidates[to_string(c.kind)] = candidate_json(c, o);
  r["candidates"] = candidates;
  r["required_preload"] = finite_or_null(o.required_preload);
  r["required_preload_unit"] = o.required_preload_unit;
  if (!o.required_preload_spring.empty()) r["required_preload_spring"] = o.required_preload_spring;
  if (!o.required_preload_unavailable.empty()) r["required_preload_unavailable"] = o.required_preload_unavailable;
  r["required_stiffness"] = finite_or_null(o.required_stiffness);
  if (!o.required_stiffness_unavailable.empty()) r["required_stiffness_unavailable"] = o.required_stiffness_unavailable;
}

}  // namespace

Json result_json(const OptimizeOutcome& o, const std::string& name, const std::string& file) {
  Json r = Json::object();
  r["name"] = name;
  r["study"] = "optimize";
  r["camdyn_version"] = CAMDYN_VERSION;
  r["algorithm"] = o.search.algorithm;
  r["method"] = o.search.method;
  r["stop_reason"] = o.search.stop_reason;
  r["evaluations"] = o.search.evaluations;
  r["invalid_evaluations"] = o.search.invalid_evaluations;
  r["budget_cut_evaluations"] = o.budget_cut_evaluations;
  Json budgets = Json::array();
  for (const std::string& b : o.budget_cut_by) budgets.push_back(b);
  r["budget_cut_by"] = budgets;
  r["simulations"] = o.simulations;
  r["loop_simulations"] = o.loop_simulations;
  r["run_time_s"] = o.run_time_s;
  r["loop_time_s"] = o.loop_time_s;
  r["evaluations_per_second"] = o.loop_time_s > 0 ? static_cast<double>(o.search.evaluations) / o.loop_time_s : 0.0;
  r["simulations_per_second"] = o.loop_time_s > 0 ? static_cast<double>(o.loop_simulations) / o.loop_time_s : 0.0;
  r["operating_rpm"] = o.config.operating_rpm;
  r["loop_simulated"] = o.loop_simulated;
  r["normalisation"] = Json{{"force", o.normalisation.force},
                            {"mean_gap", o.normalisation.mean_gap},
                            {"peak_acceleration", o.normalisation.acceleration},
                            {"peak_jerk", o.normalisation.jerk}};
  Json starts = Json::array();
  for (const StartResult& s : o.search.starts) {
    Json sj{{"index", s.index}, {"stop_reason", s.stop_reason}, {"evaluations", s.evaluations}};
    if (!s.message.empty()) sj["message"] = s.message;
    sj["best_objective"] = s.found ? finite_or_null(s.best_objective) : Json(nullptr);
    sj["best_feasible"] = s.found && s.best_feasible;
    starts.push_back(sj);
  }
  r["starts"] = starts;

  Json vars = Json::array();
  for (std::size_t i = 0; i < o.variables.size(); ++i) {
    vars.push_back(Json{{"name", o.variables[i].name},
                        {"lower", o.variables[i].lower},
                        {"upper", o.variables[i].upper},
                        {"initial", o.x_initial[i]},
                        {"optimized", i < o.x_optimized.size() ? Json(o.x_optimized[i]) : Json(nullptr)}});
  }
  r["design"] = Json{
      {"segments", o.config.design.segments},
      {"degree", o.config.design.degree},
      {"control_points", o.config.design.control_points},
      {"monotone", o.config.design.monotone},
      {"fit", Json{{"max_lift_error", o.fit.max_lift_error}, {"max_acceleration_error", o.fit.max_acceleration_error}}},
      {"candidates_tried", o.candidates_tried},
      {"variables", vars}};
  r["rigid_stage"] = rigid_json(o.rigid, o.config.rigid.enabled);
  r["rigid_stage"]["proven_rpm"] = o.proven_rpm;
  if (o.rigid.certificate.available)  // each design's one jump-free figure (optim/optimize/certificate_text.h)
    r["rigid_stage"]["jump_free_rpm"] =
        Json{{"model", jump_free_model_text(o.rigid.certificate)},
             {"baseline", finite_or_null(o.rigid.certificate.baseline_rpm)},
             {"rigid_design", o.rigid.design.have ? finite_or_null(o.rigid.design.jump_free_rpm) : Json()},
             {"answer", finite_or_null(o.answer_jump_free_rpm)}};
  add_selection(o, r);
  r["resumed_evaluations"] = o.resumed_evaluations;
  r["resumed_simulations"] = o.resumed_simulations;
  const WindowCheck& w = o.window_check;
  r["window_check"] = w.checked ? Json{{"checked", true},
                                       {"evaluated_cycles", w.evaluated_cycles},
                                       {"doubled_cycles", w.doubled_cycles},
                                       {"objective", w.objective},
                                       {"objective_doubled", w.objective_doubled},
                                       {"feasible_doubled", w.feasible_doubled},
                                       {"relative_change", w.relative_change},
                                       {"tolerance", WindowCheck::kTolerance},
                                       {"converged", w.converged},
                                       {"steady_state", steady_state_check_json(w.steady_state)}}
                                : Json{{"checked", false}, {"reason", w.reason}};
  r["baseline"] = design_json(o.baseline, o, file);
  r["initial"] = Json{{"objective", o.initial.objective}, {"feasible", o.initial.feasible}, {"valid", o.initial.valid}};
  r["optimized"] = design_json(o.optimized, o, file);
  r["optimized_config"] = "optimized.json";
  return r;
}

Json optimized_config_json(const OptimizeOutcome& o, const std::string& config_file) {
  const Json scene = to_json(o.optimized_scene);
  Json out = Json::object();
  out["name"] = scene["name"];
  out["description"] = "Optimised by `camdyn run " + config_file + "` (" + o.search.method + ", " +
                       std::to_string(o.search.evaluations) + " evaluations, stop reason " + o.search.stop_reason +
                       "), at the top operating speed; the answer is the " + to_string(o.selection.choice.chosen) +
                       " design (result.json `chosen`).";
  for (const auto& [key, value] : scene.items())
    if (key != "name") out[key] = value;
  return out;
}

void write_history_csv(const std::filesystem::path& path, const OptimizeOutcome& o) {
  std::vector<std::string> columns = {"evaluation", "objective"};
  for (const ConstraintSpec& c : o.constraints) columns.push_back(c.name);
  for (const char* c : {"feasible", "start", "kind", "valid", "best_objective", "error"}) columns.emplace_back(c);
  CsvWriter csv(path, columns);
  for (const HistoryRecord& h : o.history) {
    std::vector<CsvCell> row = {h.evaluation, h.objective};
    for (std::size_t i = 0; i < o.constraints.size(); ++i) {
      if (h.valid && i < h.constraints.size())
        row.emplace_back(h.constraints[i].value);
      else
        row.emplace_back("");
    }
    row.emplace_back(h.feasible ? 1 : 0);
    row.emplace_back(h.start);
    row.emplace_back(h.kind == PointKind::nlopt ? "nlopt" : "gradient");
    row.emplace_back(h.valid ? 1 : 0);
    row.emplace_back(h.best_objective);
    row.emplace_back(h.error);
    csv.row(row);
  }
  csv.commit();
}

void write_optimize_outputs(const std::filesystem::path& dir, const OptimizeOutcome& o, const std::string& name,
                            const std::string& config_file) {
  std::filesystem::create_directories(dir);
  write_json_atomic(dir / "optimized.json", optimized_config_json(o, config_file));
  write_history_csv(dir / "history.csv", o);
  // A withheld answer has no verdict to show (docs/optimize.md "Budgets").
  if (o.withheld.empty())
    write_report(dir / "report.html", optimize_report(o, name));
  else
    std::filesystem::remove(dir / "report.html");
  // outputs.profile: the optimised cam for manufacturing. A tool radius the
  // new contour cannot take costs the profile, not the optimisation's results.
  try {
    write_profile_outputs(dir, o.optimized_scene, build_model(o.optimized_scene, config_file), config_file);
  } catch (const InputError& e) {
    std::cerr << "camdyn: warning: optimised cam profile not written: " << e.what() << "\n";
  }
  write_json_atomic(dir / "result.json",
                    result_json(o, name, config_file));  // last: its presence means the run is complete
}

}  // namespace camdyn::optim
