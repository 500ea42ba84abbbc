#include "optim/optimize/optimize_report.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <utility>
#include <vector>

#include "common/constants.h"
#include "common/errors.h"
#include "dynamics/coordinate_units.h"
#include "dynamics/model.h"
#include "optim/optimize/certificate_text.h"
#include "optim/optimize/rigid_design.h"
#include "optim/optimize/train_rows.h"
#include "output/cam_plots.h"

namespace camdyn::optim {

namespace {

constexpr double kDegPerRad = 180.0 / std::numbers::pi;
constexpr double kLawStepDeg = 0.25;
constexpr const char* kCamAngleLabel = "cam angle [deg]";

Plot make_plot(std::string title, std::string xlabel, std::string ylabel, std::vector<Series> series) {
  Plot plot;
  plot.title = std::move(title);
  plot.xlabel = std::move(xlabel);
  plot.ylabel = std::move(ylabel);
  plot.series = std::move(series);
  plot.xrange = std::pair{0.0, 360.0};
  return plot;
}

/// One column of the last simulated revolution against cam angle in [0, 360).
Series last_cycle(const SpeedResult& s, const std::vector<double>& column, double scale, std::string label,
                  PlotRole role) {
  Series out;
  out.label = std::move(label);
  out.role = role;
  const TimeSeries& ts = s.result.series;
  const double period = 60.0 / s.rpm;
  const double from = s.result.end_time - period * (1.0 + 1e-9);
  double previous = -1.0;
  for (std::size_t i = 0; i < ts.time.size(); ++i) {
    if (ts.time[i] < from) continue;
    const double deg = std::fmod(ts.cam_angle_deg[i], 360.0);
    if (deg < previous) {  // wrapped: break the line
      out.x.push_back(kBreak);
      out.y.push_back(kBreak);
    }
    previous = deg;
    out.x.push_back(deg);
    out.y.push_back(scale * column[i]);
  }
  return out;
}

std::string yes_no(bool b) { return b ? "yes" : "NO"; }

/// The sized preload with its unit and spring, or why there is none (docs/model.md §11, §12).
std::string required_preload_text(const OptimizeOutcome& o) {
  if (!o.required_preload_unavailable.empty()) return "not available: " + o.required_preload_unavailable;
  std::string text = format_number(o.required_preload) + " " + o.required_preload_unit;
  if (o.rigid.certificate.model == "held train")
    text += " of " + o.required_preload_spring + " (held train: every contact and link loaded)";
  return text + " at the rate given";
}

const SpeedResult* at_rpm(const DesignEvaluation& e, double rpm) {
  for (const SpeedResult& s : e.speeds)
    if (s.rpm == rpm) return &s;
  return nullptr;
}

/// The answer first: each design's jump-free figure, the jump speed before and after, and the certificate.
std::vector<std::pair<std::string, std::string>> answer_facts(const OptimizeOutcome& o) {
  std::vector<std::pair<std::string, std::string>> facts;
  const DesignEvaluation& b = o.baseline;
  const DesignEvaluation& p = o.optimized;
  const Certificate& c = o.rigid.certificate;
  if (const std::string jump_free = jump_free_text(o); !jump_free.empty())
    facts.emplace_back("jump-free to (" + jump_free_model_text(c) + ")", jump_free);
  if (!b.speeds.empty() && !p.speeds.empty())
    facts.emplace_back(
        std::string(c.model == "held train" ? "train jump speed (held, linearised)" : "rigid-model jump speed") +
            ", where a force first reaches 0 N",
        format_number(b.speeds.front().result.metrics.jump_speed_rpm, 5) + " → " +
            format_number(p.speeds.front().result.metrics.jump_speed_rpm, 5) + " rpm");
  if (!c.available) {
    facts.emplace_back("certificate", o.config.rigid.enabled ? "not available: " + c.reason : "rigid stage disabled");
    return facts;
  }
  facts.emplace_back("certificate (" + jump_free_model_text(c) + ")",
                     any_law_text(c) + "; this spline family: " + family_text(c) +
                         "; baseline law: " + format_number(c.baseline_rpm, 5) + " rpm");
  if (const std::string convergence = any_law_convergence_text(c); !convergence.empty())
    facts.emplace_back("any law: convergence", convergence);
  std::string verdict;
  for (std::size_t i = 0; i < c.speeds.size(); ++i)
    verdict += (verdict.empty() ? "" : "; ") + format_number(c.speeds[i].rpm) + " rpm " + speed_text(o, i);
  facts.emplace_back("operating speeds", verdict);
  if (const LiftAreaCertificate& a = c.lift_area; a.available)
    facts.emplace_back("lift area (rigid design, over the event)",
                       format_number(1e3 * a.design, 6) + " mm·rad, " + format_number(100.0 * a.design / a.bound, 4) +
                           " % of the most any law can have under the same constraints (" +
                           format_number(1e3 * a.bound, 6) + " mm·rad); baseline " +
                           format_number(1e3 * a.baseline, 6) + " mm·rad");
  return facts;
}

/// The run at a glance: algorithm, budget used, run time, objective, feasibility.
std::vector<std::pair<std::string, std::string>> summary_facts(const OptimizeOutcome& o) {
  const DesignEvaluation& b = o.baseline;
  const DesignEvaluation& p = o.optimized;
  std::string speeds;
  for (double rpm : o.config.operating_rpm) speeds += (speeds.empty() ? "" : ", ") + format_number(rpm);
  return {{"algorithm", o.search.method},
          {"stop reason", o.search.stop_reason},
          {"evaluations", std::to_string(o.search.evaluations) + " (" + std::to_string(o.search.invalid_evaluations) +
                              " invalid designs)"},
          {"simulations", std::to_string(o.simulations)},
          {"run time",
           format_number(o.run_time_s, 4) + " s (search loop " + format_number(o.loop_time_s, 4) + " s, " +
               format_number(o.loop_time_s > 0 ? static_cast<double>(o.search.evaluations) / o.loop_time_s : 0.0, 4) +
               " evaluations/s)"},
          {"operating speeds", speeds + " rpm (" + o.config.objective.aggregate + " case)"},
          {"objective", format_number(b.objective) + " → " + format_number(p.objective)},
          {"answer", std::string(to_string(o.selection.choice.chosen)) + " (" + o.selection.choice.reason + ")"},
          {"required spring preload", required_preload_text(o)},
          {"all constraints hold", "baseline: " + yes_no(b.feasible) + ", optimised: " + yes_no(p.feasible)}};
}

/// The banner: which candidate is the answer and why, coloured by what was
/// verified (green: jump-free at every operating speed, every constraint,
/// better than the baseline; amber: the baseline kept, or an answer that
/// separates somewhere; red: nothing meets the constraints), then the jump
/// speed before → after, the certificate and the speeds it covers.
Verdict optimize_verdict(const OptimizeOutcome& o) {
  Verdict v;
  const Selection& sel = o.selection;
  const CandidateVerification& chosen = sel.chosen();
  v.tone = sel.good() ? Verdict::Tone::good : sel.choice.feasible ? Verdict::Tone::warning : Verdict::Tone::bad;
  if (!sel.choice.feasible)
    v.headline = "no design meets every constraint: the " + std::string(to_string(sel.choice.chosen)) +
                 " design breaks the fewest";
  else if (sel.choice.chosen == CandidateKind::baseline)
    v.headline = "baseline kept: no design the study made is better on the steady state";
  else
    v.headline = std::string("the ") + to_string(sel.choice.chosen) + " design: objective " +
                 format_number(o.selection.candidates.front().verified.objective) + " → " +
                 format_number(chosen.verified.objective) + " on the steady state";
  v.details.push_back("why: " + sel.choice.reason);
  if (!chosen.separating_rpm.empty()) {
    std::string speeds;
    for (double rpm : chosen.separating_rpm) speeds += (speeds.empty() ? "" : ", ") + format_number(rpm);
    v.details.push_back("separates on the steady state at " + speeds + " rpm");
  }
  if (!sel.lift_given_up.empty()) v.details.push_back("lift given up: " + sel.lift_given_up);
  for (const auto& [key, value] : answer_facts(o)) v.details.push_back(key + ": " + value);
  return v;
}

/// On a train: at the top speed, the held train's margin of the contact and
/// of each link (baseline and optimised), and each spring's frame-end force
/// against its static one (docs/optimize.md "Trains").
void add_train_margin_plots(const OptimizeOutcome& o, Report& r) {
  const double top = *std::max_element(o.config.operating_rpm.begin(), o.config.operating_rpm.end());
  const double pmin = o.rigid.certificate.min_contact_force;
  const Model base = build_model(o.baseline.scene, ""), opt = build_model(o.optimized.scene, "");
  const HeldCurves b = held_train_curves(base, top), p = held_train_curves(opt, top), s = held_train_curves(opt, 0.0);
  for (std::size_t k = 0; k < p.quantities.size() && k < b.quantities.size(); ++k) {
    const HeldQuantity& q = p.quantities[k];
    if (q.held()) {
      std::vector<double> mb = b.values[k], mp = p.values[k];
      for (double& x : mb) x -= pmin;
      for (double& x : mp) x -= pmin;
      r.plots.push_back(make_plot("Held train: " + q.name + " force margin F − " + format_number(pmin) + " N at " +
                                      format_number(top) + " rpm (< 0: it lets go)",
                                  kCamAngleLabel, "margin [N]",
                                  {{"baseline", b.angles_deg, mb}, {"optimised", p.angles_deg, mp}}));
    } else if (q.kind == HeldQuantity::Kind::spring_end) {
      r.plots.push_back(make_plot(
          "Held train: " + q.name + " force at its frame end, optimised design", kCamAngleLabel, "force [N]",
          {{"static", s.angles_deg, s.values[k]}, {"at " + format_number(top) + " rpm", p.angles_deg, p.values[k]}}));
    }
  }
}

/// Rigid-model margin P − P_min against cam angle, baseline and optimised, at each operating speed.
void add_margin_plots(const OptimizeOutcome& o, Report& r) {
  if (!o.rigid.certificate.available) return;
  if (o.rigid.certificate.model == "held train") {
    add_train_margin_plots(o, r);
    return;
  }
  std::vector<double> angles;
  for (int i = 0; i <= static_cast<int>(360.0 / kLawStepDeg); ++i) angles.push_back(i * kLawStepDeg);
  const double pmin = o.rigid.certificate.min_contact_force;
  for (const double rpm : o.config.operating_rpm) {
    const std::vector<double> mb = rigid_margin_curve(o.baseline.scene, rpm, pmin, angles);
    const std::vector<double> mp = rigid_margin_curve(o.optimized.scene, rpm, pmin, angles);
    if (mb.empty() || mp.empty()) return;
    r.plots.push_back(make_plot("Rigid-model contact-force margin P − " + format_number(pmin) + " N at " +
                                    format_number(rpm) + " rpm (< 0: the follower jumps)",
                                "cam angle [deg]", "margin [" + o.rigid.certificate.margin_unit + "]",
                                {{"baseline", angles, mb}, {"optimised", angles, mp}}));
  }
}

/// Constraints with their limits and margins, baseline against optimised.
Table constraints_table(const OptimizeOutcome& o) {
  Table constraints{"Constraints (value at the worst operating speed)",
                    {"constraint", "limit", "unit", "baseline", "optimised", "margin", "holds"},
                    {},
                    true};
  for (std::size_t i = 0; i < o.constraints.size(); ++i) {
    const ConstraintSpec& spec = o.constraints[i];
    const std::string limit = spec.sense == ConstraintSpec::Sense::at_most    ? "≤ " + format_number(spec.limit)
                              : spec.sense == ConstraintSpec::Sense::at_least ? "≥ " + format_number(spec.limit)
                                                                              : "= 0";
    // A jerk limit is on d³s/dθ³, in q per rad³: an arm's rad/rad^3.
    const std::string unit =
        spec.name == "max_peak_jerk" ? coordinate_units(o.optimized_scene).per_cam_radian(3, true) : spec.unit;
    constraints.rows.push_back({spec.name, limit, unit, format_number(o.baseline.constraints[i].value),
                                format_number(o.optimized.constraints[i].value),
                                format_number(o.optimized.constraints[i].margin),
                                yes_no(o.optimized.constraints[i].holds)});
  }
  return constraints;
}

/// The objective's terms, raw and normalised, baseline against optimised.
Table terms_table(const DesignEvaluation& b, const DesignEvaluation& p) {
  Table terms{"Objective terms (normalised value = value / scale; objective = Σ weight × normalised)",
              {"term", "weight", "unit", "baseline", "optimised", "baseline normalised", "optimised normalised"},
              {},
              true};
  for (std::size_t i = 0; i < p.terms.size() && i < b.terms.size(); ++i) {
    terms.rows.push_back({p.terms[i].name, format_number(p.terms[i].weight), p.terms[i].unit,
                          format_number(b.terms[i].value), format_number(p.terms[i].value),
                          format_number(b.terms[i].normalised), format_number(p.terms[i].normalised)});
  }
  return terms;
}

/// Simulation metrics at each operating speed, baseline → optimised.
Table metrics_table(const OptimizeOutcome& o) {
  Table metrics{"Metrics per operating speed (baseline → optimised)",
                {"rpm", "separation_fraction", "impacts", "peak_contact_force [N]", "min_contact_force [N]",
                 "max_impact_velocity [m/s]"},
                {},
                true};
  for (double rpm : o.config.operating_rpm) {
    const SpeedResult* sb = at_rpm(o.baseline, rpm);
    const SpeedResult* sp = at_rpm(o.optimized, rpm);
    if (!sb || !sp) continue;
    const Metrics& mb = sb->result.metrics;
    const Metrics& mp = sp->result.metrics;
    auto pair = [](double x, double y) { return format_number(x) + " → " + format_number(y); };
    metrics.rows.push_back({format_number(rpm), pair(mb.separation_fraction, mp.separation_fraction),
                            std::to_string(mb.impact_count) + " → " + std::to_string(mp.impact_count),
                            pair(mb.peak_contact_force, mp.peak_contact_force),
                            pair(mb.min_contact_force, mp.min_contact_force),
                            pair(mb.max_impact_velocity, mp.max_impact_velocity)});
  }
  return metrics;
}

/// Dimensionless velocity, acceleration and jerk coefficients of every rise
/// and return segment, baseline rows then optimised rows.
Table segments_table(const DesignEvaluation& b, const DesignEvaluation& p) {
  Table segments{"Rise and return segments: C_v = v β/h, C_a = a β²/h, C_j = j β³/h (cycloidal 2, 6.28, 39.5)",
                 {"segment", "type", "design", "start [deg]", "end [deg]", "C_v", "C_a", "C_j"},
                 {},
                 true};
  for (const auto* e : {&b, &p}) {
    for (const SegmentKinematics& s : e->kinematics.segments) {
      segments.rows.push_back({std::to_string(s.index), s.type, e == &b ? "baseline" : "optimised",
                               format_number(s.start_deg), format_number(s.end_deg),
                               format_number(s.velocity_coefficient), format_number(s.acceleration_coefficient),
                               format_number(s.jerk_coefficient)});
    }
  }
  return segments;
}

/// The candidates the answer was chosen from, as the verification saw them.
Table candidates_table(const Selection& sel) {
  Table t{"Candidates, verified with the scene's settings on the steady state (answer: " +
              std::string(to_string(sel.choice.chosen)) + ")",
          {"candidate", "objective", "meets every constraint", "breaks", "separates at [rpm]"},
          {},
          true};
  t.wrap = true;
  for (const CandidateVerification& c : sel.candidates) {
    if (!c.available) {
      t.rows.push_back({to_string(c.kind), "–", "–", c.reason, "–"});
      continue;
    }
    std::string breaks, speeds;
    for (const std::string& v : c.score.violated) breaks += (breaks.empty() ? "" : ", ") + v;
    for (double rpm : c.separating_rpm) speeds += (speeds.empty() ? "" : ", ") + format_number(rpm);
    if (!c.verified.valid) breaks = c.verified.error;
    t.rows.push_back({to_string(c.kind), c.verified.valid ? format_number(c.verified.objective) : "–",
                      yes_no(c.score.feasible), breaks, speeds.empty() ? "none" : speeds});
  }
  return t;
}

/// What each start of the search ended with.
Table starts_table(const SearchResult& search) {
  Table starts{"Starts", {"start", "stop reason", "evaluations", "best objective", "feasible", "message"}, {}, true};
  for (const StartResult& s : search.starts) {
    starts.rows.push_back({std::to_string(s.index + 1), s.stop_reason, std::to_string(s.evaluations),
                           s.found ? format_number(s.best_objective) : "–", yes_no(s.found && s.best_feasible),
                           s.message});
  }
  return starts;
}

/// The design variables with their bounds, initial (fitted) and optimised values.
Table variables_table(const OptimizeOutcome& o) {
  Table vars{"Design variables (monotone: share of the remaining rise; end angles: share of their range)",
             {"variable", "lower", "upper", "initial (fit)", "optimised"},
             {},
             true};
  for (std::size_t i = 0; i < o.variables.size(); ++i) {
    vars.rows.push_back({o.variables[i].name, format_number(o.variables[i].lower), format_number(o.variables[i].upper),
                         format_number(o.x_initial[i]),
                         i < o.x_optimized.size() ? format_number(o.x_optimized[i]) : "–"});
  }
  return vars;
}

/// The optimised cam to scale with the baseline's contour, the pressure
/// angle and radius of curvature of both against the study's constraints,
/// and the SVAJ of both laws per radian of cam angle (the study runs at
/// several speeds).
void add_cam_plots(const OptimizeOutcome& o, Report& r) {
  std::vector<Model> models;
  std::vector<std::string> labels;
  std::vector<PlotRole> roles;
  auto add = [&](const SceneConfig& scene, const char* label, PlotRole role) {
    try {
      models.push_back(build_model(scene, ""));
      labels.emplace_back(label);
      roles.push_back(role);
    } catch (const InputError&) {  // a design that cannot be built has no cam to draw
    }
  };
  add(o.optimized_scene, "optimised", PlotRole::optimised);
  if (o.baseline.valid) add(o.baseline.scene, "baseline", PlotRole::baseline);
  if (models.empty()) return;
  std::vector<CamDesign> designs;
  for (std::size_t i = 0; i < models.size(); ++i) designs.push_back({labels[i], &models[i], roles[i]});
  const ConstraintsConfig& c = o.config.constraints;
  const double mark = models.front().geometry.max_pressure_angle_at_deg / kDegPerRad;
  r.plots.push_back(cam_layout_plot(designs, mark));
  r.plots.push_back(pressure_angle_plot(designs, c.max_pressure_angle_deg));
  r.plots.push_back(curvature_plot(designs, c.min_radius_of_curvature));
  for (Plot& p : svaj_plots(designs, 0.0)) r.plots.push_back(std::move(p));
}

/// Contact force and gap over the last simulated revolution at each operating speed.
void add_dynamics_plots(const OptimizeOutcome& o, Report& r) {
  const std::string xlabel = kCamAngleLabel;
  for (double rpm : o.config.operating_rpm) {
    const SpeedResult* sb = at_rpm(o.baseline, rpm);
    const SpeedResult* sp = at_rpm(o.optimized, rpm);
    if (!sb || !sp) continue;
    const std::string at = " at " + format_number(rpm) + " rpm (last revolution)";
    r.plots.push_back(
        make_plot("Contact force" + at, xlabel, "force [N]",
                  {last_cycle(*sb, sb->result.series.contact_force, 1.0, "baseline", PlotRole::baseline),
                   last_cycle(*sp, sp->result.series.contact_force, 1.0, "optimised", PlotRole::optimised)}));
    const Series gap_b = last_cycle(*sb, sb->result.series.gap, 1.0, "baseline", PlotRole::baseline);  // [m]
    const Series gap_p = last_cycle(*sp, sp->result.series.gap, 1.0, "optimised", PlotRole::optimised);
    const LengthUnit unit = length_unit({&gap_b.y, &gap_p.y});
    Plot gap = make_plot("Gap" + at + " (> 0 separated)", xlabel, unit.axis("gap"), {gap_b, gap_p});
    for (Series& s : gap.series) s.y = unit.of(s.y);
    r.plots.push_back(std::move(gap));
  }
}

/// The objective of each evaluation and the best so far (valid designs only:
/// the penalty of invalid ones would flatten the plot), log scale when all positive.
Plot convergence_plot(const std::vector<HistoryRecord>& history) {
  Series all{"objective of each evaluation", {}, {}, "points"}, feasible{"feasible designs", {}, {}, "points"},
      best{"best so far", {}, {}, "lines"};
  for (const HistoryRecord& h : history) {
    if (!h.valid) continue;
    const double n = static_cast<double>(h.evaluation);
    (h.feasible ? feasible : all).x.push_back(n);
    (h.feasible ? feasible : all).y.push_back(h.objective);
    best.x.push_back(n);
    best.y.push_back(h.best_objective);
  }
  bool positive = true;
  for (const Series* se : {&all, &feasible, &best})
    for (double y : se->y) positive = positive && y > 0.0;
  Plot convergence =
      make_plot("Convergence (search loop settings)", "evaluation [-]", "objective [–]", {all, feasible, best});
  convergence.xrange.reset();
  convergence.logy = positive && !best.y.empty();
  return convergence;
}

/// Notes on the normalisation, the search-loop settings and the initial fit,
/// and a warning when the optimised design breaks a constraint.
std::vector<std::string> report_notes(const OptimizeOutcome& o) {
  std::vector<std::string> notes;
  const Normalisation& nm = o.normalisation;
  const CoordinateUnits units = coordinate_units(o.optimized_scene);  // the law's derivatives are in q per rad^n
  notes.push_back("Normalisation: forces by " + format_number(nm.force) +
                  " N (baseline peak rigid-model contact force at the top speed), separation by a mean gap of " +
                  format_number(nm.mean_gap) + " m, peak acceleration by " + format_number(nm.acceleration) + " " +
                  units.per_cam_radian(2) + ", peak jerk by " + format_number(nm.jerk) + " " + units.per_cam_radian(3) +
                  " (baseline values).");
  const OptimizerConfig& oc = o.config.optimizer;
  notes.push_back(
      std::string("The search loop ") +
      (o.loop_simulated
           ? "simulates with " +
                 (oc.evaluation_cycles ? format_number(*oc.evaluation_cycles) + " cycles" : "the scene's cycles") +
                 " and rtol " + (oc.evaluation_rtol ? format_number(*oc.evaluation_rtol) : "of the scene")
           : "evaluates kinematics and geometry only (no term or constraint needs a simulation)") +
      "; the baseline and the optimised design are evaluated with the scene's own settings (" +
      std::to_string(o.candidates_tried) + " best design(s) re-evaluated to find one that holds every constraint).");
  if (o.rigid.design.have)
    notes.push_back("Rigid-model stage: " + std::to_string(o.rigid.lp_solves) + " linear programmes in " +
                    format_number(o.rigid.run_time_s, 3) + " s; its design starts the search.");
  notes.push_back("Spline fit of the baseline law: max lift error " + format_number(o.fit.max_lift_error, 3) +
                  " of the lift, max acceleration error " + format_number(o.fit.max_acceleration_error, 3) +
                  " of the peak.");
  const WindowCheck& w = o.window_check;
  if (w.checked)
    notes.push_back("Window check: the objective over a window twice as long changes by " +
                    format_number(w.relative_change, 2) + (w.converged ? " (converged)." : " (NOT converged)."));
  if (w.steady_state.checked)
    notes.push_back("Steady-state check: with the metrics over the periodic orbit (" +
                    std::to_string(w.steady_state.speeds_on_orbit) + " of " + std::to_string(w.steady_state.speeds) +
                    " speeds on one) the objective changes by " + format_number(w.steady_state.relative_change, 2) +
                    (w.steady_state.agrees ? " (agrees)." : " (DIFFERS: set simulation.steady_state)."));
  if (!o.optimized.feasible) notes.push_back("WARNING: the optimised design does not satisfy every constraint.");
  return notes;
}

}  // namespace

Report optimize_report(const OptimizeOutcome& o, const std::string& name) {
  Report r;
  r.title = "camdyn optimize: " + name;
  r.subtitle =
      "Spline cam design: rigid-model linear programmes, then NLopt on simulations; baseline against the optimised "
      "design";
  r.verdict = optimize_verdict(o);
  r.facts = summary_facts(o);
  r.tables.push_back(candidates_table(o.selection));
  const Table constraints = constraints_table(o);
  if (!constraints.rows.empty()) r.tables.push_back(constraints);
  r.tables.push_back(terms_table(o.baseline, o.optimized));
  r.tables.push_back(metrics_table(o));
  r.tables.push_back(segments_table(o.baseline, o.optimized));
  r.appendix.push_back(starts_table(o.search));
  r.appendix.push_back(variables_table(o));
  add_margin_plots(o, r);
  add_cam_plots(o, r);
  add_dynamics_plots(o, r);
  r.plots.push_back(convergence_plot(o.history));
  r.notes = report_notes(o);
  return r;
}

}  // namespace camdyn::optim
